// The lights' core (core/lights): a cone's mean profile against the GLSL
// cone's average over the sphere, the eye's threshold illuminance at the
// ICAO classes, and the air's transmittance along a segment against a fine
// trapezoid sum.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/atmosphere/atmosphere_model.h"
#include "core/fog/fog_twin.h"
#include "core/lights/light_points.h"
#include "core/lights/light_set.h"

namespace {

using namespace atmo;

// The GLSL cone averaged over the sphere (d omega = 2 pi d cos) by a 200 000-point midpoint rule.
double sampled_mean(double cos_inner, double cos_outer, float lobes) {
  const int n = 200000;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const float c = static_cast<float>(-1.0 + 2.0 * (i + 0.5) / n);
    sum += fog::twin::atmo_fog_cone(glm::vec3(0.0f, 0.0f, 1.0f), float(cos_inner), float(cos_outer), lobes,
                                    glm::vec3(std::sqrt(1.0f - c * c), 0.0f, c));
  }
  return sum / n;
}

TEST(LightSet, ConeMeanIsTheClosedForm) {
  const double cones[][2] = {{0.0, 0.1}, {0.17, 0.44}, {0.5, 1.2}, {1.0, 1.57}, {0.0, 3.1}};
  for (const auto& c : cones)
    for (const float lobes : {1.0f, 2.0f}) {
      if (lobes > 1.0f && c[1] > 0.5 * M_PI) continue;  // bidirectional cones may not overlap
      const double ci = std::cos(c[0]), co = std::cos(c[1]);
      const double exact = lights::mean_cone_profile(ci, co, lobes), sampled = sampled_mean(ci, co, lobes);
      std::printf("cone %.2f-%.2f rad, %g lobe(s): mean %.6f, sampled %.6f\n", c[0], c[1], lobes, exact, sampled);
      EXPECT_NEAR(exact, sampled, 2e-5);
    }
  EXPECT_EQ(lights::mean_cone_profile(-2.0, -2.0), 1.0);  // omnidirectional
}

TEST(LightPointsCore, AllardThresholdAtTheIcaoClasses) {
  EXPECT_NEAR(lights::allard_threshold_lux(1e-4), 8e-7, 1e-12);  // night
  EXPECT_NEAR(lights::allard_threshold_lux(50.0), 8e-7, 1e-12);
  EXPECT_NEAR(lights::allard_threshold_lux(1000.0), 1e-5, 1e-10);     // intermediate's upper bound
  EXPECT_NEAR(lights::allard_threshold_lux(12000.0), 1e-4, 1e-9);     // normal day's upper bound
  EXPECT_NEAR(lights::allard_threshold_lux(1e6), 1e-3, 1e-8);         // bright day (sunlit fog)
  // Continuous and rising with the background: no light pops as B crosses a class boundary.
  double last = 0.0;
  for (double b = 1e-3; b < 1e6; b *= 1.01) {
    const double e = lights::allard_threshold_lux(b);
    EXPECT_GE(e, last);
    if (last > 0.0) {
      EXPECT_LT(e / last, 1.05);
    }
    last = e;
  }
}

// 8-point Gauss-Legendre on the curved segment against a 100 000-step trapezoid sum in double, from the
// ground to 9 km, horizontal to vertical, 10 m to 400 km, in clear air and haze.
TEST(LightPointsCore, AirTransmittanceAgainstAFineSum) {
  double worst = 0.0;
  for (const double visibility : {40000.0, 5000.0}) {
    core::AtmosphereSettings air;
    air.visibility_m = visibility;
    const twin::AtmosphereParameters atm = core::make_atmosphere_parameters(air, 6371000.0, 1.0);
    for (const double eye : {2.0, 300.0, 3000.0, 9000.0})
      for (const double length : {10.0, 1000.0, 8047.0, 50000.0, 400000.0})
        for (const double elevation_deg : {-90.0, -10.0, -1.0, 0.0, 2.0, 45.0}) {
          const double e = glm::radians(elevation_deg);
          const glm::dvec3 to = length * glm::dvec3(0.0, std::cos(e), std::sin(e));
          const glm::dvec3 centre_to_eye(0.0, 0.0, 6371000.0 + eye);
          if (glm::length(centre_to_eye + to) < 6371000.0 - 1.0) continue;  // below the ground
          const int n = 100000;
          glm::dvec3 depth(0.0);
          for (int i = 0; i <= n; ++i) {
            const double altitude = glm::length(centre_to_eye + (double(i) / n) * to) - 6371000.0;
            depth += (i == 0 || i == n ? 0.5 : 1.0) * glm::dvec3(twin::extinction_at(atm, float(altitude)));
          }
          const glm::dvec3 reference = glm::exp(-depth / double(n) * length);
          const glm::dvec3 got = lights::air_transmittance(atm, eye, to);
          for (int c = 0; c < 3; ++c) {
            const double err = std::abs(got[c] - reference[c]) / std::max(reference[c], 1e-30);
            if (reference[c] > 1e-6) worst = std::max(worst, err);
            EXPECT_LT(err, reference[c] > 1e-6 ? 1e-4 : 1.0);
          }
        }
  }
  std::printf("air transmittance, Gauss-Legendre 8 against the fine sum: worst relative error %.2e\n", worst);
}

}  // namespace
