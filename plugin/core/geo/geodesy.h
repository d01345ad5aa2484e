// geodesy.h — WGS84 conversions (GeographicLib) between geodetic latitude /
// longitude / height, ECEF, and the local east-north-up (ENU) frame.
// Degrees at this edge (latitude, longitude), metres, ECEF axes: X to 0°N 0°E,
// Z to the North Pole.
#pragma once

#include <glm/glm.hpp>

namespace atmo::core {

struct Geodetic {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double height_m = 0.0;
};

glm::dvec3 ecef_from_geodetic(const Geodetic& g);
Geodetic geodetic_from_ecef(const glm::dvec3& ecef_m);

// Columns are the east, north and up unit vectors in ECEF at (lat, lon).
glm::dmat3 ecef_from_enu(double latitude_deg, double longitude_deg);

// The local ENU frame at a geodetic origin as a transform: ENU metres -> ECEF metres.
glm::dmat4 ecef_from_enu_at(const Geodetic& origin);

// A unit direction's elevation above the horizontal plane, [-pi/2, pi/2], and its
// azimuth from north through east, [0, 2 pi), radians.
struct HorizontalAngles {
  double elevation_rad = 0.0;
  double azimuth_rad = 0.0;
};
HorizontalAngles horizontal_angles(const glm::dvec3& direction_enu);

// Radius of the sphere tangent to the ellipsoid at this latitude: the Gaussian
// mean radius of curvature sqrt(M N), metres (6 335 km at the equator to
// 6 400 km at the poles). The atmosphere is modelled on this sphere.
double local_earth_radius_m(double latitude_deg);

}  // namespace atmo::core
