#include "scene_settings.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "atmo_host_scene/terrain.h"

namespace atmo::sample {

// H. Hinnant's civil calendar algorithms (public domain).
int64_t days_from_civil(int year, int month, int day) {
  const int64_t y = static_cast<int64_t>(year) - (month <= 2 ? 1 : 0);
  const int64_t era = (y >= 0 ? y : y - 399) / 400;
  const int64_t yoe = y - era * 400;
  const int64_t doy = (153 * (month + (month > 2 ? -3 : 9)) + 2) / 5 + day - 1;
  const int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + doe - 719468;
}

void civil_from_days(int64_t days, int* year, int* month, int* day) {
  days += 719468;
  const int64_t era = (days >= 0 ? days : days - 146096) / 146097;
  const int64_t doe = days - era * 146097;
  const int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const int64_t mp = (5 * doy + 2) / 153;
  const int64_t d = doy - (153 * mp + 2) / 5 + 1;
  const int64_t m = mp < 10 ? mp + 3 : mp - 9;
  *year = static_cast<int>(yoe + era * 400 + (m <= 2 ? 1 : 0));
  *month = static_cast<int>(m);
  *day = static_cast<int>(d);
}

bool parse_utc(const std::string& text, double* posix_s) {
  if (text.empty()) return false;
  char* end = nullptr;
  const double number = std::strtod(text.c_str(), &end);
  if (end && *end == '\0' && text.find('-', 1) == std::string::npos) {
    if (!std::isfinite(number)) return false;
    *posix_s = number;
    return true;
  }
  int y = 0, mo = 0, d = 0, h = 0, mi = 0, consumed = 0;
  double s = 0.0;
  char sep = 0;
  if (std::sscanf(text.c_str(), "%d-%d-%d%c%d:%d%n", &y, &mo, &d, &sep, &h, &mi, &consumed) != 6) return false;
  if (sep != 'T' && sep != ' ') return false;
  const char* rest = text.c_str() + consumed;
  if (*rest == ':') {
    int more = 0;
    if (std::sscanf(rest, ":%lf%n", &s, &more) != 1) return false;
    rest += more;
  }
  if (*rest == 'Z') ++rest;
  if (*rest != '\0') return false;
  if (mo < 1 || mo > 12 || d < 1 || d > 31 || h < 0 || h > 23 || mi < 0 || mi > 59 || s < 0.0 || s >= 61.0) {
    return false;
  }
  *posix_s = static_cast<double>(days_from_civil(y, mo, d)) * 86400.0 + h * 3600.0 + mi * 60.0 + s;
  return true;
}

std::string format_utc(double posix_s) {
  const double days = std::floor(posix_s / 86400.0);
  int64_t second_of_day = static_cast<int64_t>(std::floor(posix_s - days * 86400.0));
  int y = 0, mo = 0, d = 0;
  civil_from_days(static_cast<int64_t>(days), &y, &mo, &d);
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%04d-%02d-%02dT%02d:%02d:%02dZ", y, mo, d,
                static_cast<int>(second_of_day / 3600), static_cast<int>(second_of_day / 60 % 60),
                static_cast<int>(second_of_day % 60));
  return buffer;
}

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
