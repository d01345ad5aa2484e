// What of the night sky the passes draw (core/night_sky/night_plan.h):
// nothing of the night passes in daylight, everything on a dark night, and
// between the two the limits move continuously — the stars fade in as the sky
// darkens, by physics and exposure, not by a switch. Figures are printed with
// the prefix "[ plan ]" and quoted in docs/NIGHT_SKY.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/atmosphere/atmosphere_model.h"
#include "core/night_sky/moon_photometry.h"
#include "core/night_sky/night_plan.h"
#include "core/night_sky/star_photometry.h"
#include "core/scene/scene.h"

using namespace atmo;

namespace {

constexpr double kDeg = M_PI / 180.0;

const core::ModelTables& air() {
  static const core::ModelTables a = core::compute_model_tables(core::AtmosphereSettings{}, 6370000.0);
  return a;
}

// A scene with the Sun at `sun_deg` elevation (north) and a Moon of the given
// phase at `moon_deg` elevation (south), eye 300 m up.
core::Scene scene_with(double sun_deg, double moon_deg, double moon_phase_deg) {
  core::Scene s;
  s.atmosphere = air().atmosphere;
  s.sphere_radius_m = 6370000.0;
  s.eye_altitude_m = 300.0;
  const double e = sun_deg * kDeg, m = moon_deg * kDeg;
  s.sun_direction_enu = glm::dvec3(0.0, std::cos(e), std::sin(e));
  s.bodies.sun_enu = s.bodies.sun_enu_unrefracted = s.sun_direction_enu;
  s.bodies.moon_enu = s.bodies.moon_enu_unrefracted = glm::dvec3(0.0, -std::cos(m), std::sin(m));
  s.bodies.moon_phase_angle_rad = moon_phase_deg * kDeg;
  s.bodies.moon_angular_radius_rad = 0.2591 * kDeg;
  const auto light = core::night::moon_illuminance(moon_phase_deg * kDeg);
  s.bodies.moon_illuminance_rgb_lux = light.total() * core::night::moon_color_rgb();
  return s;
}

core::night::NightPlanInputs inputs(double exposure) {
  core::night::NightPlanInputs in;
  in.exposure = exposure;
  in.display_encoded = true;
  in.pixel_solid_angle_sr = core::night::pixel_solid_angle_sr(std::tan(30.0 * kDeg), 720.0);
  return in;
}

double exposure_ev100(double ev100) { return 1.0 / (1.2 * std::pow(2.0, ev100)); }

}  // namespace

TEST(NightPlan, DaylightDrawsNoNightTermButTheDayMoon) {
  const core::Scene noon = scene_with(60.0, 30.0, 90.0);  // a quarter Moon in the afternoon sky
  const auto plan = core::night::plan_night_sky(noon, air().transmittance, air().multiple_scattering, inputs(exposure_ev100(15.0)));
  std::printf("[ plan ] noon, EV100 15: darkest sky %.0f cd/m^2, limiting magnitude %.2f; points %d, background %d, "
              "moonlit sky %d, Moon disc %d\n",
              plan.darkest_sky_cd_m2, plan.limiting_magnitude, plan.points, plan.background, plan.moonlit_sky,
              plan.moon_disc);
  // No star can show (at most Venus or Jupiter near their brightest: the
  // plugin then checks the brightest planet before any astrometry).
  EXPECT_LT(plan.limiting_magnitude, core::night::kBrightestStarMagnitude);
  EXPECT_FALSE(plan.background);
  EXPECT_FALSE(plan.moonlit_sky);
  EXPECT_FALSE(plan.moon_lights_haze());  // the Sun lights the haze by day
  // The day Moon is seen (quarter Moon ~1000 cd/m^2 against a ~5000 cd/m^2 sky): its disc stays on.
  EXPECT_TRUE(plan.moon_disc);
  // Below the horizon it is not.
  const auto set = core::night::plan_night_sky(scene_with(60.0, -5.0, 90.0), air().transmittance, air().multiple_scattering,
                                               inputs(exposure_ev100(15.0)));
  EXPECT_FALSE(set.moon_disc);
  EXPECT_FALSE(set.moon_up);
}

TEST(NightPlan, DarkNightDrawsEverything) {
  const core::Scene night = scene_with(-40.0, 40.0, 30.0);
  const auto plan = core::night::plan_night_sky(night, air().transmittance, air().multiple_scattering, inputs(exposure_ev100(-3.0)));
  std::printf("[ plan ] moonlit night (Moon 40° up, phase 30°), EV100 -3: darkest sky %.3g cd/m^2, limiting "
              "magnitude %.2f\n",
              plan.darkest_sky_cd_m2, plan.limiting_magnitude);
  EXPECT_TRUE(plan.points);
  EXPECT_TRUE(plan.background);
  EXPECT_TRUE(plan.moonlit_sky);
  EXPECT_TRUE(plan.moon_disc);
  EXPECT_GT(plan.limiting_magnitude, 4.0);
  // The Moon's sky outshines the Sun's: the haze over the ground is lit by the Moon.
  std::printf("[ plan ] moonlit night: zenith lit by the Sun %.3g, by the Moon %.3g cd/m^2\n", plan.sun_zenith_cd_m2,
              plan.moon_zenith_cd_m2);
  EXPECT_TRUE(plan.moon_lights_haze());
  // At civil twilight the Sun's sky still wins.
  const auto dusk = core::night::plan_night_sky(scene_with(-4.0, 40.0, 30.0), air().transmittance, air().multiple_scattering,
                                                inputs(exposure_ev100(7.0)));
  EXPECT_FALSE(dusk.moon_lights_haze());
  // Without the Moon: no moonlit sky, a darker sky (the limit is the display's:
  // in the tone curve's toe a darker background does not show fainter stars).
  const auto moonless = core::night::plan_night_sky(scene_with(-40.0, -30.0, 30.0), air().transmittance, air().multiple_scattering,
                                                    inputs(exposure_ev100(-3.0)));
  std::printf("[ plan ] moonless night, EV100 -3: darkest sky %.3g cd/m^2, limiting magnitude %.2f\n",
              moonless.darkest_sky_cd_m2, moonless.limiting_magnitude);
  EXPECT_FALSE(moonless.moonlit_sky);
  EXPECT_FALSE(moonless.moon_disc);
  EXPECT_FALSE(moonless.moon_lights_haze());
  EXPECT_LT(moonless.darkest_sky_cd_m2, 0.3 * plan.darkest_sky_cd_m2);
  EXPECT_GT(moonless.limiting_magnitude, 4.0);
  // A method without a sky-view table (the march, above the atmosphere) gets no moonlit sky.
  auto no_table = inputs(exposure_ev100(-3.0));
  no_table.method_has_sky_view = false;
  EXPECT_FALSE(core::night::plan_night_sky(night, air().transmittance, air().multiple_scattering, no_table).moonlit_sky);
}

