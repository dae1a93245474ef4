// rng.h: a small, portable, seeded random generator (splitmix64 seeding, xoshiro256**).
// The standard library's distributions differ between implementations; these do not, so a world is
// the same function of (scenario, seed) on every machine.
#pragma once

#include <cmath>
#include <cstdint>

namespace roger {

class Rng {
 public:
  // Seeds the four state words from one 64-bit seed through splitmix64.
  explicit Rng(uint64_t seed = 0) { reseed(seed); }

  // Restarts the sequence from a seed.
  void reseed(uint64_t seed) {
    for (auto& word : s_) {
      seed += 0x9E3779B97F4A7C15ull;
      uint64_t z = seed;
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
      word = z ^ (z >> 31);
    }
  }

  // The next raw 64-bit value.
  uint64_t next() {
    const uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  // Uniform in [0, 1).
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }

  // Uniform in [lo, hi). A span past the largest double (hi - lo overflows: found by a probe, rng:
  // uniform(-1e308, 1e308) gave inf) is drawn at half scale and doubled, exactly; every finite span
  // keeps the one formula, and every range the same one draw.
  double uniform(double lo, double hi) {
    const double u = uniform();
    if (const double span = hi - lo; std::isfinite(span)) return lo + span * u;
    return 2.0 * (0.5 * lo + (0.5 * hi - 0.5 * lo) * u);
  }

  // Uniform integer in [lo, hi] (inclusive); lo <= hi.
  int64_t integer(int64_t lo, int64_t hi) {
    // In unsigned arithmetic: hi - lo overflows int64_t on the full range, and
    // the compiler may assume it does not (it did: a modulo by zero).
    const uint64_t span = uint64_t(hi) - uint64_t(lo) + 1;
    if (span == 0) return int64_t(next());  // the whole int64_t range
    // Rejection keeps it unbiased.
    const uint64_t limit = UINT64_MAX - UINT64_MAX % span;
    uint64_t v;
    do v = next(); while (v >= limit);
    return int64_t(uint64_t(lo) + v % span);
  }

  // Normal with mean mu and standard deviation sigma (Box-Muller, one value per call).
  double normal(double mu = 0.0, double sigma = 1.0) {
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    return mu + sigma * std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }

  // Derives an independent stream, for example one per episode from a trial seed.
  static uint64_t mix(uint64_t a, uint64_t b) {
    Rng r(a ^ (b * 0xD1B54A32D192ED03ull + 0x8CB92BA72F3D8DD7ull));
    return r.next();
  }

 private:
  static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  uint64_t s_[4];
};

}  // namespace roger
