#include <gtest/gtest.h>

#include "core/geo/geodesy.h"

using namespace atmo::core;

TEST(Geodesy, KnownPoints) {
  glm::dvec3 equator = ecef_from_geodetic({0.0, 0.0, 0.0});
  EXPECT_NEAR(equator.x, 6378137.0, 1e-6);
  EXPECT_NEAR(equator.y, 0.0, 1e-6);
  glm::dvec3 pole = ecef_from_geodetic({90.0, 0.0, 0.0});
  EXPECT_NEAR(pole.z, 6356752.314245, 1e-5);
}

TEST(Geodesy, RoundTripIncludingPolesDateLineAndAltitudes) {
  for (double lat : {-90.0, -45.5, 0.0, 33.3, 89.9999, 90.0})
    for (double lon : {-180.0, -179.9999, 0.0, 11.35, 179.9999})
      for (double h : {-400.0, 0.0, 12000.0, 100000.0}) {
        Geodetic g = geodetic_from_ecef(ecef_from_geodetic({lat, lon, h}));
        EXPECT_NEAR(g.latitude_deg, lat, 1e-9);
        EXPECT_NEAR(g.height_m, h, 1e-6);
        if (std::abs(lat) < 90.0) {
          EXPECT_NEAR(std::remainder(g.longitude_deg - lon, 360.0), 0.0, 1e-9);
        }
      }
}

TEST(Geodesy, EnuBasisIsOrthonormalAndUpIsTheEllipsoidNormal) {
  for (double lat : {-60.0, 0.0, 47.26, 89.0}) {
    glm::dmat3 m = ecef_from_enu(lat, 11.35);
    glm::dmat3 should_be_identity = glm::transpose(m) * m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(should_be_identity[i][j], i == j ? 1.0 : 0.0, 1e-12);
    // Up: the direction in which geodetic height grows.
    glm::dvec3 a = ecef_from_geodetic({lat, 11.35, 0.0}), b = ecef_from_geodetic({lat, 11.35, 1.0});
    glm::dvec3 up = glm::normalize(b - a);
    EXPECT_NEAR(glm::dot(up, m[2]), 1.0, 1e-12);
  }
}

TEST(Geodesy, LocalRadiusBetweenEquatorAndPoleValues) {
  EXPECT_NEAR(local_earth_radius_m(0.0), 6356752.3, 1.0);  // sqrt(M N) = b at the equator
  EXPECT_NEAR(local_earth_radius_m(90.0), 6399594.0, 1.0);  // a^2 / b at the poles
  EXPECT_GT(local_earth_radius_m(45.0), local_earth_radius_m(0.0));
}
