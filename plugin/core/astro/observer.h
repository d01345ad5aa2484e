// observer.h — where the sky is seen from: a geodetic point on the WGS84
// ellipsoid (GeographicLib through core/geo/geodesy.h), the same ellipsoid ERFA
// uses for the observer in the astrometry context (eraGd2gc(ERFA_WGS84)), so
// an observer built from the frame state's ECEF eye is the eye.
#pragma once

#include <optional>
#include <string>

#include <glm/glm.hpp>

namespace atmo::core::astro {

// Heights accepted, above the WGS84 ellipsoid: the one range of the eye's
// height (the ABI checks AtmoViewState's eye against it). From 1000 m below
// it (the Dead Sea shore is at -430 m; the standard atmosphere's refraction
// conditions stay valid there) to 10 000 km, a view from orbit. The observer
// is at rest in the Earth-fixed frame (its velocity, for the diurnal
// aberration, is the Earth's rotation at its position).
constexpr double kMinObserverHeightM = -1000.0;
constexpr double kMaxObserverHeightM = 1.0e7;

struct Observer {
  double latitude_rad = 0.0;   // geodetic, north positive, [-pi/2, pi/2]
  double longitude_rad = 0.0;  // east positive, (-pi, pi]
  double height_m = 0.0;       // above the WGS84 ellipsoid
};

// Degrees in, validated: latitude in [-90, 90], longitude finite (wrapped to
// (-180, 180]), height in [kMinObserverHeightM, kMaxObserverHeightM]. nullopt
// + message otherwise.
std::optional<Observer> observer_from_geodetic(double latitude_deg, double longitude_deg, double height_m,
                                               std::string* error);

// From an ECEF position in metres (e.g. the frame state's eye).
std::optional<Observer> observer_from_ecef(const glm::dvec3& ecef_m, std::string* error);

// The observer's ECEF position and local frame (columns east, north, up).
glm::dvec3 observer_ecef(const Observer& o);
glm::dmat3 observer_ecef_from_enu(const Observer& o);

}  // namespace atmo::core::astro
