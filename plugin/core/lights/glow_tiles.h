// glow_tiles.h — the lights' glows in fog at a cost bounded per pixel, not
// per light (docs/FOG.md "Glows at scale"). A glow (atmo_fog_glow) has a
// sharp core, the 1/gamma peak around its light, and a smooth rest. Split at
// the core angle gamma_c (a few pixels of the reduced image):
//   - the smooth part, glow(max(gamma, gamma_c)) (atmo_fog_glow with sin gamma
//     floored at sin gamma_c), of all lights together, is evaluated on an image
//     a quarter of the viewport's size across, per screen tile (the clusters'
//     tiles), from a cut of the light tree (best first from the root, by a
//     bound on the glow over the tile, at most kGlowOpens nodes opened): the
//     kExactGlows lights whose glow there is largest exactly, the rest of the
//     cut (lights and nodes) merged into kMergedGlows lights of the tile's own
//     (each a group split along its longest axis, omnidirectional at its
//     weighted centre, with the intensity that gives the group's summed glow
//     along the tile's central ray: a light's glow there by the twin, a
//     node's as one light with its cones as one), then upsampled to every
//     pixel between the surfaces of its block (near and far). The work per
//     tile grows with the tree's depth, not the lights;
//   - the core, glow(gamma) - glow(max(gamma, gamma_c)), which is 0 beyond
//     gamma_c, is drawn at full resolution in a small square around each
//     light whose glow reaches past the pixel on it.
// Pure; the GL layer draws what this lists.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/fog/fog_frame.h"
#include "core/lights/light_clusters.h"
#include "core/lights/light_tree.h"

namespace atmo::lights {

// The smooth image's pixels are kGlowDivisor viewport pixels across.
constexpr int kGlowDivisor = 4;
// The core angle: this many of the smooth image's pixels.
constexpr double kCorePixels = 2.0;
constexpr int kExactGlows = 6;
constexpr int kMergedGlows = 4;
constexpr int kGlowOpens = 96;
// The per-tile budget (the constants above; bench/glow_tiers_error_cost charts others).
struct GlowBudget {
  int exact = kExactGlows, merged = kMergedGlows, opens = kGlowOpens;
};

struct GlowTiles {
  ClusterGrid grid;  // its tiles (the slices are not used)
  // Per tile, its glows: entries[lists[offset[t] + k]] (the frame's lights first, then the merged ones).
  std::vector<uint32_t> offset, count, lists;
  std::vector<fog::FrameLight> merged;  // merged glows (omnidirectional; their cones applied towards the eye)
  std::vector<uint32_t> cores;          // the lights whose core is drawn
  std::vector<float> core_radius_rad;   // ... and how far it reaches (<= the core angle)
  float core_sin = 0.0f;                // sin gamma_c
  uint64_t weighed = 0, merged_entries = 0;  // the tree's entries weighed, and those merged
  uint32_t longest_list = 0;
};

// The NDC rectangle that holds the cone of half-angle `radius` about `towards`
// (ENU, unit): x0, y0, x1, y1; the whole viewport when the cone reaches behind the camera.
glm::vec4 glow_rectangle(const glm::dmat4& clip_from_enu, const glm::dvec3& towards, double radius);

// The glows of a view's frame (fog::make_fog_frame: each light's glow radius
// above the threshold) and its light tree (build_light_tree(frame.lights)).
// clip_from_enu: the host's projection times view-from-ENU (rotation only).
// min_sin: the pixel's floor of sin gamma (fog::glow_min_sin).
GlowTiles bin_glows(const fog::FogFrame& frame, const LightTree& tree, const fog::FogTable& airlight,
                    const glm::dmat4& clip_from_enu, int viewport_width, int viewport_height, double min_sin,
                    const GlowBudget& budget = GlowBudget{});

}  // namespace atmo::lights
