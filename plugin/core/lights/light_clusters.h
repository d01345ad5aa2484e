// light_clusters.h — the host's surfaces lit by thousands of lights at a
// cost bounded by a list length, not the light count (clustered shading,
// Olsson, Billeter & Assarsson 2012): the view is cut into froxels (screen
// tiles x slices of distance, exponential), and each froxel gets
//   - a list of at most kListLights lights from a cut of the light tree
//     (lightcuts, Walter et al. 2005): from the root, best first, the entry
//     that may add the most to the froxel (a node's summed intensity over
//     its nearest distance squared, fog applied) is replaced by its
//     children, or taken if it is a light, until the froxel has its
//     kListLights - kMergedLights most important lights or kCutOpens nodes
//     are opened. Of the cut, the entries that add the most at the
//     froxel's centre are listed one by one (a node as
//     one light at its weighted centre, with its lights' irradiance at the
//     froxel's centre, cones and fog applied: the ground under a group lit
//     from above stays lit from above), the rest merged into up to
//     kMergedLights lights of the froxel's own. A light or node reaches a
//     froxel where it can add at least the threshold to a white surface
//     facing it (its range, from the direct and single-scattered terms; a
//     cone light only inside its cone). atmo_fog_lights.glsl shades each
//     entry exactly;
//   - a far field at the froxel's centre: in fog, every light's diffusion (P1)
//     term, which reaches kilometres, as an ambient cube (the irradiance on
//     the six faces +E, -E, +N, -N, +U, -U; E(n) = sum n_i^2 E(face of sign
//     n_i), exact for a face's normal: the ground gets exactly the light from
//     above it, where an L1 form would give a grazing light a quarter of its
//     irradiance), from the tree (Barnes-Hut): the include adds it, filtered
//     between froxel centres.
// The work per froxel grows with the tree's depth (log n), not with n.
// Pure; the GL layer uploads the lists and the field (docs/FOG.md "Surfaces
// at scale").
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/fog/fog_frame.h"
#include "core/lights/light_tree.h"

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

// At most this many entries per froxel, each shaded exactly by the include: lights, nodes of lights, and up to
// kMergedLights merged lights (the rest of its cut).
constexpr int kListLights = 12;
constexpr int kMergedLights = 4;
// A froxel's cut of the tree opens this many nodes best first, then those too near for one light, up to
// kCutOpensMost in all.
constexpr int kCutOpens = 64;
constexpr int kCutOpensMost = 256;
// A node of at most this many lights is shaded towards a froxel with its lights' own cones (their sum at the
// froxel's centre); a larger one as one cone (node_intensity_towards).
constexpr uint32_t kExactNodeLights = 16;

struct LightClusters {
  ClusterGrid grid;
  // Per froxel, its list: lists[offset[f], offset[f] + count[f]) (light indices into the fog frame, or
  // frame.lights.size() + k for merged[k]), and each entry's range (m: it lights nothing beyond).
  std::vector<uint32_t> offset, count;
  std::vector<uint32_t> lists;
  std::vector<float> list_range_m;
  // Per froxel, the far field: the irradiance (lux, rgb) on the faces +E, -E, +N, -N, +U, -U (ENU at the eye).
  static constexpr int kFaces = 6;
  std::vector<glm::vec3> far[kFaces];
  // The nodes of the lists, each as one omnidirectional light (its cones and fog applied at its froxel's centre).
  std::vector<fog::FrameLight> merged;
  // What it cost: the tree's nodes opened, the lights inside the listed nodes.
  uint64_t opened = 0, merged_lights = 0;
  uint32_t longest_list = 0;
};

// The distance beyond which a light of peak intensity I (cd) lights a white
// Lambertian surface facing it below a threshold through the frame's fog
// (direct and single-scattered terms, the latter bounded by the surface
// table's largest e^T G), from a table made once per frame (16 intensities
// an octave, rounded up): never less than the exact range, at most that of
// a 4.4 % brighter light (2.2 % farther in clear air).
class SurfaceRange {
 public:
  SurfaceRange(const fog::FogFrame& frame, const LightTree& tree, float albedo, double threshold_cd_m2);
  float operator()(float intensity_cd) const;
  float exact(double intensity_cd) const;  // by bisection

 private:
  static constexpr int kBucketShift = 19;  // a float's bits >> 19: 16 buckets an octave
  static uint32_t bucket(float intensity_cd);
  double e_min_ = 0.0, beta_lo_ = 0.0, scattering_ = 0.0;
  uint32_t first_bucket_ = 0;
  std::vector<float> range_m_;  // at the top of bucket first_bucket_ + k
};

// The clusters of a view from its frame's lights and their tree (build_light_tree(frame.lights)).
LightClusters cluster_lights(const fog::FogFrame& frame, const LightTree& tree, const ClusterGrid& grid,
                             float fog_albedo, double threshold_cd_m2);

}  // namespace atmo::lights
