// Small helpers shared by the by-hand probes and benchmarks: GuardedMain
// runs `body`, prints an exception's message to stderr and returns 2 (bad
// input) instead of aborting; Seconds / BestSeconds time runs.
#ifndef SYLVA_TESTS_BENCH_PROBE_MAIN_H_
#define SYLVA_TESTS_BENCH_PROBE_MAIN_H_

#include <algorithm>
#include <chrono>
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

using BenchClock = std::chrono::steady_clock;

// Seconds since `start`.
inline double Seconds(BenchClock::time_point start) {
  return std::chrono::duration<double>(BenchClock::now() - start).count();
}

// The fastest of `repetitions` runs, in seconds.
template <typename Run>
double BestSeconds(int repetitions, Run&& run) {
  double best = 1e300;
  for (int r = 0; r < repetitions; ++r) {
    const BenchClock::time_point start = BenchClock::now();
    run();
    best = std::min(best, Seconds(start));
  }
  return best;
}

}  // namespace sylva

#endif  // SYLVA_TESTS_BENCH_PROBE_MAIN_H_
