// atmo_geodetic.h (the host SDK's WGS84 helper) against GeographicLib's Geocentric and LocalCartesian,
// which the plugin itself uses (core/geo/geodesy): the frame a host builds with the helper is the
// plugin's ATMO_WORLD_ENU frame. Errors are printed; the bounds are the header's stated accuracy.
#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "atmo/atmo_geodetic.h"

namespace {

double distance(const double a[3], const double b[3]) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// Latitudes including the poles and the equator, heights from 10 km below the ellipsoid to 100 000 km.
struct Sample {
  double g[3];
};
std::vector<Sample> samples() {
  std::vector<Sample> out;
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> lat(-90.0, 90.0), lon(-180.0, 180.0), logh(0.0, 8.0);
  for (double fixed_lat : {-90.0, -89.9999999, 0.0, 1e-9, 45.0, 89.9999999, 90.0})
    for (double h : {-1e4, 0.0, 1e3, 4e5, 3.6e7}) out.push_back({{fixed_lat, 10.0, h}});
  for (int i = 0; i < 20000; ++i) {
    double h = std::pow(10.0, logh(rng)) - 1e4;  // -1e4 .. 1e8 m
    out.push_back({{lat(rng), lon(rng), h}});
  }
  return out;
}

}  // namespace

TEST(Geodetic, EcefFromGeodeticMatchesGeographicLib) {
  const auto& earth = GeographicLib::Geocentric::WGS84();
  double worst = 0.0;
  for (const Sample& s : samples()) {
    double mine[3], ref[3];
    atmo_ecef_from_geodetic(s.g, mine);
    earth.Forward(s.g[0], s.g[1], s.g[2], ref[0], ref[1], ref[2]);
    worst = std::max(worst, distance(mine, ref));
  }
  std::printf("ecef_from_geodetic: worst %.3g m over %zu points\n", worst, samples().size());
  EXPECT_LT(worst, 1e-6);  // ~1e-8 m at 1e8 m: round-off
}

TEST(Geodetic, GeodeticFromEcefRoundTripsAndMatchesGeographicLib) {
  const auto& earth = GeographicLib::Geocentric::WGS84();
  double worst_position = 0.0, worst_height = 0.0;
  for (const Sample& s : samples()) {
    double ecef[3], back[3], back_ecef[3];
    earth.Forward(s.g[0], s.g[1], s.g[2], ecef[0], ecef[1], ecef[2]);
    atmo_geodetic_from_ecef(ecef, back);
    ASSERT_TRUE(std::isfinite(back[0]) && std::isfinite(back[1]) && std::isfinite(back[2]));
    earth.Forward(back[0], back[1], back[2], back_ecef[0], back_ecef[1], back_ecef[2]);
    double ref_lat, ref_lon, ref_h;
    earth.Reverse(ecef[0], ecef[1], ecef[2], ref_lat, ref_lon, ref_h);
    worst_position = std::max(worst_position, distance(ecef, back_ecef));
    worst_height = std::max(worst_height, std::abs(back[2] - ref_h));
  }
  std::printf("geodetic_from_ecef: worst position %.3g m, worst height vs GeographicLib %.3g m\n", worst_position,
              worst_height);
  EXPECT_LT(worst_position, 1e-6);
  EXPECT_LT(worst_height, 1e-6);
}

TEST(Geodetic, TheEarthsCentreAndThePolesAreFinite) {
  const double centre[3] = {0.0, 0.0, 0.0}, north[3] = {0.0, 0.0, 6356752.314245}, south[3] = {0.0, 0.0, -7e6};
  double g[3];
  atmo_geodetic_from_ecef(centre, g);
  EXPECT_EQ(g[0], 0.0);
  EXPECT_NEAR(g[2], -ATMO_WGS84_A_M, 1e-6);
  atmo_geodetic_from_ecef(north, g);
  EXPECT_EQ(g[0], 90.0);
  EXPECT_NEAR(g[2], 0.0, 1e-6);
  atmo_geodetic_from_ecef(south, g);
  EXPECT_EQ(g[0], -90.0);
  EXPECT_NEAR(g[2], 7e6 - 6356752.314245, 1e-6);
}

// The ENU frame of ATMO_WORLD_ENU is GeographicLib's LocalCartesian at the origin's latitude, longitude and
// height (the tangent plane at the origin's height), as core/geo/geodesy's ecef_from_enu_at builds it.
TEST(Geodetic, EnuFrameIsLocalCartesianAtTheOriginsHeight) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> lat(-89.0, 89.0), lon(-180.0, 180.0), h(-400.0, 9000.0), d(-2e5, 2e5);
  double worst = 0.0, worst_round_trip = 0.0;
  for (int i = 0; i < 5000; ++i) {
    const double origin[3] = {lat(rng), lon(rng), h(rng)};
    const double enu[3] = {d(rng), d(rng), d(rng) * 0.05};
    GeographicLib::LocalCartesian frame(origin[0], origin[1], origin[2]);
    double ref_g[3], mine_g[3], ref_ecef[3], mine_ecef[3], back[3];
    frame.Reverse(enu[0], enu[1], enu[2], ref_g[0], ref_g[1], ref_g[2]);
    GeographicLib::Geocentric::WGS84().Forward(ref_g[0], ref_g[1], ref_g[2], ref_ecef[0], ref_ecef[1], ref_ecef[2]);
    atmo_ecef_from_enu(origin, enu, mine_ecef);
    atmo_geodetic_from_enu(origin, enu, mine_g);
    worst = std::max(worst, distance(mine_ecef, ref_ecef));
    worst = std::max(worst, std::abs(mine_g[2] - ref_g[2]));
    atmo_enu_from_ecef(origin, mine_ecef, back);
    worst_round_trip = std::max(worst_round_trip, distance(back, enu));
  }
  std::printf("ENU: worst against LocalCartesian %.3g m, round trip %.3g m (points within 200 km)\n", worst,
              worst_round_trip);
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(worst_round_trip, 1e-6);
}

// The header's example: 10 km east of the origin at z = 0 is above the ellipsoid (the frame is a plane).
TEST(Geodetic, AnEnuPlanePointTenKilometresAwayIsAboveTheEllipsoid) {
  const double origin[3] = {45.0, 7.0, 0.0}, enu[3] = {10000.0, 0.0, 0.0};
  double g[3];
  atmo_geodetic_from_enu(origin, enu, g);
  std::printf("10 km east at z = 0: height %.3f m\n", g[2]);
  EXPECT_NEAR(g[2], 7.8, 0.1);
}
