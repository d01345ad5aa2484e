// The Moon as a light through the ABI (AtmoLighting's moon_* fields): the
// issue's photometry check (a full Moon near the zenith gives 0.1–0.3 lx at
// the ground), agreement with the ephemeris core, darkness below the horizon,
// and a host compiled with the 392-byte layout left untouched past its end.
#include <cstring>

#include "core/astro/sky_bodies.h"
#include "plugin_gl_fixture.h"

using namespace plugin_gl;

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kFullMoonUtc = 1734253320.0;  // 2024-12-15T09:02Z

double luminance(const double rgb[3]) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

AtmoViewState view_at(double lat, double lon, double height_m) {
  AtmoViewState vs = atmo::support::example_view_state(kWidth, kHeight, 0, height_m);
  vs.eye_kind = ATMO_POSITION_GEODETIC;
  vs.eye_geodetic[0] = lat;
  vs.eye_geodetic[1] = lon;
  vs.eye_geodetic[2] = height_m;
  vs.world_frame = ATMO_WORLD_ENU;
  vs.world_origin_geodetic[0] = lat;
  vs.world_origin_geodetic[1] = lon;
  vs.world_origin_geodetic[2] = height_m;
  return vs;
}

// The longitude along 27.5° N where the full Moon culminates (it is then
// 0.1° from the zenith: its declination is +27.4°).
double culmination_longitude() {
  double best_lon = 0.0, best_z = -2.0;
  for (double lon = -180.0; lon < 180.0; lon += 0.5) {
    std::string error;
    auto b = atmo::core::compute_sky_bodies(kFullMoonUtc, 0.0, atmo::core::Geodetic{27.5, lon, 0.0}, &error);
    if (b && b->moon_enu.z > best_z) best_z = b->moon_enu.z, best_lon = lon;
  }
  return best_lon;
}

}  // namespace

TEST(Moonlight, FullMoonNearTheZenithGivesATenthToThreeTenthsOfALux) {
  Fixture f;
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = kFullMoonUtc;
  f.context->set_frame(frame);
  const double lon = culmination_longitude();
  for (double visibility : {40000.0, 15000.0}) {
    f.fresh_context();  // draws the new air at once
    auto atm = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
    atm.visibility_m = visibility;
    f.context->set_atmosphere(atm);
    f.context->set_frame(frame);
    f.view->set(view_at(27.5, lon, 0.0));
    AtmoLighting l = f.view->lighting();
    const double lux = luminance(l.moon_illuminance_lux);
    std::printf("[ moonlight ] full Moon at %.2f deg elevation (27.5 N, %.1f E), visibility %.0f km: %.3f lx at the "
                "ground, lit fraction %.4f, phase %.2f deg\n",
                l.moon_elevation_rad / kDeg, lon, visibility / 1000.0, lux, l.moon_illuminated_fraction,
                l.moon_phase_angle_rad / kDeg);
    EXPECT_GT(l.moon_elevation_rad, 85.0 * kDeg);
    EXPECT_GT(l.moon_illuminated_fraction, 0.99);
    EXPECT_GE(lux, 0.1);
    EXPECT_LE(lux, 0.3);
    // Night: the sun is far below, its light is zero.
    EXPECT_EQ(luminance(l.sun_illuminance_lux), 0.0);
  }
}

TEST(Moonlight, DirectionsAgreeWithTheEphemerisAndTheMoonSetsToDarkness) {
  Fixture f;
  // Innsbruck, 2024-12-15T03:00Z: the Moon 38° up in the west (docs/EPHEMERIS.md's example).
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = 1734231600.0;
  f.context->set_frame(frame);
  f.view->set(view_at(47.26, 11.35, 620.0));
  AtmoLighting l = f.view->lighting();
  std::string error;
  auto b = atmo::core::compute_sky_bodies(frame.utc_posix_s, 0.0, atmo::core::Geodetic{47.26, 11.35, 620.0}, &error);
  ASSERT_TRUE(b) << error;
  const glm::dvec3 enu(l.moon_direction_enu[0], l.moon_direction_enu[1], l.moon_direction_enu[2]);
  EXPECT_LT(std::acos(std::min(1.0, glm::dot(enu, b->moon_enu))), 1e-7);
  EXPECT_NEAR(l.moon_elevation_rad / kDeg, 38.26, 0.02);
  EXPECT_NEAR(l.moon_azimuth_rad / kDeg, 270.70, 0.02);
  EXPECT_NEAR(glm::length(glm::dvec3(l.moon_direction_ecef[0], l.moon_direction_ecef[1], l.moon_direction_ecef[2])),
              1.0, 1e-12);
  EXPECT_GT(luminance(l.moon_illuminance_lux), 0.05);

  // At its lower culmination that day the Moon is well below the horizon: no moonlight.
  double lowest_utc = frame.utc_posix_s, lowest_z = 2.0;
  for (double t = frame.utc_posix_s; t < frame.utc_posix_s + 86400.0; t += 900.0) {
    auto later = atmo::core::compute_sky_bodies(t, 0.0, atmo::core::Geodetic{47.26, 11.35, 620.0}, &error);
    ASSERT_TRUE(later) << error;
    if (later->moon_enu.z < lowest_z) lowest_z = later->moon_enu.z, lowest_utc = t;
  }
  frame.utc_posix_s = lowest_utc;
  f.context->set_frame(frame);
  l = f.view->lighting();
  EXPECT_LT(l.moon_elevation_rad, -5.0 * kDeg);
  EXPECT_EQ(luminance(l.moon_illuminance_lux), 0.0);
}

TEST(Moonlight, AHostWithTheOlderLayoutGetsNothingPastItsEnd) {
  Fixture f;
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = 1734231600.0;
  f.context->set_frame(frame);
  f.view->set(view_at(47.26, 11.35, 620.0));
  AtmoLighting l;
  std::memset(&l, 0xAB, sizeof l);
  l.header.type = ATMO_TYPE_LIGHTING;
  l.header.struct_size = 392;  // before the Moon's fields
  l.header.next = nullptr;
  ASSERT_EQ(f.plugin->api().get_lighting(f.view->handle(), &l), ATMO_SUCCESS);
  const unsigned char* bytes = reinterpret_cast<const unsigned char*>(&l);
  for (size_t i = 392; i < sizeof l; ++i) ASSERT_EQ(bytes[i], 0xAB) << "byte " << i << " written";
  EXPECT_GT(l.sun_illuminance_lux[1] + 1.0, 0.0);  // the fields it has were written (finite)
}
