#include "core/clouds/impostor_policy.h"

#include <algorithm>
#include <cmath>

namespace atmo::clouds {

namespace {
// Angular radius of a sphere of radius r at distance d (pi/2 from inside).
double angular_radius(double r, double d) { return d > r ? std::asin(r / d) : 0.5 * M_PI; }
}  // namespace

Billboard make_billboard(const glm::dvec3& eye_m, const glm::dvec3& centre_m, double radius_m) {
  Billboard b;
  b.centre_m = centre_m;
  const glm::dvec3 to_centre = centre_m - eye_m;
  const double d = glm::length(to_centre);
  const glm::dvec3 forward = d > 0.0 ? to_centre / d : glm::dvec3(0.0, 1.0, 0.0);
  // Up as close to the frame's up as the forward direction allows.
  const glm::dvec3 hint = std::abs(forward.z) < 0.99 ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(0.0, 1.0, 0.0);
  b.right = glm::normalize(glm::cross(forward, hint));
  b.up = glm::cross(b.right, forward);
  // The silhouette cone (half-angle asin(r/d)) crosses the plane at distance d
  // at r d / sqrt(d^2 - r^2).
  const double de = std::max(d, 1.05 * radius_m);
  b.half_size_m = radius_m * de / std::sqrt(de * de - radius_m * radius_m);
  return b;
}

double impostor_view_change_rad(const glm::dvec3& baked_eye_m, const glm::dvec3& eye_m, const glm::dvec3& centre_m,
                                double radius_m) {
  const glm::dvec3 a = centre_m - baked_eye_m, b = centre_m - eye_m;
  const double la = glm::length(a), lb = glm::length(b);
  if (!(la > 0.0) || !(lb > 0.0)) return M_PI;
  const double turn = std::acos(std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0));
  const double zoom = std::abs(angular_radius(radius_m, la) - angular_radius(radius_m, lb));
  return std::max(turn, zoom);
}

double direct_march_need(double distance_m, double radius_m, double pixels_per_radian, const ImpostorSettings& s) {
  if (!(distance_m > 0.0)) return 1e9;
  const double near = s.near_radius_scale * radius_m / distance_m;
  const double screen_px = 2.0 * angular_radius(radius_m, distance_m) * pixels_per_radian;
  const double texel_px = screen_px / std::max(1, s.tile_texels);
  return std::max(near, texel_px / std::max(1e-6, s.max_pixels_per_texel));
}

double direct_march_weight(double need, const ImpostorSettings& s) {
  const double band = std::clamp(s.crossfade_band, 1e-3, 0.9);
  const double x = std::clamp((need - (1.0 - band)) / band, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

std::vector<size_t> choose_impostor_updates(const std::vector<double>& staleness, const ImpostorSettings& s) {
  std::vector<size_t> cut, stale;
  for (size_t i = 0; i < staleness.size(); ++i) {
    if (staleness[i] >= s.cut_staleness) cut.push_back(i);
    else if (staleness[i] >= 1.0) stale.push_back(i);
  }
  std::stable_sort(stale.begin(), stale.end(), [&](size_t a, size_t b) { return staleness[a] > staleness[b]; });
  const size_t budget = static_cast<size_t>(std::max(0, s.updates_per_frame));
  if (stale.size() > budget) stale.resize(budget);
  cut.insert(cut.end(), stale.begin(), stale.end());
  return cut;
}

}  // namespace atmo::clouds
