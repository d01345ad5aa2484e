// occlusion_twin.h — compiles host_sdk/include/atmo/atmo_sky_occlusion.glsl
// as C++ over GLM, in float like the GPU, reading an OcclusionFrame (what the
// GL layer uploads) the way the include reads its textures and uniforms: the
// CPU evaluates the text the hosts' shaders and the plugin's pass run.
#pragma once

#include <glm/glm.hpp>

#include "core/shadows/occlusion_frame.h"

namespace atmo::shadows::twin {

using namespace glm;
using uint = glm::uint;

struct AtmoOccSh {
  vec4 a, b, c, d;
};
struct AtmoSkyOcclusion {
  vec3 sky_lux{0.0f};
  float sun_visibility = 1.0f;
  vec3 bounce_lux{0.0f};
  float sky_visibility = 1.0f;
};
struct AtmoOccFit {
  vec4 sky{0.0f}, bounce{0.0f}, extra{0.0f};
};

#define ATMO_TWIN
#define ATMO_OCC_FN inline
#define INOUT(T) T&
#define ATMO_OCC_NO_UNIFORMS
#include "atmo/atmo_sky_occlusion.glsl"
#undef ATMO_OCC_NO_UNIFORMS
#undef ATMO_SKY_OCCLUSION_GLSL

// The include's texture and uniform reads, from the frame being evaluated (one per thread).
inline thread_local const OcclusionFrame* frame = nullptr;

inline vec4 atmo_occ_table(float u, float row) {  // GL_LINEAR, CLAMP_TO_EDGE along the row, exact row
  const OcclusionTables& t = occlusion_tables();
  const float n = static_cast<float>(OcclusionTables::kSize);
  const float x = atmo_occ_grid_coordinate(u, n) * n - 0.5f;
  const int i0 = static_cast<int>(floor(x));
  const float f = x - i0;
  auto at = [&](int i) { return t.texels[static_cast<int>(row) * OcclusionTables::kSize + clamp(i, 0, OcclusionTables::kSize - 1)]; };
  return mix(at(i0), at(i0 + 1), f);
}
inline vec4 atmo_occ_sphere(uint i) { return frame->spheres[i]; }
inline vec4 atmo_occ_object(uint i, int k) { return frame->objects[4 * i + k]; }
inline uvec2 atmo_occ_tile_list(const vec3& position_rel_eye_m) {
  const vec4 clip = frame->tile_from_position * vec4(position_rel_eye_m, 1.0f);
  if (!(clip.w > 1.0e-6f)) return uvec2(0u, 0u);
  const vec2 ndc = clamp(vec2(clip.x, clip.y) / clip.w, -1.0f, 1.0f);
  const vec2 g(frame->grid.x, frame->grid.y);
  const ivec2 tile(min(floor((ndc * 0.5f + 0.5f) * g), g - 1.0f));
  return frame->tiles[tile.y * frame->tiles_x + tile.x];
}
inline uint atmo_occ_tile_object(uint entry) { return frame->tile_objects[entry]; }
inline vec4 atmo_occ_transfer_at(int k) {
  const float* t = frame->sky.transfer.data() + 4 * k;
  return vec4(t[0], t[1], t[2], t[3]);
}
inline vec3 atmo_occ_sky_sh9_at(int k) {
  const float* t = frame->sky.sky_sh9.data() + 3 * k;
  return vec3(t[0], t[1], t[2]);
}
inline vec3 atmo_occ_sun_sh9_at(int k) {
  const float* t = frame->sky.sun_sh9.data() + 3 * k;
  return vec3(t[0], t[1], t[2]);
}
inline vec4 atmo_occ_grid_value() { return frame->grid; }
inline vec4 atmo_occ_limits_value() { return frame->limits; }
inline vec4 atmo_occ_sun_value() { return frame->sun; }
inline mat3 atmo_occ_enu_from_world_value() { return frame->enu_from_world; }

#undef ATMO_OCC_NO_UNIFORMS
#include "atmo/atmo_sky_occlusion.glsl"
#undef INOUT
#undef ATMO_OCC_FN
#undef ATMO_TWIN

// The include's answer at a receiver of this frame.
inline AtmoSkyOcclusion evaluate(const OcclusionFrame& f, const glm::vec3& position_rel_eye_m, const glm::vec3& normal) {
  frame = &f;
  const AtmoSkyOcclusion r = atmo_sky_occlusion(position_rel_eye_m, normal);
  frame = nullptr;
  return r;
}

// The include's answer and its fit by normal (a texel of ATMO_PASS_SKY_OCCLUSION_IMAGE's image).
inline AtmoSkyOcclusion evaluate_fit(const OcclusionFrame& f, const glm::vec3& position_rel_eye_m,
                                     const glm::vec3& normal, AtmoOccFit* fit) {
  frame = &f;
  const AtmoSkyOcclusion r = atmo_occ_evaluate(position_rel_eye_m, normal, true, *fit);
  frame = nullptr;
  return r;
}

// What the include with ATMO_OCC_IMAGE makes of a texel's fit for a normal (ENU axes here), on the frame's sky.
inline AtmoSkyOcclusion from_fit(const OcclusionFrame& f, const AtmoOccFit& fit, const glm::vec3& normal) {
  frame = &f;
  const glm::vec3 open = max(atmo_occ_sh9_dot(0, atmo_occ_basis(normal)), vec3(0.0f));
  const AtmoSkyOcclusion r = atmo_occ_from_fit(fit, normal, open);
  frame = nullptr;
  return r;
}

}  // namespace atmo::shadows::twin
