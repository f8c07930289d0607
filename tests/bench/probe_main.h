// The main() of the by-hand probes and benchmarks: runs `body`, prints an
// exception's message to stderr and returns 2 (bad input) instead of
// aborting.
#ifndef SYLVA_TESTS_BENCH_PROBE_MAIN_H_
#define SYLVA_TESTS_BENCH_PROBE_MAIN_H_

#include <cstdio>
#include <exception>

namespace sylva {

template <typename Body>
int GuardedMain(const Body& body) {
  try {
    return body();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}

}  // namespace sylva

#endif  // SYLVA_TESTS_BENCH_PROBE_MAIN_H_
