// light_clusters.h — the host's surfaces lit by thousands of lights at a
// cost bounded by a list length, not the light count (clustered shading,
// Olsson, Billeter & Assarsson 2012): the view is cut into froxels (screen
// tiles x slices of distance, exponential), and each froxel gets
//   - the list of the lights that reach it (a light reaches a point where it
//     can add at least the threshold to a white surface facing it: its range,
//     from the direct and single-scattered terms; a cone light only inside
//     its cone), the kNearLights most important of them: atmo_fog_lights.glsl
//     shades each exactly;
//     The lights that reach it beyond those are merged into up to
//     kMergedLights lights of the froxel's own (lightcuts, Walter et al.
//     2005): each a group of them split along its longest axis, at the
//     group's intensity-weighted centre, with the intensity that gives the
//     group's irradiance at the froxel's centre (cones and fog applied
//     there): the include shades these like the others, so the ground under
//     a group lit from above stays lit from above;
//   - a far field at the froxel's centre: in fog, every light's diffusion (P1)
//     term, which reaches kilometres, as an ambient cube (the irradiance on
//     the six faces +E, -E, +N, -N, +U, -U; E(n) = sum n_i^2 E(face of sign
//     n_i), exact for a face's normal: the ground gets exactly the light from
//     above it, where an L1 form would give a grazing light a quarter of its
//     irradiance): the include adds it, filtered between froxel centres.
// Pure; the GL layer uploads the lists and the field (docs/FOG.md "Surfaces
// at scale").
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/fog/fog_frame.h"

namespace atmo::lights {

// The cluster grid of a view: square tiles of about tile_px pixels (at least
// kMinTiles and at most kMaxTiles across) and kSlices slices of distance from
// the eye, d_k = near (far / near)^(k / kSlices): each slice 1.47 times as
// deep as the last, from 1 m to 10 km (beyond: the last slice). The surfaces'
// clusters use kSurfaceTilePx (a light's list costs its pairs of light and
// cluster, so they are coarse), the glows' tiles kGlowTilePx.
struct ClusterGrid {
  static constexpr int kSurfaceTilePx = 64, kGlowTilePx = 32;
  static constexpr int kMinTiles = 16, kMaxTiles = 64;
  static constexpr int kSlices = 24;
  int tiles_x = 1, tiles_y = 1;
  double near_m = 1.0, far_m = 10000.0;
  glm::dmat4 clip_from_enu{1.0};  // the host's projection times view-from-ENU-at-the-eye (rotation only)

  static ClusterGrid for_view(const glm::dmat4& clip_from_enu, int viewport_width, int viewport_height, int tile_px);
  int froxels() const { return tiles_x * tiles_y * kSlices; }
  int index(int x, int y, int slice) const { return (slice * tiles_y + y) * tiles_x + x; }
  double slice_distance(double k) const;  // the distance at slice coordinate k
  // The slice coordinate of a distance (fractional; clamped to [0, kSlices]).
  double slice_of(double distance_m) const;
};

// At most this many lights per froxel shade each pixel exactly; the rest are merged into at most kMergedLights.
constexpr int kNearLights = 8;
constexpr int kMergedLights = 4;

struct LightClusters {
  ClusterGrid grid;
  // Per froxel, its list: lists[offset[f], offset[f] + count[f]) (light indices into the fog frame).
  std::vector<uint32_t> offset, count;
  std::vector<uint32_t> lists;
  // Per froxel, the far field: the irradiance (lux, rgb) on the faces +E, -E, +N, -N, +U, -U (ENU at the eye).
  static constexpr int kFaces = 6;
  std::vector<glm::vec3> far[kFaces];
  std::vector<float> range_m;  // per light, its range (0: it lights nothing above the threshold)
  // The merged lights (omnidirectional, their cones and fog applied at their froxel's centre): lists index
  // them after the frame's lights (frame.lights.size() + k); merged_range_m their ranges.
  std::vector<fog::FrameLight> merged;
  std::vector<float> merged_range_m;
  // What it cost: (light, froxel) pairs tested and kept, lights sent to far fields.
  uint64_t pairs = 0, overflow = 0;
  uint32_t longest_list = 0;
};

// Per light, the distance beyond which its direct and single-scattered light
// on a white Lambertian surface facing it stays below `threshold_cd_m2`
// (conservative: the scattered term bounded by the table's largest e^T G), m.
std::vector<float> surface_ranges(const fog::FogFrame& frame, float albedo, double threshold_cd_m2);

// The clusters of a view. `diffusion_field`: add every light's diffusion term
// (fog with multiple scattering) to the far fields.
LightClusters cluster_lights(const fog::FogFrame& frame, const ClusterGrid& grid, float fog_albedo,
                             double threshold_cd_m2);

}  // namespace atmo::lights
