#include "core/clouds/noise.h"

#include <algorithm>
#include <cmath>

namespace atmo::clouds::noise {
namespace {

// One mix per lattice corner: the coordinates enter through odd 64-bit
// multipliers (distinct per axis, so (1, 2) and (2, 1) differ) and the seed;
// mix64 then avalanches. Noise evaluation is dominated by this call.
inline uint64_t lattice(uint64_t seed, int64_t x, int64_t y, int64_t z) {
  return mix64(static_cast<uint64_t>(x) * 0x9e3779b97f4a7c15ull + static_cast<uint64_t>(y) * 0xc2b2ae3d27d4eb4full +
               static_cast<uint64_t>(z) * 0x165667b19e3779f9ull + seed);
}

inline float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
inline float lerp(float a, float b, float t) { return a + (b - a) * t; }

// 2-D: 8 unit directions.
inline float grad2(uint64_t h, float x, float y) {
  constexpr float d = 0.70710678f;
  switch ((h >> 32) & 7u) {
    case 0: return x;
    case 1: return -x;
    case 2: return y;
    case 3: return -y;
    case 4: return d * (x + y);
    case 5: return d * (x - y);
    case 6: return d * (-x + y);
    default: return d * (-x - y);
  }
}

// 3-D: Perlin's 12 cube-edge directions (16 entries, 4 repeated).
inline float grad3(uint64_t h, float x, float y, float z) {
  switch ((h >> 32) & 15u) {
    case 0: return x + y;
    case 1: return -x + y;
    case 2: return x - y;
    case 3: return -x - y;
    case 4: return x + z;
    case 5: return -x + z;
    case 6: return x - z;
    case 7: return -x - z;
    case 8: return y + z;
    case 9: return -y + z;
    case 10: return y - z;
    case 11: return -y - z;
    case 12: return x + y;
    case 13: return -x + y;
    case 14: return -y + z;
    default: return -y - z;
  }
}

}  // namespace

float gradient_noise(double x, double y, uint64_t seed) {
  const double xf = std::floor(x), yf = std::floor(y);
  const int64_t xi = static_cast<int64_t>(xf), yi = static_cast<int64_t>(yf);
  const float fx = static_cast<float>(x - xf), fy = static_cast<float>(y - yf);
  const float n00 = grad2(lattice(seed, xi, yi, 0), fx, fy);
  const float n10 = grad2(lattice(seed, xi + 1, yi, 0), fx - 1.0f, fy);
  const float n01 = grad2(lattice(seed, xi, yi + 1, 0), fx, fy - 1.0f);
  const float n11 = grad2(lattice(seed, xi + 1, yi + 1, 0), fx - 1.0f, fy - 1.0f);
  const float u = fade(fx), v = fade(fy);
  // Unit gradients give at most ~0.71 in 2-D; scale to about [-1, 1].
  return 1.41421356f * lerp(lerp(n00, n10, u), lerp(n01, n11, u), v);
}

float gradient_noise(double x, double y, double z, uint64_t seed) {
  const double xf = std::floor(x), yf = std::floor(y), zf = std::floor(z);
  const int64_t xi = static_cast<int64_t>(xf), yi = static_cast<int64_t>(yf), zi = static_cast<int64_t>(zf);
  const float fx = static_cast<float>(x - xf), fy = static_cast<float>(y - yf), fz = static_cast<float>(z - zf);
  const float n000 = grad3(lattice(seed, xi, yi, zi), fx, fy, fz);
  const float n100 = grad3(lattice(seed, xi + 1, yi, zi), fx - 1.0f, fy, fz);
  const float n010 = grad3(lattice(seed, xi, yi + 1, zi), fx, fy - 1.0f, fz);
  const float n110 = grad3(lattice(seed, xi + 1, yi + 1, zi), fx - 1.0f, fy - 1.0f, fz);
  const float n001 = grad3(lattice(seed, xi, yi, zi + 1), fx, fy, fz - 1.0f);
  const float n101 = grad3(lattice(seed, xi + 1, yi, zi + 1), fx - 1.0f, fy, fz - 1.0f);
  const float n011 = grad3(lattice(seed, xi, yi + 1, zi + 1), fx, fy - 1.0f, fz - 1.0f);
  const float n111 = grad3(lattice(seed, xi + 1, yi + 1, zi + 1), fx - 1.0f, fy - 1.0f, fz - 1.0f);
  const float u = fade(fx), v = fade(fy), w = fade(fz);
  const float nx00 = lerp(n000, n100, u), nx10 = lerp(n010, n110, u);
  const float nx01 = lerp(n001, n101, u), nx11 = lerp(n011, n111, u);
  return lerp(lerp(nx00, nx10, v), lerp(nx01, nx11, v), w);
}

float fbm(double x, double y, int octaves, uint64_t seed) {
  float sum = 0.0f, amp = 1.0f, norm = 0.0f;
  double f = 1.0;
  for (int o = 0; o < octaves; ++o) {
    // Each octave its own lattice seed and a fixed irrational shift, so the
    // lattice zeros of the octaves do not line up.
    sum += amp * gradient_noise(x * f + 0.31 * o, y * f + 0.67 * o, seed + 0x632be59bd9b4e019ull * (o + 1));
    norm += amp;
    amp *= 0.5f;
    f *= 2.0;
  }
  return sum / norm;
}

float fbm(double x, double y, double z, int octaves, uint64_t seed) {
  float sum = 0.0f, amp = 1.0f, norm = 0.0f;
  double f = 1.0;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * gradient_noise(x * f + 0.31 * o, y * f + 0.67 * o, z * f + 0.13 * o,
                                seed + 0x632be59bd9b4e019ull * (o + 1));
    norm += amp;
    amp *= 0.5f;
    f *= 2.0;
  }
  return sum / norm;
}

float worley(double x, double y, double z, uint64_t seed) {
  const double xf = std::floor(x), yf = std::floor(y), zf = std::floor(z);
  const int64_t xi = static_cast<int64_t>(xf), yi = static_cast<int64_t>(yf), zi = static_cast<int64_t>(zf);
  const float fx = static_cast<float>(x - xf), fy = static_cast<float>(y - yf), fz = static_cast<float>(z - zf);
  constexpr float kUnit = 1.0f / 16777216.0f;  // 24 bits -> [0, 1)
  float best = 1e9f;
  for (int k = -1; k <= 1; ++k)
    for (int j = -1; j <= 1; ++j)
      for (int i = -1; i <= 1; ++i) {
        const uint64_t h = lattice(seed, xi + i, yi + j, zi + k);
        const float px = i + static_cast<float>(h & 0xffffffu) * kUnit;
        const float py = j + static_cast<float>((h >> 24) & 0xffffffu) * kUnit;
        const float pz = k + static_cast<float>((h >> 48) & 0xffffu) * (1.0f / 65536.0f);
        const float dx = px - fx, dy = py - fy, dz = pz - fz;
        best = std::min(best, dx * dx + dy * dy + dz * dz);
      }
  return std::sqrt(best);
}

}  // namespace atmo::clouds::noise
