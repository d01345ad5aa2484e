#include "core/astro/solar_system.h"

#include <erfa.h>
#include <erfam.h>
#include <libnova/lunar.h>
#include <libnova/jupiter.h>
#include <libnova/mars.h>
#include <libnova/mercury.h>
#include <libnova/saturn.h>
#include <libnova/venus.h>

#include <cmath>
#include <mutex>

namespace atmo::core::astro {

namespace {

constexpr double kJ2000 = 2451545.0;
// ELP 2000-82B truncation (radians in longitude/latitude, scaled to km in
// distance by libnova): 1e-8 keeps the error at the full theory's level
// (measured: 1.74" worst vs DE431 over 1900-2100, 1.70" untruncated) at ~20 %
// of the cost.
constexpr double kElpTruncation = 1.0e-8;

std::mutex& libnova_mutex() {
  static std::mutex m;
  return m;
}

// The frame bias and the J2000 mean obliquity (IAU 2006), computed once.
struct J2000Frame {
  double rb[3][3];   // ICRS -> J2000 mean equator and equinox
  double eps0 = 0.0; // mean obliquity of J2000
  J2000Frame() {
    double rp[3][3], rbp[3][3];
    eraBp06(kJ2000, 0.0, rb, rp, rbp);
    eps0 = eraObl06(kJ2000, 0.0);
  }
};
const J2000Frame& j2000() {
  static const J2000Frame f;
  return f;
}

// J2000 ecliptic rectangular -> ICRS.
glm::dvec3 icrs_from_j2000_ecliptic(double x, double y, double z) {
  const J2000Frame& f = j2000();
  const double c = std::cos(f.eps0), s = std::sin(f.eps0);
  double mean[3] = {x, c * y - s * z, s * y + c * z};
  double icrs[3];
  double rb[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rb[i][j] = f.rb[i][j];
  eraTrxp(rb, mean, icrs);
  return {icrs[0], icrs[1], icrs[2]};
}

glm::dvec3 v3(const double p[3]) { return {p[0], p[1], p[2]}; }

int plan94_index(Body b) {
  switch (b) {
    case Body::kMercury: return 1;
    case Body::kVenus: return 2;
    case Body::kMars: return 4;
    case Body::kJupiter: return 5;
    case Body::kSaturn: return 6;
    default: return 3;
  }
}

}  // namespace

const char* to_string(Body body) {
  switch (body) {
    case Body::kSun: return "Sun";
    case Body::kMoon: return "Moon";
    case Body::kMercury: return "Mercury";
    case Body::kVenus: return "Venus";
    case Body::kMars: return "Mars";
    case Body::kJupiter: return "Jupiter";
    case Body::kSaturn: return "Saturn";
  }
  return "?";
}

EarthSun earth_and_sun(JulianDate tt) {
  double pvh[2][3], pvb[2][3];
  EarthSun out;
  out.in_range = eraEpv00(tt.jd1, tt.jd2, pvh, pvb) == 0;
  out.earth_barycentric_au = v3(pvb[0]);
  out.earth_barycentric_velocity_au_d = v3(pvb[1]);
  out.earth_heliocentric_au = v3(pvh[0]);
  out.sun_barycentric_au = v3(pvb[0]) - v3(pvh[0]);
  out.sun_barycentric_velocity_au_d = v3(pvb[1]) - v3(pvh[1]);
  return out;
}

glm::dvec3 moon_geocentric_au(JulianDate tt) {
  ln_rect_posn m{};
  {
    std::lock_guard<std::mutex> lock(libnova_mutex());
    ln_get_lunar_geo_posn(tt.value(), &m, kElpTruncation);
  }
  const double km_to_au = 1000.0 / ERFA_DAU;
  return icrs_from_j2000_ecliptic(m.X * km_to_au, m.Y * km_to_au, m.Z * km_to_au);
}

glm::dvec3 moon_geocentric_velocity_au_d(JulianDate tt) {
  double pv[2][3];
  eraMoon98(tt.jd1, tt.jd2, pv);
  return v3(pv[1]);
}

glm::dvec3 moon_geocentric_moon98_au(JulianDate tt) {
  double pv[2][3];
  eraMoon98(tt.jd1, tt.jd2, pv);
  return v3(pv[0]);
}

glm::dvec3 planet_heliocentric_au(Body body, JulianDate tt) {
  ln_helio_posn h{};
  {
    std::lock_guard<std::mutex> lock(libnova_mutex());
    const double jd = tt.value();
    switch (body) {
      case Body::kMercury: ln_get_mercury_helio_coords(jd, &h); break;
      case Body::kVenus: ln_get_venus_helio_coords(jd, &h); break;
      case Body::kMars: ln_get_mars_helio_coords(jd, &h); break;
      case Body::kJupiter: ln_get_jupiter_helio_coords(jd, &h); break;
      case Body::kSaturn: ln_get_saturn_helio_coords(jd, &h); break;
      default: return glm::dvec3(0.0);
    }
  }
  const double l = h.L * ERFA_DD2R, b = h.B * ERFA_DD2R, r = h.R;
  return icrs_from_j2000_ecliptic(r * std::cos(b) * std::cos(l), r * std::cos(b) * std::sin(l), r * std::sin(b));
}

glm::dvec3 planet_heliocentric_plan94_au(Body body, JulianDate tt) {
  double pv[2][3];
  eraPlan94(tt.jd1, tt.jd2, plan94_index(body), pv);
  return v3(pv[0]);
}

}  // namespace atmo::core::astro
