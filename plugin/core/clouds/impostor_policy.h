// impostor_policy.h — when a cloud is drawn from its impostor and when by the
// direct march, when an impostor is re-rendered, and the billboard it lies on
// (Harris & Lastra 2001's dynamic impostors, seed 000 and docs/CLOUDS.md).
// Pure functions of the geometry, tested on the CPU; gl/cloud_impostors draws
// what they decide. Positions are metres in any one fixed frame (the clouds'
// ENU frame in the plugin).
#pragma once

#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

namespace atmo::clouds {

struct ImpostorSettings {
  int tile_texels = 128;                 // an impostor's square side in the atlas
  double angle_threshold_rad = 0.5 * 3.14159265358979323846 / 180.0;  // re-render past this view change
  int updates_per_frame = 8;             // re-renders of existing impostors per frame (new ones always render)
  double near_radius_scale = 2.0;        // the direct march takes over within this many bounding radii
  double max_pixels_per_texel = 1.0;     // ... or when an impostor texel would cover more screen pixels
  double crossfade_band = 0.25;          // both drawn, cross-faded, over this fraction below the switch
  double cut_staleness = 16.0;           // this many thresholds (a camera cut): re-render at once, budget or not
};

// The billboard an impostor is rendered on and drawn with: the plane through
// the cloud's centre facing the eye it was rendered from, the square on it
// that the bounding sphere's silhouette cone crosses.
struct Billboard {
  glm::dvec3 centre_m{0.0};   // the cloud's bounding-sphere centre
  glm::dvec3 right{1.0, 0.0, 0.0};
  glm::dvec3 up{0.0, 0.0, 1.0};
  double half_size_m = 0.0;   // half the square's side
};

// The billboard for an eye outside the sphere; a degenerate eye (inside or on
// the sphere) gets the half size of an eye at 1.05 radii, so it stays finite.
Billboard make_billboard(const glm::dvec3& eye_m, const glm::dvec3& centre_m, double radius_m);

// How far the view of a sphere changed between the eye it was rendered from
// and this one, rad: the larger of the turn of the direction to its centre
// and the change of its angular radius (moving straight at a cloud changes
// its perspective without turning the direction).
double impostor_view_change_rad(const glm::dvec3& baked_eye_m, const glm::dvec3& eye_m, const glm::dvec3& centre_m,
                                double radius_m);

// Need of the direct march, >= 1: direct only; below 1 - crossfade_band:
// impostor only. The larger of (near_radius_scale * r / distance) and the
// impostor's screen texel size over max_pixels_per_texel, where
// pixels_per_radian is the target image's (the march's) pixel density.
double direct_march_need(double distance_m, double radius_m, double pixels_per_radian, const ImpostorSettings& s);

// The direct march's share of a cloud in [0, 1] from its need: 0 below the
// band, 1 from 1 up, smooth between (the impostor gets the rest).
double direct_march_weight(double need, const ImpostorSettings& s);

// Which stale impostors to re-render this frame: indices of `staleness`
// (view change / threshold, light change counting as 1 or more): every one
// at or past cut_staleness, then those >= 1, largest first, up to
// updates_per_frame of them.
std::vector<size_t> choose_impostor_updates(const std::vector<double>& staleness, const ImpostorSettings& s);

}  // namespace atmo::clouds
