#include "scene_settings.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "atmo_host_scene/terrain.h"
#include "core/astro/iso8601.h"

namespace atmo::sample {

bool parse_utc(const std::string& text, double* posix_s, std::string* error) {
  char* end = nullptr;
  const double number = std::strtod(text.c_str(), &end);
  if (!text.empty() && end && *end == '\0' && text.find('-', 1) == std::string::npos) {
    if (!std::isfinite(number)) {
      if (error) *error = "'" + text + "' is not a finite number of POSIX seconds";
      return false;
    }
    *posix_s = number;
    return true;
  }
  const auto t = core::astro::parse_iso8601_posix(text, error);
  if (t) *posix_s = *t;
  return t.has_value();
}

std::string format_utc(double posix_s) { return core::astro::format_iso8601_posix(posix_s); }

host_scene::CameraPose approach_path(double t) {
  const host_scene::TerrainOptions runway;  // heading 90: landing eastwards
  const double touchdown = -0.5 * runway.runway_length_m + 300.0;
  const double distance = 6000.0 + 300.0 + (1000.0 - 6000.0) * t;  // to the touchdown point
  const double glide = glm::radians(3.0);
  host_scene::CameraPose pose;
  const double h = glm::radians(runway.runway_heading_deg);
  pose.position_enu_m = glm::dvec3(std::sin(h) * (touchdown - distance), std::cos(h) * (touchdown - distance),
                                   std::tan(glide) * distance + 3.0);
  // Curvature: stay on the glide path above the dropped ground.
  pose.position_enu_m.z -= host_scene::curvature_drop_m(pose.position_enu_m.x, pose.position_enu_m.y);
  pose.heading_deg = runway.runway_heading_deg;
  pose.pitch_deg = -3.0;
  return pose;
}

}  // namespace atmo::sample
