// Parallel loops with deterministic errors.
#ifndef SYLVA_CORE_UTIL_THREADING_H_
#define SYLVA_CORE_UTIL_THREADING_H_

#include <functional>

namespace sylva {

// Runs body(i) for every i in [0, n) in parallel (TBB). If some calls throw,
// all others still finish, then the exception of the smallest i is rethrown,
// so the error a user sees does not depend on scheduling.
void ParallelForFirstError(int n, const std::function<void(int)>& body);

}  // namespace sylva

#endif  // SYLVA_CORE_UTIL_THREADING_H_
