// cloud_shadow.h — the clouds' shadow on the ground: a square map, in the
// clouds' ENU frame, of the direct transmittance exp(-tau) of every cloud
// between a point of the plane z = 0 and the light (Sun or Moon). A host
// samples it for a point p by sliding p along the light onto z = 0 (an affine
// map: cloud_shadow_uv_from_enu), so terrain at any height gets the shadow of
// the clouds above it (points above the clouds are shadowed as if below: the
// map is for terrain and low objects). Pure CPU, no GL.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "core/clouds/cloud_field.h"

namespace atmo::clouds {

struct CloudShadowMap {
  int size = 0;                         // texels per side (0: no map)
  glm::dvec2 corner_enu_m{0.0};         // (east, north) of the map's south-west corner, on z = 0
  double texel_m = 1.0;                 // texel edge, m
  glm::dvec3 light_direction_enu{0.0, 0.0, 1.0};  // unit, towards the light, the map was made for
  std::vector<float> transmittance;     // size * size, east fastest, row 0 southmost; 1 = no cloud
};

// The map for `light_direction_enu` (unit, z > 0.02: a lower light casts
// shadows longer than any map; below that the map is all 1). It covers the
// clouds' shadows on z = 0, at most max_extent_m across (centred on the
// shadows), size x size texels; each texel is one ray marched through every
// cloud box it crosses (trilinear density, steps of `step_voxels`).
// `threads` share the rows (the caller's is one); the map is the same for any count.
CloudShadowMap compute_cloud_shadow_map(const CloudField& field, const glm::dvec3& light_direction_enu, int size = 256,
                                        double max_extent_m = 100000.0, float step_voxels = 1.0f, int threads = 1);

// The affine map from an ENU point (clouds' frame) to the map's (u, v) in
// [0, 1]^2: rows 0 and 1 of the returned 4x4 (column-major, glm), rows 2
// and 3 (0 0 0 0) and (0 0 0 1).
glm::dmat4 cloud_shadow_uv_from_enu(const CloudShadowMap& map);

// For the sky passes (functions.glsl CloudShadowing): a point given in a
// frame F -> (u, v, its height z in the clouds' ENU, 1), where
// clouds_from_frame is the affine map from F to the clouds' ENU.
glm::dmat4 cloud_shadow_uvz_from(const CloudShadowMap& map, const glm::dmat4& clouds_from_frame);

// Bilinear lookup at an ENU point, 1 outside the map (what the GLSL include does).
double sample_cloud_shadow(const CloudShadowMap& map, const glm::dvec3& p_enu_m);

}  // namespace atmo::clouds
