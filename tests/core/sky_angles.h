// Angle constants and the angular separation the ephemeris tests print in
// arcseconds (ERFA's eraSepp: robust for tiny and near-antipodal angles).
#pragma once

#include <erfa.h>
#include <glm/glm.hpp>

namespace sky_angles {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kArcsec = kDeg / 3600.0;

inline double sep_arcsec(const glm::dvec3& a, const glm::dvec3& b) {
  double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z};
  return eraSepp(pa, pb) / kArcsec;
}

}  // namespace sky_angles
