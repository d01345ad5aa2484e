// The Sun and the Moon as the passes and get_lighting use them
// (core/astro/sky_bodies.h): against the independent low-precision solar formula,
// the cache against fresh results (time, position, height: refraction depends
// on the height through the horizon's dip), and the moonlight's photometry.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/geo/eye_frame.h"
#include "core/geo/geodesy.h"
#include "core/astro/sky_bodies.h"
#include "core/astro/solar_position.h"

using namespace atmo;

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kArcsec = kDeg / 3600.0;

double angle_rad(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

core::SkyBodies bodies_at(double utc, const core::Geodetic& g) {
  std::string error;
  auto b = core::compute_sky_bodies(utc, 0.0, g, &error);
  EXPECT_TRUE(b.has_value()) << error;
  return b.value_or(core::SkyBodies{});
}

}  // namespace

// The low-precision Astronomical Almanac formula (~0.01°, 1950–2050) is an
// independent check of the whole chain (time scales, frames, ENU).
TEST(SkyBodies, SunAgreesWithTheLowPrecisionFormula) {
  double worst = 0.0;
  for (int year = 1960; year <= 2040; year += 4) {
    for (double lat : {-60.0, 0.0, 47.26, 78.0}) {
      const double utc = (year - 1970) * 365.2425 * 86400.0 + 0.37 * 86400.0 * (year % 7);
      const core::Geodetic g{lat, 11.35, 0.0};
      core::SkyBodies b = bodies_at(utc, g);
      const glm::dvec3 sun_ecef = core::solar_position(utc, 0.0).direction_ecef;
      const glm::dvec3 low = glm::transpose(core::ecef_from_enu(lat, 11.35)) * glm::normalize(sun_ecef);
      worst = std::max(worst, angle_rad(b.sun_enu_unrefracted, low));
    }
  }
  std::printf("[ bodies ] Sun vs the low-precision formula, 1960-2040: worst %.4f deg\n", worst / kDeg);
  EXPECT_LT(worst, 0.02 * kDeg);
}

TEST(SkyBodies, CacheStaysWithinOneAndAHalfArcseconds) {
  const core::Geodetic start{47.26, 11.35, 0.0};
  const double utc0 = 1734231600.0;  // 2024-12-15T03:00Z, Moon up
  double worst_sun = 0.0, worst_moon = 0.0;
  for (double lift_m : {0.0, 1.0, 10.0, 50.0, 99.0}) {
    for (double dt : {0.0, 0.03, 0.099, -0.099}) {
      core::SkyBodiesCache cache;
      std::string error;
      ASSERT_TRUE(cache.get(utc0, 0.0, start, core::ecef_from_geodetic(start), &error)) << error;
      const core::Geodetic moved{start.latitude_deg, start.longitude_deg, start.height_m + lift_m};
      auto cached = cache.get(utc0 + dt, 0.0, moved, core::ecef_from_geodetic(moved), &error);
      ASSERT_TRUE(cached) << error;
      EXPECT_EQ(cache.computations(), 1u) << "within 0.1 s and 100 m the cache must answer";
      core::SkyBodies fresh = bodies_at(utc0 + dt, moved);
      worst_sun = std::max(worst_sun, angle_rad(cached->sun_enu, fresh.sun_enu));
      worst_moon = std::max(worst_moon, angle_rad(cached->moon_enu, fresh.moon_enu));
    }
  }
  std::printf("[ bodies ] cache vs fresh (<= 0.1 s, <= 100 m up): Sun %.2f\", Moon %.2f\"\n", worst_sun / kArcsec,
              worst_moon / kArcsec);
  EXPECT_LT(worst_sun, 1.5 * kArcsec);
  EXPECT_LT(worst_moon, 1.5 * kArcsec);
}

// Refraction near the horizon depends on the height (the dip): a sun put at
// -1° from the ground is lifted differently from 1 m and from 90 m, and the
// cache must follow (it once kept the refracted value and was 0.016° off).
TEST(SkyBodies, CachedRefractionFollowsTheEyeHeight) {
  const core::Geodetic ground{47.26, 11.35, 0.0};
  core::SkyBodiesCache cache;
  std::string error;
  // 2024-06-21 19:30Z: the sun about 2.9° below the geometric horizon at Innsbruck.
  const double utc = 1718998200.0;
  ASSERT_TRUE(cache.get(utc, 0.0, ground, core::ecef_from_geodetic(ground), &error));
  for (double h : {1.0, 30.0, 90.0}) {
    const core::Geodetic up{ground.latitude_deg, ground.longitude_deg, h};
    auto cached = cache.get(utc, 0.0, up, core::ecef_from_geodetic(up), &error);
    ASSERT_TRUE(cached);
    core::SkyBodies fresh = bodies_at(utc, up);
    EXPECT_LT(angle_rad(cached->sun_enu, fresh.sun_enu), 0.5 * kArcsec) << "height " << h;
  }
}

// Jensen's check, through the light the host gets: the full Moon's
// illuminance outside the air is about 0.3 lx at mean distance (here at the
// distance of the day, without the atmosphere's transmittance, which the ABI
// applies: tests/plugin_gl/moonlight_test.cpp).
TEST(SkyBodies, FullMoonGivesAFewTenthsOfALux) {
  const core::Geodetic g{27.5, -100.0, 0.0};
  core::SkyBodies b = bodies_at(1734253320.0, g);  // 2024-12-15T09:02Z, full Moon
  const double lux = 0.2126 * b.moon_illuminance_rgb_lux.r + 0.7152 * b.moon_illuminance_rgb_lux.g +
                     0.0722 * b.moon_illuminance_rgb_lux.b;
  std::printf("[ bodies ] full Moon 2024-12-15: phase %.2f deg, lit %.4f, %.3f lx outside the air\n",
              b.moon_phase_angle_rad / kDeg, b.moon_illuminated_fraction, lux);
  EXPECT_LT(b.moon_phase_angle_rad, 5.0 * kDeg);
  EXPECT_GT(lux, 0.2);
  EXPECT_LT(lux, 0.4);
}

TEST(SkyBodies, BadInputIsRefused) {
  std::string error;
  EXPECT_FALSE(core::compute_sky_bodies(NAN, 0.0, core::Geodetic{0.0, 0.0, 0.0}, &error));
  EXPECT_NE(error.find("finite"), std::string::npos) << error;
  error.clear();
  EXPECT_FALSE(core::compute_sky_bodies(0.0, 5.0, core::Geodetic{0.0, 0.0, 0.0}, &error));
  EXPECT_FALSE(error.empty());
  error.clear();
  EXPECT_FALSE(core::compute_sky_bodies(0.0, 0.0, core::Geodetic{95.0, 0.0, 0.0}, &error));
  EXPECT_FALSE(error.empty());
}
