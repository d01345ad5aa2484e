#include "core/astro/solar_position.h"

#include <cmath>

namespace atmo::core {

namespace {
constexpr double kDeg = M_PI / 180.0;
// TT - UTC since 2017-01-01 (32.184 s + 37 leap seconds); the error from
// using it at other dates is < 1.5 min of time, i.e. < 0.001° of solar motion.
constexpr double kTtMinusUtcS = 69.184;

double wrap_degrees(double x) {
  x = std::fmod(x, 360.0);
  return x < 0 ? x + 360.0 : x;
}
}  // namespace

SunPosition solar_position(double utc_posix_s, double dut1_s) {
  const double n = julian_date_from_posix(utc_posix_s + kTtMinusUtcS) - 2451545.0;  // days from J2000 (TT)
  const double mean_longitude = wrap_degrees(280.460 + 0.9856474 * n);
  const double mean_anomaly = wrap_degrees(357.528 + 0.9856003 * n) * kDeg;
  const double ecliptic_longitude =
      (mean_longitude + 1.915 * std::sin(mean_anomaly) + 0.020 * std::sin(2.0 * mean_anomaly)) * kDeg;
  const double obliquity = (23.439 - 0.0000004 * n) * kDeg;

  // Equatorial (true of date) unit vector.
  const double x = std::cos(ecliptic_longitude);
  const double y = std::cos(obliquity) * std::sin(ecliptic_longitude);
  const double z = std::sin(obliquity) * std::sin(ecliptic_longitude);

  // Greenwich mean sidereal time from UT1 (IAU 1982, linear part).
  const double d_ut1 = julian_date_from_posix(utc_posix_s + dut1_s) - 2451545.0;
  const double gmst = wrap_degrees(280.46061837 + 360.98564736629 * d_ut1) * kDeg;

  SunPosition out;
  out.direction_ecef = glm::normalize(glm::dvec3(std::cos(gmst) * x + std::sin(gmst) * y,
                                                 -std::sin(gmst) * x + std::cos(gmst) * y, z));
  out.distance_au = 1.00014 - 0.01671 * std::cos(mean_anomaly) - 0.00014 * std::cos(2.0 * mean_anomaly);
  return out;
}

}  // namespace atmo::core
