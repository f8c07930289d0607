#include "core/util/random.h"

#include <cmath>

#include "core/util/check.h"

namespace sylva {

uint64_t DeriveSeed(uint64_t seed, uint64_t stream) {
  uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

RandomEngine::RandomEngine(uint64_t seed, uint64_t stream)
    : state_(0), increment_((DeriveSeed(stream, 0x5eed) << 1u) | 1u) {
  NextUint32();
  state_ += DeriveSeed(seed, 0);
  NextUint32();
}

uint32_t RandomEngine::NextUint32() {
  const uint64_t old_state = state_;
  state_ = old_state * 6364136223846793005ULL + increment_;
  const auto xorshifted = static_cast<uint32_t>(((old_state >> 18u) ^ old_state) >> 27u);
  const auto rot = static_cast<uint32_t>(old_state >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
}

double RandomEngine::Uniform() {
  // 53 random bits from two draws.
  const uint64_t hi = NextUint32() >> 5;  // 27 bits
  const uint64_t lo = NextUint32() >> 6;  // 26 bits
  return static_cast<double>((hi << 26) | lo) * (1.0 / 9007199254740992.0);
}

uint32_t RandomEngine::UniformInt(uint32_t n) {
  SYLVA_CHECK(n > 0);
  const uint32_t threshold = (~n + 1u) % n;
  for (;;) {
    const uint32_t r = NextUint32();
    if (r >= threshold) return r % n;
  }
}

double RandomEngine::Normal() {
  double u1 = Uniform();
  while (u1 <= 0.0) u1 = Uniform();
  const double u2 = Uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

}  // namespace sylva