// Dusk with a camera that keeps the zenith at mid grey (exposure = 0.18 /
// L_zenith, no brighter than EV100 -3): the limiting magnitude rises
// smoothly as the sun sinks; stars appear where the display could first show
// one, not at a fixed sun elevation.
TEST(NightPlan, StarsFadeInContinuouslyAtDusk) {
  double previous = -1e9, largest_step = 0.0, largest_step_at = 0.0, first_points_at = 1e9;
  for (int i = 0; i <= 96; ++i) {
    const double sun_deg = 6.0 - 0.25 * i;
    const core::Scene s = scene_with(sun_deg, -30.0, 0.0);
    const glm::vec3 zenith = twin::sky_radiance(s.atmosphere, air().transmittance, glm::vec2(air().transmittance.width, air().transmittance.height),
                                                air().multiple_scattering, glm::vec2(air().multiple_scattering.width, air().multiple_scattering.height), 300.0f,
                                                glm::vec3(0, 0, 1), glm::vec3(s.sun_direction_enu), 32);
    const double l_zenith = core::night::rgb_luminance(glm::dvec3(zenith)) + 2e-4;
    const double exposure = std::min(0.18 / l_zenith, exposure_ev100(-3.0));
    const auto plan = core::night::plan_night_sky(s, air().transmittance, air().multiple_scattering, inputs(exposure));
    ASSERT_TRUE(std::isfinite(plan.limiting_magnitude) || plan.limiting_magnitude < 0.0) << sun_deg;
    if (plan.limiting_magnitude >= core::night::kBrightestStarMagnitude && first_points_at > 1e8) first_points_at = sun_deg;
    if (i % 8 == 0) {
      std::printf("[ plan ] dusk: sun %6.2f°  zenith %.3g cd/m^2  exposure %.3g  limiting magnitude %6.2f  points %d "
                  "background %d\n",
                  sun_deg, l_zenith, exposure, plan.limiting_magnitude, plan.points, plan.background);
    }
    if (previous > -1e8 && std::isfinite(plan.limiting_magnitude)) {
      // While the exposure follows the sky, no star is lost as it darkens
      // (0.02 mag slack for the bisections). Once the exposure is at its
      // limit the display's toe sets the limit, which then eases back slowly.
      if (exposure < exposure_ev100(-3.0)) {
        EXPECT_GE(plan.limiting_magnitude, previous - 0.02) << "at sun " << sun_deg;
      }
      if (std::abs(plan.limiting_magnitude - previous) > largest_step) {
        largest_step = std::abs(plan.limiting_magnitude - previous);
        largest_step_at = sun_deg;
      }
    }
    if (std::isfinite(plan.limiting_magnitude)) previous = plan.limiting_magnitude;
  }
  std::printf("[ plan ] dusk: the first star (Sirius) can show from sun %.2f°; largest change of the limiting magnitude per 0.25°: "
              "%.3f mag at sun %.2f°\n",
              first_points_at, largest_step, largest_step_at);
  // A gradual fade: no 0.25° step of the sun changes the limit by more than 0.75 mag
  // (the sun sinks 0.25° in about a minute; the test camera's exposure follows the sky).
  EXPECT_LE(largest_step, 0.75);
  // Not in the bright day sky, and by civil twilight (the display's one-step
  // criterion is more sensitive than the eye, which sees Sirius from about -2°).
  EXPECT_LT(first_points_at, 5.0);
  EXPECT_GT(first_points_at, -6.0);
  EXPECT_GT(previous, 5.0);          // and a dark night shows the naked-eye stars
}

TEST(NightPlan, DegenerateInputsDrawNothingAndStayFinite) {
  const core::Scene night = scene_with(-40.0, 40.0, 30.0);
  for (double exposure : {0.0, -1.0, std::nan(""), static_cast<double>(INFINITY)}) {
    const auto plan = core::night::plan_night_sky(night, air().transmittance, air().multiple_scattering, inputs(exposure));
    EXPECT_FALSE(plan.points) << exposure;
    EXPECT_FALSE(plan.moon_disc || plan.moonlit_sky || plan.background) << exposure;
  }
  const auto no_tables = core::night::plan_night_sky(night, twin::Lut2D{}, twin::Lut2D{}, inputs(1.0));
  EXPECT_FALSE(no_tables.points);
  // A degenerate camera (zero solid angle) is clamped.
  auto zero = inputs(1.0);
  zero.pixel_solid_angle_sr = 0.0;
  const auto p = core::night::plan_night_sky(night, air().transmittance, air().multiple_scattering, zero);
  EXPECT_FALSE(std::isnan(p.limiting_magnitude));
}
