// Deterministic random numbers.
//
// Every random choice in sylva goes through RandomEngine, seeded explicitly,
// so that the same inputs and seed give the same tree on every platform (the
// standard library's distributions are implementation-defined, so they are not
// used). Independent streams for parallel work or separate stages come from
// DeriveSeed(seed, stream), never from reseeding with the time.
#ifndef SYLVA_CORE_UTIL_RANDOM_H_
#define SYLVA_CORE_UTIL_RANDOM_H_

#include <cstdint>

namespace sylva {

// Mixes a seed with a stream id into an independent seed (SplitMix64).
uint64_t DeriveSeed(uint64_t seed, uint64_t stream);

// PCG32 (O'Neill 2014): small state, good statistical quality, fast.
class RandomEngine {
 public:
  explicit RandomEngine(uint64_t seed, uint64_t stream = 0);

  uint32_t NextUint32();
  // Uniform in [0, 1).
  double Uniform();
  // Uniform in [lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Uniform integer in [0, n), n > 0, without modulo bias.
  uint32_t UniformInt(uint32_t n);
  // Standard normal (Box-Muller, one value per call).
  double Normal();
  double Normal(double mean, double sigma) { return mean + sigma * Normal(); }

 private:
  uint64_t state_;
  uint64_t increment_;
};

}  // namespace sylva

#endif  // SYLVA_CORE_UTIL_RANDOM_H_
