// solar_position.h — a low-precision solar position (Astronomical Almanac
// formula, ~0.01° 1950–2050). The plugin draws with the ephemeris
// (core/astro/sky_bodies.h) alone; this formula is kept as an independent rough
// check for the tests. Time is POSIX UTC seconds; UT1 = UTC + dut1_s for the
// Earth's rotation.
#pragma once

#include <glm/glm.hpp>

namespace atmo::core {

struct SunPosition {
  glm::dvec3 direction_ecef;  // unit vector, geocentric (parallax of 8.8" ignored)
  double distance_au = 1.0;   // Earth–Sun distance, astronomical units
};

SunPosition solar_position(double utc_posix_s, double dut1_s);

// Julian date (UT) from POSIX seconds.
inline double julian_date_from_posix(double posix_s) { return posix_s / 86400.0 + 2440587.5; }

}  // namespace atmo::core
