#include "core/astro/photometry.h"

#include <algorithm>
#include <cmath>

namespace atmo::core::astro {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kMoonMeanDistanceAu = 384400.0e3 / 149597870.7e3;

double wrap_2pi(double a) {
  a = std::fmod(a, 2.0 * kPi);
  return a < 0.0 ? a + 2.0 * kPi : a;
}
}  // namespace

double body_radius_m(Body body) {
  switch (body) {
    case Body::kSun: return 695700.0e3;
    case Body::kMoon: return 1737.4e3;
    case Body::kMercury: return 2440.53e3;
    case Body::kVenus: return 6051.8e3;
    case Body::kMars: return 3396.19e3;
    case Body::kJupiter: return 71492.0e3;
    case Body::kSaturn: return 60268.0e3;
  }
  return 0.0;
}

double illuminated_fraction(double phase_angle_rad) { return 0.5 * (1.0 + std::cos(phase_angle_rad)); }

double apparent_magnitude(Body body, double r, double delta, double phase_angle_rad, double ring_tilt_rad) {
  r = std::max(r, 1e-9);
  delta = std::max(delta, 1e-12);
  const double a = std::clamp(phase_angle_rad / kDeg, 0.0, 180.0);  // degrees
  const double distance = 5.0 * std::log10(r * delta);
  switch (body) {
    case Body::kSun:
      return -26.76 + 5.0 * std::log10(delta);
    case Body::kMoon: {
      // Krisciunas & Schaefer to 150°; beyond, a thin-crescent tail with the
      // flux falling as (180° - a)^3, joined continuously.
      auto phase_law = [](double x) { return -12.73 + 0.026 * x + 4.0e-9 * x * x * x * x; };
      constexpr double kJoinDeg = 150.0;
      const double v = a <= kJoinDeg ? phase_law(a)
                                     : phase_law(kJoinDeg) - 7.5 * std::log10(std::max(180.0 - a, 1e-3) /
                                                                               (180.0 - kJoinDeg));
      return v + 5.0 * std::log10(r * delta / kMoonMeanDistanceAu);
    }
    case Body::kMercury:
      return -0.613 + distance +
             a * (6.3280e-02 + a * (-1.6336e-03 + a * (3.3644e-05 + a * (-3.4265e-07 + a * (1.6893e-09 -
                                                                                          a * 3.0334e-12)))));
    case Body::kVenus:
      if (a < 163.7)
        return -4.384 + distance + a * (-1.044e-03 + a * (3.687e-04 + a * (-2.814e-06 + a * 8.938e-09)));
      return 236.05828 + distance + a * (-2.81914 + a * 8.39034e-03);
    case Body::kMars:
      if (a <= 50.0) return -1.601 + distance + a * (2.267e-02 - a * 1.302e-04);
      return -0.367 + distance + a * (-0.02573 + a * 3.445e-04);
    case Body::kJupiter:
      if (a <= 12.0) return -9.395 + distance + a * (-3.7e-04 + a * 6.16e-04);
      {
        const double x = a / 180.0;
        const double f = 1.0 + x * (-1.507 + x * (-0.363 + x * (-0.062 + x * (2.809 - x * 1.876))));
        return -9.428 + distance - 2.5 * std::log10(std::max(f, 1e-6));
      }
    case Body::kSaturn: {
      // Globe and rings, geocentric phase angles (<= 6.5°) and ring tilts (<= 27°).
      const double sb = std::fabs(std::sin(ring_tilt_rad));
      return -8.914 + distance - 1.825 * sb + 0.026 * a - 0.378 * sb * std::exp(-2.25 * a);
    }
  }
  return 0.0;
}

double bright_limb_position_angle(double ra0, double dec0, double ra, double dec) {
  const double y = std::cos(dec0) * std::sin(ra0 - ra);
  const double x = std::sin(dec0) * std::cos(dec) - std::cos(dec0) * std::sin(dec) * std::cos(ra0 - ra);
  return wrap_2pi(std::atan2(y, x));
}

double parallactic_angle(double h, double dec, double lat) {
  const double y = std::cos(lat) * std::sin(h);
  const double x = std::sin(lat) * std::cos(dec) - std::cos(lat) * std::sin(dec) * std::cos(h);
  return (x == 0.0 && y == 0.0) ? 0.0 : std::atan2(y, x);
}

glm::dvec3 saturn_pole_icrs(JulianDate tt) {
  const double t = ((tt.jd1 - 2451545.0) + tt.jd2) / 36525.0;
  const double ra = (40.589 - 0.036 * t) * kDeg;
  const double dec = (83.537 - 0.004 * t) * kDeg;
  return {std::cos(dec) * std::cos(ra), std::cos(dec) * std::sin(ra), std::sin(dec)};
}

}  // namespace atmo::core::astro
