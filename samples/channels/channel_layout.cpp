#include "channel_layout.h"

#include <cmath>

namespace atmo::channels {

namespace {
constexpr double kPi = 3.14159265358979323846;
double rad(double deg) { return deg * kPi / 180.0; }
}  // namespace

std::string layout_error(const Layout& l) {
  if (l.count < 1) return "the channel count is " + std::to_string(l.count) + ", at least 1 is needed";
  if (!(l.horizontal_fov_deg > 0.0 && l.horizontal_fov_deg < 180.0))
    return "horizontal_fov_deg " + std::to_string(l.horizontal_fov_deg) + " is not in (0, 180)";
  if (!(l.vertical_fov_deg > 0.0 && l.vertical_fov_deg < 180.0))
    return "vertical_fov_deg " + std::to_string(l.vertical_fov_deg) + " is not in (0, 180)";
  if (!(l.overlap_deg >= 0.0 && l.overlap_deg < l.horizontal_fov_deg))
    return "overlap_deg " + std::to_string(l.overlap_deg) + " is not in [0, horizontal_fov_deg)";
  if (l.width < 1 || l.height < 1) return "the channel size is not positive";
  const double span = l.count * (l.horizontal_fov_deg - l.overlap_deg);
  if (span > 360.0 + 1e-9)
    return std::to_string(l.count) + " channels of " + std::to_string(l.horizontal_fov_deg) + " deg less " +
           std::to_string(l.overlap_deg) + " deg of overlap wrap " + std::to_string(span) +
           " deg, past a full turn (360)";
  if (l.count > 1 && l.overlap_deg > 0.0 && band_columns(l) < 1) return "the overlap band is narrower than a column";
  if (band_columns(l) > l.width / 2) return "the overlap band is wider than half a channel";
  return "";
}

double channel_yaw_deg(const Layout& l, int channel) {
  return (channel - 0.5 * (l.count - 1)) * (l.horizontal_fov_deg - l.overlap_deg);
}

int band_columns(const Layout& l) {
  if (l.overlap_deg <= 0.0) return 0;
  const double h = rad(l.horizontal_fov_deg) * 0.5;
  const double inner = std::tan(h - rad(l.overlap_deg)) / std::tan(h);  // where the band starts, in [-1, 1]
  // Columns from the edge whose centres lie in the band: x + 0.5 <= W / 2 * (1 - inner).
  return static_cast<int>(std::floor(0.5 * l.width * (1.0 - inner) + 0.5));
}

glm::dmat3 enu_from_channel_camera(double heading_deg, double pitch_deg, double channel_yaw) {
  const double h = rad(heading_deg), p = rad(pitch_deg), a = rad(channel_yaw);
  // As tools/host_scene camera.cpp: a level camera looking north (right = east, up = up, back = south), pitched
  // about east, turned clockwise by the heading.
  const glm::dmat3 level(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, -1, 0));
  const double ch = std::cos(h), sh = std::sin(h);
  const glm::dmat3 yaw(glm::dvec3(ch, -sh, 0), glm::dvec3(sh, ch, 0), glm::dvec3(0, 0, 1));
  const double cp = std::cos(p), sp = std::sin(p);
  const glm::dmat3 pitch(glm::dvec3(1, 0, 0), glm::dvec3(0, cp, sp), glm::dvec3(0, -sp, cp));
  // The channel turned right by `a` about the eye's up (camera y): right (cos a, 0, sin a), up, back (-sin a, 0, cos a).
  const double ca = std::cos(a), sa = std::sin(a);
  const glm::dmat3 turn(glm::dvec3(ca, 0, sa), glm::dvec3(0, 1, 0), glm::dvec3(-sa, 0, ca));
  return yaw * pitch * level * turn;
}

glm::dmat4 view_from_enu(const glm::dmat3& enu_from_camera, const glm::dvec3& eye_enu_m) {
  const glm::dmat3 camera_from_enu = glm::transpose(enu_from_camera);
  glm::dmat4 m(camera_from_enu);
  m[3] = glm::dvec4(-(camera_from_enu * eye_enu_m), 1.0);
  return m;
}

glm::dmat4 channel_projection(const Layout& l) {
  glm::dmat4 m(0.0);
  m[0][0] = 1.0 / std::tan(0.5 * rad(l.horizontal_fov_deg));
  m[1][1] = 1.0 / std::tan(0.5 * rad(l.vertical_fov_deg));
  m[2][3] = -1.0;
  m[2][2] = -(l.far_m + l.near_m) / (l.far_m - l.near_m);
  m[3][2] = -2.0 * l.far_m * l.near_m / (l.far_m - l.near_m);
  return m;
}

}  // namespace atmo::channels
