#include "core/geo/geodesy.h"

#include <GeographicLib/Geocentric.hpp>

#include <algorithm>
#include <cmath>

namespace atmo::core {

glm::dvec3 ecef_from_geodetic(const Geodetic& g) {
  glm::dvec3 out;
  GeographicLib::Geocentric::WGS84().Forward(g.latitude_deg, g.longitude_deg, g.height_m, out.x, out.y,
                                             out.z);
  return out;
}

Geodetic geodetic_from_ecef(const glm::dvec3& p) {
  Geodetic g;
  GeographicLib::Geocentric::WGS84().Reverse(p.x, p.y, p.z, g.latitude_deg, g.longitude_deg, g.height_m);
  return g;
}

glm::dmat3 ecef_from_enu(double latitude_deg, double longitude_deg) {
  const double kDeg = M_PI / 180.0;
  double sl = std::sin(latitude_deg * kDeg), cl = std::cos(latitude_deg * kDeg);
  double so = std::sin(longitude_deg * kDeg), co = std::cos(longitude_deg * kDeg);
  glm::dvec3 east(-so, co, 0.0);
  glm::dvec3 north(-sl * co, -sl * so, cl);
  glm::dvec3 up(cl * co, cl * so, sl);
  return glm::dmat3(east, north, up);
}

double local_earth_radius_m(double latitude_deg) {
  const double a = GeographicLib::Constants::WGS84_a();
  const double f = GeographicLib::Constants::WGS84_f();
  const double e2 = f * (2.0 - f);
  double s = std::sin(latitude_deg * M_PI / 180.0);
  double w = 1.0 - e2 * s * s;
  double n = a / std::sqrt(w);               // prime vertical
  double m = a * (1.0 - e2) / (w * std::sqrt(w));  // meridian
  return std::sqrt(m * n);
}

glm::dmat4 ecef_from_enu_at(const Geodetic& origin) {
  glm::dmat4 m(ecef_from_enu(origin.latitude_deg, origin.longitude_deg));
  m[3] = glm::dvec4(ecef_from_geodetic(origin), 1.0);
  return m;
}

HorizontalAngles horizontal_angles(const glm::dvec3& d) {
  HorizontalAngles a;
  a.elevation_rad = std::asin(std::clamp(d.z, -1.0, 1.0));
  const double azimuth = std::atan2(d.x, d.y);
  a.azimuth_rad = azimuth < 0.0 ? azimuth + 2.0 * M_PI : azimuth;
  return a;
}

}  // namespace atmo::core
