// shader_twin.h — compiles shaders/atmosphere/functions.glsl as C++ over GLM,
// so the CPU evaluates exactly the formulas the GPU runs (one source of truth,
// in float like the GPU). Texture sampling is emulated by Lut2D,
// with GL_LINEAR + GL_CLAMP_TO_EDGE semantics.
#pragma once

#include <glm/glm.hpp>
#include <vector>

namespace atmo::twin {

using namespace glm;

// Row-major table of RGB transmittance, `width` along u (x_mu), `height` along v (x_r).
struct Lut2D {
  int width = 0;
  int height = 0;
  std::vector<vec3> texels;
  const vec3& at(int x, int y) const { return texels[static_cast<size_t>(y) * width + x]; }
};

// Bilinear filtering with clamp-to-edge, as GL does for texture(sampler2D, uv).
inline vec3 sample_lut(const Lut2D& table, const vec2& uv) {
  float fx = uv.x * table.width - 0.5f;
  float fy = uv.y * table.height - 0.5f;
  int x0 = static_cast<int>(floor(fx));
  int y0 = static_cast<int>(floor(fy));
  float ax = fx - x0;
  float ay = fy - y0;
  auto cx = [&](int x) { return x < 0 ? 0 : (x >= table.width ? table.width - 1 : x); };
  auto cy = [&](int y) { return y < 0 ? 0 : (y >= table.height ? table.height - 1 : y); };
  vec3 a = mix(table.at(cx(x0), cy(y0)), table.at(cx(x0 + 1), cy(y0)), ax);
  vec3 b = mix(table.at(cx(x0), cy(y0 + 1)), table.at(cx(x0 + 1), cy(y0 + 1)), ax);
  return mix(a, b, ay);
}

#include "core/twin/glsl_begin.h"
#define LUT2D const Lut2D&
#include "atmosphere/functions.glsl"
// The aerial-perspective volume's slice mapping, from the host include.
#define ATMO_TWIN
#define ATMO_AP_FN inline
#define ATMO_AP_OUT(T) T&
#include "atmo/atmo_aerial_perspective.glsl"
#undef ATMO_AP_OUT
#undef ATMO_AP_FN
#undef ATMO_TWIN
#include "core/twin/glsl_end.h"
#undef LUT2D

}  // namespace atmo::twin
