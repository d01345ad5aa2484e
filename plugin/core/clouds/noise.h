// noise.h — the hand-written randomness of the procedural clouds: an integer
// hash, a small PRNG, gradient noise (2-D and 3-D), fBm and Worley (cellular)
// noise. Everything is integer hashing plus fixed float arithmetic, so the same
// seed gives bit-identical clouds on every run of a build (std::*_distribution
// is implementation-defined, so it is not used).
#pragma once

#include <cstdint>

namespace atmo::clouds::noise {

// splitmix64's finaliser: a bijective 64-bit mix with full avalanche.
inline uint64_t mix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// Hash of a seed and up to three lattice coordinates.
inline uint64_t hash(uint64_t seed, int64_t x, int64_t y = 0, int64_t z = 0) {
  uint64_t h = mix64(seed ^ 0x51a3c0ffee123457ull);
  h = mix64(h ^ static_cast<uint64_t>(x));
  h = mix64(h ^ static_cast<uint64_t>(y));
  return mix64(h ^ static_cast<uint64_t>(z));
}

// A seed derived from a parent seed and a label (so streams never overlap).
inline uint64_t derive_seed(uint64_t seed, uint64_t label) {
  return hash(seed, static_cast<int64_t>(label), 0x7e57, 1);
}

// splitmix64 generator: tiny, fast, passes BigCrush; enough for placement.
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    state_ += 0x9e3779b97f4a7c15ull;
    uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  // [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  // [0, n) for n > 0 (multiply-shift; the bias is < n / 2^64).
  uint32_t below(uint32_t n) {
    return static_cast<uint32_t>((static_cast<unsigned __int128>(next()) * n) >> 64);
  }

 private:
  uint64_t state_;
};

// Gradient (Perlin-style) noise, quintic fade, about [-1, 1], 0 at lattice
// points, period 1 lattice unit of features. Coordinates are double so that
// world positions tens of km from the origin keep their fraction.
float gradient_noise(double x, double y, uint64_t seed);
float gradient_noise(double x, double y, double z, uint64_t seed);

// Fractal sum of gradient noise: octaves at lacunarity 2 and gain 0.5,
// normalised by the sum of amplitudes, so about [-1, 1] (std ~0.2-0.3).
float fbm(double x, double y, int octaves, uint64_t seed);
float fbm(double x, double y, double z, int octaves, uint64_t seed);

// Worley F1: distance (lattice units) from the point to the nearest of one
// jittered feature point per lattice cell, in [0, ~1.2]. 1 - F1 gives round
// lumps: the cauliflower of cumulus tops.
float worley(double x, double y, double z, uint64_t seed);

}  // namespace atmo::clouds::noise
