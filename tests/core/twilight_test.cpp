// Twilight continuity: as the sun sinks from +2° to −18° (astronomical
// twilight's end) the sky darkens smoothly — no step ("pop"), no black frame,
// no brightening. The model is the shared GLSL compiled as C++ (the CPU twin),
// so this is what every sky method draws below the horizon (all hand over to
// the LUT/march sky there). The night-sky layer adds its own light on top.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/atmosphere/atmosphere_model.h"
#include "core/atmosphere/shader_twin.h"

using namespace atmo;

namespace {

double luminance(const glm::vec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

}  // namespace

TEST(Twilight, SkyDarkensSmoothlyToMinus18Degrees) {
  const double radius = 6370000.0;
  const auto atm = core::make_atmosphere_parameters(core::AtmosphereSettings{}, radius, 1.0);
  const auto t = core::compute_transmittance_table(atm, core::kTransmittanceWidth, core::kTransmittanceHeight);
  const auto ms = core::compute_multiple_scattering_table(atm, t);
  const glm::vec2 t_size(t.width, t.height), ms_size(ms.width, ms.height);
  const float altitude = 300.0f;

  // Sun in the north (+y). Directions: zenith, 5° up toward the sun, 5° up
  // away from it, and 30° up toward it.
  auto dir = [](double elevation_deg, double toward_sun) {
    double e = elevation_deg * M_PI / 180.0;
    return glm::vec3(0.0f, float(toward_sun * std::cos(e)), float(std::sin(e)));
  };
  struct Direction {
    const char* name;
    glm::vec3 d;
  } directions[] = {{"zenith", dir(90.0, 1.0)}, {"5 deg toward the sun", dir(5.0, 1.0)},
                    {"5 deg away from the sun", dir(5.0, -1.0)}, {"30 deg toward the sun", dir(30.0, 1.0)}};

  constexpr double kStepDeg = 0.25;
  // Observed twilight darkens by about a factor of 10 per 2–3° of solar
  // depression (a factor of 1.2–1.3 per 0.25°). A factor of 2 in one 0.25°
  // step would be a visible pop.
  constexpr double kMaxStepRatio = 2.0;
  for (const Direction& direction : directions) {
    double previous = -1.0, worst_ratio = 1.0, worst_at = 0.0;
    double at_minus6 = 0.0, at_minus12 = 0.0, at_minus18 = 0.0;
    for (int i = 0; i <= int(20.0 / kStepDeg); ++i) {
      const double sun_deg = 2.0 - i * kStepDeg;
      const double e = sun_deg * M_PI / 180.0;
      const glm::vec3 sun(0.0f, float(std::cos(e)), float(std::sin(e)));
      const glm::vec3 radiance =
          twin::sky_radiance_parts(atm, t, t_size, ms, ms_size, altitude, direction.d, sun, 64).diffuse;
      const double l = luminance(radiance);
      ASSERT_TRUE(std::isfinite(l)) << direction.name << " at sun " << sun_deg;
      // No black frame: the lit upper atmosphere and the multiple-scattering
      // term keep every direction above zero down to -18°.
      ASSERT_GT(l, 0.0) << direction.name << " is black at sun " << sun_deg << "°";
      if (previous > 0.0) {
        // Never brighter as the sun sinks (1e-6 relative slack for float).
        EXPECT_LE(l, previous * (1.0 + 1e-6)) << direction.name << " brightens at sun " << sun_deg << "°";
        const double ratio = previous / l;
        if (ratio > worst_ratio) worst_ratio = ratio, worst_at = sun_deg;
      }
      if (std::abs(sun_deg + 6.0) < 1e-9) at_minus6 = l;
      if (std::abs(sun_deg + 12.0) < 1e-9) at_minus12 = l;
      if (std::abs(sun_deg + 18.0) < 1e-9) at_minus18 = l;
      previous = l;
    }
    std::printf("[ twilight ] %-24s  L(-6°) %.3g  L(-12°) %.3g  L(-18°) %.3g cd/m^2; largest darkening per 0.25° "
                "x%.3f at sun %.2f°\n",
                direction.name, at_minus6, at_minus12, at_minus18, worst_ratio, worst_at);
    EXPECT_LE(worst_ratio, kMaxStepRatio) << direction.name << ": a pop at sun " << worst_at << "°";
  }
}
