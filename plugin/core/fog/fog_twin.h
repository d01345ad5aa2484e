// fog_twin.h — compiles host_sdk/include/atmo/atmo_fog_lights.glsl as C++
// over GLM, in float like the GPU, with the tables sampled as GL_LINEAR +
// CLAMP_TO_EDGE does: the CPU evaluates the text the glow pass and the
// hosts' surface shaders run (core/atmosphere/shader_twin.h does this for the sky).
#pragma once

#include <glm/glm.hpp>

#include "core/fog/fog_model.h"

namespace atmo::fog::twin {

using namespace glm;

// texture(sampler2D, uv).r for a GL_R32F table with GL_LINEAR, GL_CLAMP_TO_EDGE.
inline float atmo_fog_table_fetch(const FogTable& t, const vec2& uv) {
  const float fx = uv.x * t.width - 0.5f, fy = uv.y * t.height - 0.5f;
  const int x0 = static_cast<int>(floor(fx)), y0 = static_cast<int>(floor(fy));
  const float ax = fx - x0, ay = fy - y0;
  auto cx = [&](int x) { return x < 0 ? 0 : (x >= t.width ? t.width - 1 : x); };
  auto cy = [&](int y) { return y < 0 ? 0 : (y >= t.height ? t.height - 1 : y); };
  const float a = mix(t.at(cx(x0), cy(y0)), t.at(cx(x0 + 1), cy(y0)), ax);
  const float b = mix(t.at(cx(x0), cy(y0 + 1)), t.at(cx(x0 + 1), cy(y0 + 1)), ax);
  return mix(a, b, ay);
}

#define ATMO_TWIN
#define ATMO_FOG_FN inline
#define ATMO_FOG_TABLE FogTable
#define ATMO_FOG_IN(T) const T&
#include "atmo/atmo_fog_lights.glsl"
#undef ATMO_FOG_IN
#undef ATMO_FOG_TABLE
#undef ATMO_FOG_FN
#undef ATMO_TWIN

// What the fog pass (fog_medium.frag) draws for one omnidirectional light of
// 1 cd at `distance` metres from the eye, in fog without a top of extinction
// `beta` (1/m) and diffusion vector `diffusion` (make_fog_frame's), along an
// open-sky ray at cos_gamma to the direction of the light, without ambient:
// the light's fluence and flux at the eye as make_fog_frame sums them
// (atmo_fog_diffusion_light), through atmo_fog_medium_light. For the
// measurements against the Monte Carlo (tools/fog_reference, its tests).
inline float atmo_fog_pass_one_light(const vec4& diffusion, float beta, float distance, float cos_gamma) {
  const vec2 p1 = atmo_fog_diffusion_light(diffusion, distance, beta * distance, false);
  const vec3 towards(1.0f, 0.0f, 0.0f);
  const vec3 dir(cos_gamma, sqrt(max(1.0f - cos_gamma * cos_gamma, 0.0f)), 0.0f);
  const mat3 flux(p1.y * towards, p1.y * towards, p1.y * towards);
  const float transmittance = atmo_fog_transmittance(beta, atmo_fog_ray_length(ATMO_FOG_FAR, dir.z, ATMO_FOG_FAR));
  return atmo_fog_medium_light(transmittance, vec3(0.0f), vec3(p1.x), flux, dir).x;
}

}  // namespace atmo::fog::twin
