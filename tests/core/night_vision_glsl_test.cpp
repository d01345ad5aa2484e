// The host's night-vision include (host_sdk/include/atmo/atmo_night_vision.glsl)
// compiled as C++ over GLM, against the core's double-precision
// night_vision_rgb (plugin/core/night_sky/night_vision.h): same weights, same
// tint, same output. Printed with the prefix "[ night vision ]".
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include <glm/glm.hpp>

#include "core/night_sky/night_vision.h"
#include "core/night_sky/star_photometry.h"

namespace nv_twin {
using namespace glm;
#define ATMO_NV_FN inline
#include "atmo/atmo_night_vision.glsl"
#undef ATMO_NV_FN
}  // namespace nv_twin

TEST(NightVisionGlsl, MatchesTheCore) {
  namespace night = atmo::core::night;
  night::NightVisionSettings on;
  on.enabled = true;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0.0;
  int compared = 0;
  for (int i = 0; i < 20000; ++i) {
    const double adaptation = std::pow(10.0, -4.5 + 5.5 * u(rng));  // 3e-5 .. 10 cd/m^2
    const glm::dvec3 rgb(u(rng), u(rng), u(rng));
    const glm::dvec3 scale = rgb * std::pow(10.0, -5.0 + 6.0 * u(rng));
    const glm::dvec3 core = night::night_vision_rgb(scale, adaptation, on);
    const glm::vec3 glsl = nv_twin::atmo_night_vision(glm::vec3(scale), static_cast<float>(adaptation));
    const double ref = std::max({core.x, core.y, core.z, 1e-30});
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(double(glsl[c]) - core[c]) / ref);
    ++compared;
    EXPECT_NEAR(nv_twin::atmo_photopic_weight(float(adaptation)), night::photopic_weight(adaptation), 2e-6);
  }
  std::printf("[ night vision ] GLSL include vs core over %d colours and adaptations (3e-5 .. 10 cd/m^2): worst "
              "relative difference %.2e of the largest channel\n",
              compared, worst);
  EXPECT_LT(worst, 1e-5);
  // Identity above the photopic limit, NaN-safe below.
  const glm::vec3 c(0.2f, 0.5f, 0.9f);
  EXPECT_EQ(nv_twin::atmo_night_vision(c, 5.0f), c);
  const glm::vec3 n = nv_twin::atmo_night_vision(glm::vec3(NAN, -1.0f, 0.0f), NAN);
  EXPECT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
}
