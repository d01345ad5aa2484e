// point_footprint.glsl — how much of a point source's light falls in a pixel:
// ONE source for two compilers, like atmosphere/functions.glsl. The night-sky
// pass (shaders/night_points.frag) #includes it, and
// plugin/core/night_sky/point_footprint_twin.h compiles it as C++ over GLM
// (the CPU twin, in float like the GPU); tests/core/point_sources_test.cpp
// checks it against the core's double-precision star_footprint_weight
// (plugin/core/night_sky/star_photometry.h).
//
// A star is a Gaussian of standard deviation sigma_px pixels whose integral is
// 1; a pixel receives the Gaussian integrated over its square, so the weights
// of all pixels sum to 1 wherever the star's centre falls: no flicker when it
// crosses pixel boundaries. GLSL has no erf: Abramowitz & Stegun 7.1.26
// (|error| < 1.5e-7), the same formula as the core's erf_approx.
// Needs ATMO_FN defined (nothing in GLSL, `inline` in C++).

ATMO_FN float footprint_erf(float x) {
  float ax = abs(x);
  float t = 1.0f / (1.0f + 0.3275911f * ax);
  float poly = t * (0.254829592f + t * (-0.284496736f + t * (1.421413741f + t * (-1.453152027f + t * 1.061405429f))));
  float y = 1.0f - poly * exp(-ax * ax);
  return x < 0.0f ? -y : y;
}

// The fraction of a 1-D Gaussian (k = 1 / (sqrt(2) sigma)) inside the pixel
// whose centre is d pixels from the Gaussian's centre.
ATMO_FN float footprint_axis_weight(float d, float k) {
  return max(0.5f * (footprint_erf((d + 0.5f) * k) - footprint_erf((d - 0.5f) * k)), 0.0f);
}

// The fraction of the star's light in the pixel whose centre is (dx, dy)
// pixels from the star's centre.
ATMO_FN float point_footprint_weight(float dx, float dy, float sigma_px) {
  float k = 0.70710678f / max(sigma_px, 1e-6f);
  return footprint_axis_weight(dx, k) * footprint_axis_weight(dy, k);
}
