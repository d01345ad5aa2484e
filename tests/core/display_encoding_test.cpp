// The one tone map (host_sdk/include/atmo/atmo_tone_map.glsl: the plugin's display output, the tools'
// previews and the sample host's pass) through the plugin's twin (encode_display_srgb), against the curve and
// the transfer function written out here in double: Narkowicz 2015's ACES fit, IEC 61966-2-1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/atmosphere/shader_twin.h"

namespace {

double reference(double exposed) {
  const double x = std::max(exposed, 0.0);
  const double a = std::clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
  return a <= 0.0031308 ? 12.92 * a : 1.055 * std::pow(a, 1.0 / 2.4) - 0.055;
}

}  // namespace

TEST(DisplayEncoding, MatchesTheCurveAndSaturatesToExactlyOne) {
  double worst = 0.0;
  for (double e = 1e-4; e < 1e5; e *= 1.05) {
    const float got = atmo::twin::encode_display_srgb(glm::vec3(static_cast<float>(e))).x;
    worst = std::max(worst, std::abs(got - reference(e)));
  }
  std::printf("[ display ] encode_display_srgb vs the double formula, exposed 1e-4 .. 1e5: worst %.2e\n", worst);
  EXPECT_LT(worst, 2e-6);
  EXPECT_EQ(atmo::twin::encode_display_srgb(glm::vec3(0.0f)).x, 0.0f);
  EXPECT_EQ(atmo::twin::encode_display_srgb(glm::vec3(-5.0f)).x, 0.0f);
  // Saturated pixels (the Sun's disc) encode to 1, not 0.99999994, and +inf does not become NaN.
  EXPECT_EQ(atmo::twin::encode_display_srgb(glm::vec3(1.0e9f)).x, 1.0f);
  EXPECT_EQ(atmo::twin::encode_display_srgb(glm::vec3(std::numeric_limits<float>::infinity())).x, 1.0f);
}
