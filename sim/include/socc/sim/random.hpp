#pragma once
// Deterministic random numbers that do not depend on the standard library implementation or on
// thread scheduling: SplitMix64 streams, and a stateless hash for per-ray draws.
#include <cmath>
#include <cstdint>

namespace socc::sim {

inline std::uint64_t splitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// Uniform in [0, 1) from 53 random bits.
inline double toUnit(std::uint64_t bits) {
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() { return splitMix64(state_++ * 0x2545F4914F6CDD1Dull); }
  double uniform(double lo = 0.0, double hi = 1.0) { return lo + (hi - lo) * toUnit(next()); }
  bool chance(double p) { return uniform() < p; }
  double sign() { return chance(0.5) ? 1.0 : -1.0; }

 private:
  std::uint64_t state_;
};

/// Independent uniforms for one (seed, stream, index) triple; a gaussian from u1, u2.
struct RayDraw {
  double u1;
  double u2;
  double u3;
  double gaussian() const {
    return std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(2.0 * M_PI * u2);
  }
};
inline RayDraw rayDraw(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
  const std::uint64_t h = splitMix64(splitMix64(seed ^ (stream * 0x9E3779B97F4A7C15ull)) + index);
  return {toUnit(splitMix64(h)), toUnit(splitMix64(h + 1)), toUnit(splitMix64(h + 2))};
}

}  // namespace socc::sim
