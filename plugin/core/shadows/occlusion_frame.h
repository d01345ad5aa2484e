// occlusion_frame.h — a view's occluders as atmo_sky_occlusion.glsl reads
// them: the spheres moved to the eye's ENU frame, each object's bound and
// far stand-in, and per screen tile the objects that may shade a receiver in
// it (docs/SKY_OCCLUSION.md). Pure: the GL layer uploads it as is, the twin
// evaluates it on the CPU.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "core/shadows/occlusion_tables.h"

namespace atmo::shadows {

// A group of an object's spheres (the hierarchy's middle level): its bound and stand-in, and its spheres
// [first, first + count) of the object's (which are stored group by group).
struct OccluderGroup {
  glm::dvec4 bound{0.0}, proxy{0.0};
  uint32_t first = 0, count = 0;
};

// One object of the host's, in its own frame (m).
struct OccluderObject {
  std::vector<glm::dvec4> spheres;  // centre, radius; reordered group by group
  glm::dvec3 albedo{0.0};           // diffuse, linear RGB, for the bounce
  glm::dvec4 bound{0.0};            // a sphere holding every sphere
  // Where the object is small in the sky it counts as this one sphere: at the spheres' volume-weighted
  // centre, of the union's mean projected area (Cauchy: over directions, sampled).
  glm::dvec4 proxy{0.0};
  // Where it is large, group by group: each group small in the sky counts as its own stand-in.
  std::vector<OccluderGroup> groups;
};
// The most spheres a group holds (groups by median splits of the centres along their longest extent).
constexpr uint32_t kGroupSpheres = 8;
// Computes the groups, bounds and stand-ins (deterministic; ~1 ms for 32 spheres).
OccluderObject make_occluder_object(std::vector<glm::dvec4> spheres, const glm::dvec3& albedo);

// Where spheres stop counting (sin of angular radii) and the Sun's disc.
struct OcclusionLimits {
  double sin_cull = 0.0261769;       // sin 1.5 deg: a sphere smaller in the sky is left out (faded in to 3 deg)
  double sin_far = 0.3420201;        // sin 20 deg: an object's (a group's) bound smaller than this is its proxy alone
  double sin_near = 0.5;             // sin 30 deg: larger, its spheres alone (blended between)
  double sun_radius_rad = 0.0046542; // the Sun's mean angular radius
  bool bounce = true;
  bool hybrid = true;  // the hybrid exponential (else optimal linear)
};

struct OcclusionFrame {
  int tiles_x = 1, tiles_y = 1;
  static constexpr int kTilePx = 32;
  glm::mat4 tile_from_position{1.0f};  // clip from the position relative to the eye, world axes
  glm::mat3 enu_from_world{1.0f};
  // ENU relative to the eye: every sphere (centre, radius), then 3 texels a group: bound, stand-in,
  // (first sphere, count, 0, 0).
  std::vector<glm::vec4> spheres;
  std::vector<glm::vec4> objects;      // 4 per object: bound, proxy, (albedo, 0), (first group's texel, groups, 0, 0)
  std::vector<glm::uvec2> tiles;       // per tile: first entry in tile_objects, count
  std::vector<uint32_t> tile_objects;
  glm::vec4 grid{0.0f}, limits{0.0f}, sun{0.0f};
  glm::vec3 sun_lux{0.0f};
  SkyTransfer sky;
  uint32_t longest_tile_list = 0;
};

// enu_from_object[i]: object i's pose, its frame to ENU at the eye relative to the eye (rigid).
// clip_from_world: the host's projection times its view rotation (positions relative to the eye, world
// axes); enu_from_world: the eye's ENU axes. Sun: unit ENU direction and its illuminance (lux).
OcclusionFrame make_occlusion_frame(const std::vector<const OccluderObject*>& objects,
                                    const std::vector<glm::dmat4>& enu_from_object, const glm::dmat4& clip_from_world,
                                    const glm::dmat3& enu_from_world, int viewport_width, int viewport_height,
                                    const SkyTransfer& sky, const glm::dvec3& sun_direction_enu,
                                    const glm::dvec3& sun_illuminance_lux, const OcclusionLimits& limits);

}  // namespace atmo::shadows
