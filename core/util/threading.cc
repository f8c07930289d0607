#include "core/util/threading.h"

#include <tbb/parallel_for.h>

#include <exception>
#include <vector>

namespace sylva {

void ParallelForFirstError(int n, const std::function<void(int)>& body) {
  std::vector<std::exception_ptr> errors(n > 0 ? n : 0);
  tbb::parallel_for(0, n, [&](int i) {
    try {
      body(i);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  });
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
}

}  // namespace sylva
