// Sky irradiance from 9 SH coefficients against brute-force quadrature of the
// same diffuse sky radiance (cosine-weighted, 8192 directions), for surfaces
// facing up, sideways, down and in between, at noon, low sun, twilight and
// from 10 km.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/sky/sky_lighting.h"

using namespace atmo;

namespace {

core::Scene scene_for(double sun_elevation_deg, double altitude_m) {
  core::Scene s;
  s.sphere_radius_m = 6370000.0;
  s.atmosphere = core::make_atmosphere_parameters(core::AtmosphereSettings{}, s.sphere_radius_m, 1.0);
  double e = glm::radians(sun_elevation_deg);
  s.sun_direction_enu = glm::dvec3(0.0, std::cos(e), std::sin(e));  // sun in the north
  s.eye_altitude_m = altitude_m;
  return s;
}

glm::dvec3 brute_force_irradiance(const core::Scene& s, const twin::Lut2D& t, const twin::Lut2D& ms,
                                  const glm::dvec3& normal) {
  const int bands = 64, azimuths = 128;
  const double solid_angle = 4.0 * M_PI / (bands * azimuths);
  glm::dvec3 e(0.0);
  for (int b = 0; b < bands; ++b) {
    double z = 1.0 - 2.0 * (b + 0.5) / bands, ring = std::sqrt(1.0 - z * z);
    for (int a = 0; a < azimuths; ++a) {
      double phi = 2.0 * M_PI * (a + 0.5) / azimuths;
      glm::dvec3 w(ring * std::cos(phi), ring * std::sin(phi), z);
      double c = glm::dot(w, normal);
      if (c <= 0.0) continue;
      auto r = twin::sky_radiance_parts(s.atmosphere, t, glm::vec2(t.width, t.height), ms, glm::vec2(ms.width, ms.height),
                                        float(s.eye_altitude_m), glm::vec3(w), glm::vec3(s.sun_direction_enu), 16);
      e += glm::dvec3(r.diffuse) * (c * solid_angle);
    }
  }
  return e;
}

double luminance(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

}  // namespace

TEST(SkyLighting, Sh9IrradianceMatchesBruteForce) {
  // max_sh9_error: docs/SKY.md's measured figure per case plus ~0.2 points.
  struct Case {
    const char* name;
    double sun_deg, altitude_m, max_sh9_error;
  } cases[] = {{"noon", 60.0, 300.0, 0.018},
               {"sun at 5 deg", 5.0, 300.0, 0.043},
               {"sun at -4 deg", -4.0, 300.0, 0.051},
               {"10 km", 30.0, 10000.0, 0.060}};
  // Horizontal illuminance vs the brute force: docs/SKY.md's 0.3-1.05 % plus a margin.
  constexpr double kMaxHorizontalError = 0.012;
  const glm::dvec3 normals[] = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}, {0, -1, 0}, {0, 0, -1}, glm::normalize(glm::dvec3(0, 1, 1))};
  for (const Case& c : cases) {
    core::Scene s = scene_for(c.sun_deg, c.altitude_m);
    auto t = core::compute_transmittance_table(s.atmosphere, 256, 64);
    auto ms = core::compute_multiple_scattering_table(s.atmosphere, t);
    core::SkyLighting sky = core::compute_sky_lighting(s, t, ms);
    double up = luminance(brute_force_irradiance(s, t, ms, glm::dvec3(0, 0, 1)));
    double brightest = 0.0, worst_abs = 0.0;
    for (const glm::dvec3& n : normals) {
      double ref = luminance(brute_force_irradiance(s, t, ms, n));
      double sh = luminance(core::sh9_irradiance(sky.irradiance_sh9, n));
      brightest = std::max(brightest, ref);
      worst_abs = std::max(worst_abs, std::abs(sh - ref));
    }
    // Ramamoorthi & Hanrahan's measure: error relative to the largest irradiance (SH9 smooths the
    // horizon's step, so a dim face carries an absolute error); their worst case is 9 %.
    double worst = worst_abs / brightest;
    double horizontal = luminance(sky.horizontal_illuminance_lux);
    std::printf("[ sky lighting ] %-14s E(up) %9.4g lux vs brute force %9.4g (%+.2f %%); SH9 worst error over 6 normals "
                "%.2f %% of the largest irradiance\n",
                c.name, horizontal, up, 100.0 * (horizontal - up) / up, 100.0 * worst);
    EXPECT_LT(worst, c.max_sh9_error) << c.name;
    EXPECT_NEAR(horizontal, up, kMaxHorizontalError * up) << c.name;
  }
}

TEST(SkyLighting, NoonSkyIlluminanceIsPlausible) {
  core::Scene s = scene_for(60.0, 300.0);
  auto t = core::compute_transmittance_table(s.atmosphere, 256, 64);
  auto ms = core::compute_multiple_scattering_table(s.atmosphere, t);
  core::SkyLighting sky = core::compute_sky_lighting(s, t, ms);
  // Diffuse sky illuminance on a horizontal surface, clear day, sun at 60°: about 10-25 klx in measurements.
  double e = luminance(sky.horizontal_illuminance_lux);
  std::printf("[ sky lighting ] noon diffuse horizontal illuminance %.0f lux, sky average %.0f cd/m^2, blue/red %.2f\n", e,
              luminance(sky.average_radiance), sky.horizontal_illuminance_lux.b / sky.horizontal_illuminance_lux.r);
  EXPECT_GT(e, 5000.0);
  EXPECT_LT(e, 40000.0);
  EXPECT_GT(sky.horizontal_illuminance_lux.b, sky.horizontal_illuminance_lux.r);  // blue sky light
}
