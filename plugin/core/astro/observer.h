// observer.h — where the sky is seen from: a geodetic point on the WGS84
// ellipsoid (GeographicLib through core/geo/geodesy.h), the same ellipsoid ERFA
// uses for the observer in the astrometry context (eraGd2gc(ERFA_WGS84)), so
// an observer built from the frame state's ECEF eye is the eye.
#pragma once

#include <optional>
#include <string>

#include <glm/glm.hpp>

namespace atmo::core::astro {

// Heights accepted: the Dead Sea shore (-430 m) to well above the atmosphere.
constexpr double kMinObserverHeightM = -1000.0;
constexpr double kMaxObserverHeightM = 1.0e6;

struct Observer {
  double latitude_rad = 0.0;   // geodetic, north positive, [-pi/2, pi/2]
  double longitude_rad = 0.0;  // east positive, (-pi, pi]
  double height_m = 0.0;       // above the WGS84 ellipsoid
};

// Degrees in, validated: latitude in [-90, 90], longitude finite (wrapped to
// (-180, 180]), height in [-1000 m, 1000 km]. nullopt + message otherwise.
std::optional<Observer> observer_from_geodetic(double latitude_deg, double longitude_deg, double height_m,
                                               std::string* error);

// From an ECEF position in metres (e.g. the frame state's eye).
std::optional<Observer> observer_from_ecef(const glm::dvec3& ecef_m, std::string* error);

// The observer's ECEF position and local frame (columns east, north, up).
glm::dvec3 observer_ecef(const Observer& o);
glm::dmat3 observer_ecef_from_enu(const Observer& o);

}  // namespace atmo::core::astro
