#include "core/astro/observer.h"

#include <cmath>
#include <cstdio>

#include "core/geo/geodesy.h"

namespace atmo::core::astro {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

bool fail(std::string* error, const char* what, double value, const char* range) {
  if (error) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s %g is not in %s", what, value, range);
    *error = buf;
  }
  return false;
}
}  // namespace

std::optional<Observer> observer_from_geodetic(double latitude_deg, double longitude_deg, double height_m,
                                               std::string* error) {
  if (!std::isfinite(latitude_deg) || latitude_deg < -90.0 || latitude_deg > 90.0) {
    fail(error, "latitude", latitude_deg, "[-90, 90] degrees");
    return std::nullopt;
  }
  if (!std::isfinite(longitude_deg)) {
    fail(error, "longitude", longitude_deg, "the finite numbers (degrees)");
    return std::nullopt;
  }
  if (!std::isfinite(height_m) || height_m < kMinObserverHeightM || height_m > kMaxObserverHeightM) {
    char range[64];
    std::snprintf(range, sizeof range, "[%g, %g] m", kMinObserverHeightM, kMaxObserverHeightM);
    fail(error, "height", height_m, range);
    return std::nullopt;
  }
  double lon = std::remainder(longitude_deg, 360.0);  // [-180, 180]
  if (lon <= -180.0) lon += 360.0;
  Observer o;
  o.latitude_rad = latitude_deg * kDeg;
  o.longitude_rad = lon * kDeg;
  o.height_m = height_m;
  return o;
}

std::optional<Observer> observer_from_ecef(const glm::dvec3& ecef_m, std::string* error) {
  if (!std::isfinite(ecef_m.x) || !std::isfinite(ecef_m.y) || !std::isfinite(ecef_m.z)) {
    if (error) *error = "ECEF position is not finite";
    return std::nullopt;
  }
  const Geodetic g = geodetic_from_ecef(ecef_m);
  return observer_from_geodetic(g.latitude_deg, g.longitude_deg, g.height_m, error);
}

glm::dvec3 observer_ecef(const Observer& o) {
  return ecef_from_geodetic(Geodetic{o.latitude_rad / kDeg, o.longitude_rad / kDeg, o.height_m});
}

glm::dmat3 observer_ecef_from_enu(const Observer& o) {
  return ecef_from_enu(o.latitude_rad / kDeg, o.longitude_rad / kDeg);
}

}  // namespace atmo::core::astro
