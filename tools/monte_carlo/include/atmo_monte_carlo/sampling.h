// sampling.h — what the CPU Monte Carlo references share: xoshiro256**
// (Blackman & Vigna) seeded through splitmix64, 53-bit uniform doubles, an
// orthonormal basis about a direction and Henyey-Greenstein sampling.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace atmo::monte_carlo {

inline uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// xoshiro256**, its state the next four outputs of splitmix64 from `splitmix_state`.
class Xoshiro256 {
 public:
  explicit Xoshiro256(uint64_t splitmix_state) {
    for (uint64_t& w : s_) w = splitmix64(splitmix_state);
  }
  uint64_t next() {
    const uint64_t r = rotl(s_[1] * 5, 7) * 9;
    const uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return r;
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double exponential() { return -std::log(1.0 - uniform()); }                 // rate 1; 1 - u > 0

 private:
  static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  uint64_t s_[4];
};

// Unit vectors b1, b2 orthogonal to unit n (Duff et al. 2017).
inline void basis(const glm::dvec3& n, glm::dvec3& b1, glm::dvec3& b2) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b = n.x * n.y * a;
  b1 = glm::dvec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
  b2 = glm::dvec3(b, sign + n.y * n.y * a, -n.y);
}

// Cosine of the deflection sampled from Henyey-Greenstein (inverse CDF); isotropic for |g| < 1e-5.
inline double sample_hg_cos(double g, double u) {
  if (std::abs(g) < 1e-5) return 1.0 - 2.0 * u;
  const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
  return std::clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
}

}  // namespace atmo::monte_carlo
