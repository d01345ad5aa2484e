// The host include atmo_sky_occlusion.glsl (through its C++ twin, as shipped:
// order 4, hybrid exponential, the culling limits) against the ray-traced
// reference (tools/shadow_reference) on the configurations of
// occlusion_scenes.h: the occluded sky irradiance's error as a fraction of
// the unoccluded, per receiver, printed; median <= 5 %, worst <= 15 %
// (docs/SKY_OCCLUSION.md). Also the Sun's visibility and the bounce; and the
// include's image (ATMO_OCC_IMAGE: a receiver's light by normal, fitted at one
// normal) at normals tilted from the one it was fitted at.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>

#include "core/shadows/occlusion_frame.h"
#include "core/shadows/occlusion_twin.h"
#include "occlusion_scenes.h"
#include "shadow_reference.h"

namespace atmo::shadow_reference {
namespace {

// The eye at the origin looking north (world = ENU): the receivers lie ahead of it.
shadows::OcclusionFrame frame_for(const std::vector<shadows::OccluderObject>& objects, const glm::dvec3& sun,
                                  const glm::dvec3& sun_lux) {
  std::vector<const shadows::OccluderObject*> ptrs;
  std::vector<glm::dmat4> poses;
  for (const auto& o : objects) {
    ptrs.push_back(&o);
    poses.push_back(glm::translate(glm::dmat4(1.0), glm::dvec3(0, 60, -3)));
  }
  const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1));  // north
  const glm::dmat4 proj = glm::perspective(1.5, 16.0 / 9.0, 0.1, 1e5);
  return shadows::make_occlusion_frame(ptrs, poses, proj * view, glm::dmat3(1.0), 1280, 720,
                                       shadows::make_sky_transfer(test_sky_sh(4), sun, sun_lux), sun, sun_lux,
                                       shadows::OcclusionLimits{});
}

// A configuration as the include sees it (one object of albedo 0.5) and as the ray tracer does.
struct Configured {
  std::vector<shadows::OccluderObject> objects;
  shadows::OcclusionFrame frame;
  Scene scene;
};
Configured configure(const OcclusionConfig& c, const glm::dvec3& sun, const glm::dvec3& sun_lux) {
  Configured k;
  k.objects = {shadows::make_occluder_object(c.spheres, glm::dvec3(0.5))};
  k.frame = frame_for(k.objects, sun, sun_lux);
  for (const glm::dvec4& s : c.spheres) k.scene.spheres.push_back({glm::dvec3(s), s.w, 0});
  k.scene.object_albedo = {glm::dvec3(0.5)};
  k.scene.sky_radiance = test_sky_radiance;
  k.scene.sun_direction = sun;
  k.scene.sun_illuminance = sun_lux;
  return k;
}

TEST(SkyOcclusionAccuracy, IncludeAgainstTheRayTracedReference) {
  const glm::dvec3 sun = glm::normalize(glm::dvec3(0.3, -0.5, 0.8)), sun_lux(9e4, 8.8e4, 8.5e4);
  std::vector<double> errors;
  double worst = 0.0, worst_bounce = 0.0;
  std::string worst_at;
  for (const OcclusionConfig& c : occlusion_configs()) {
    const Configured k = configure(c, sun, sun_lux);
    const shadows::OcclusionFrame& frame = k.frame;
    const Scene& scene = k.scene;
    double config_worst = 0.0;
    for (const Receiver& r : c.receivers) {
      const Estimate open = sky_irradiance(scene, r.position_m, r.normal, false, 40000);
      const Estimate shut = sky_irradiance(scene, r.position_m, r.normal, true, 100000);
      const glm::vec3 rel_eye = glm::vec3(r.position_m + glm::dvec3(0, 60, -3));
      const shadows::twin::AtmoSkyOcclusion got = shadows::twin::evaluate(frame, rel_eye, glm::vec3(r.normal));
      const double err = std::abs(got.sky_lux.y - shut.value.y) / open.value.y;
      const double sun_ref = sun_visibility(scene, r.position_m, 4096);
      // The bounce: the reference with the model's assumption (each sphere's surface lit by the open sky and
      // the Sun) and traced (the object shadowing itself), against the open sky's irradiance.
      const Estimate bounce = bounce_irradiance(scene, r.position_m, r.normal, BounceMode::unshadowed_hit, 4000, 16);
      const Estimate traced = bounce_irradiance(scene, r.position_m, r.normal, BounceMode::traced, 4000, 16);
      const double bounce_err = std::abs(got.bounce_lux.y - bounce.value.y) / open.value.y;
      worst_bounce = std::max(worst_bounce, bounce_err);
      std::printf("    bounce: include %.1f lx, reference %.1f (traced %.1f): %.2f %% of the open sky\n", got.bounce_lux.y,
                  bounce.value.y, traced.value.y, 100.0 * bounce_err);
      // The Sun's visibility where the Sun lights the receiver (elsewhere it multiplies nothing).
      if (glm::dot(r.normal, sun) > 0.05) {
        EXPECT_NEAR(got.sun_visibility, sun_ref, 0.05) << c.name;
      }
      std::printf("%-22s receiver (%5.1f %5.1f %4.1f) n (%2.0f %2.0f %2.0f): reference %7.1f lx of %7.1f, include "
                  "%7.1f: error %5.2f %% of open; sun %.2f vs %.2f\n",
                  c.name.c_str(), r.position_m.x, r.position_m.y, r.position_m.z, r.normal.x, r.normal.y, r.normal.z,
                  shut.value.y, open.value.y, got.sky_lux.y, 100.0 * err, got.sun_visibility, sun_ref);
      errors.push_back(err);
      config_worst = std::max(config_worst, err);
      if (err > worst) worst = err, worst_at = c.name;
      EXPECT_TRUE(std::isfinite(got.bounce_lux.y) && got.bounce_lux.y >= 0.0f);
    }
    std::printf("  %s: worst %.2f %%\n", c.name.c_str(), 100.0 * config_worst);
  }
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2];
  std::printf("[ measured ] %zu receivers in %zu configurations: median %.2f %%, worst %.2f %% (%s) of the "
              "unoccluded sky irradiance\n",
              errors.size(), occlusion_configs().size(), 100.0 * median, 100.0 * worst, worst_at.c_str());
  EXPECT_GE(occlusion_configs().size(), 6u);
  EXPECT_LE(median, 0.05);
  EXPECT_LE(worst, 0.15);
  std::printf("[ measured ] bounce: worst %.2f %% of the unoccluded sky irradiance against the reference's "
              "unshadowed-hit bounce\n", 100.0 * worst_bounce);
  // Measured 17 % at worst (a receiver between two vans, their sunlit sides 1.5 m away: docs/SKY_OCCLUSION.md).
  EXPECT_LE(worst_bounce, 0.20);
}

// The image's fit (twin::evaluate_fit at the receiver's normal, as ATMO_PASS_SKY_OCCLUSION_IMAGE makes it at a
// block's) read back at normals tilted 20 and 45 degrees from it in four azimuths (a host's surface whose normal
// is not the depth's), against the reference at those normals; at the fitted normal it is the include's answer.
TEST(SkyOcclusionAccuracy, ImageFitAtTiltedNormals) {
  const glm::dvec3 sun = glm::normalize(glm::dvec3(0.3, -0.5, 0.8)), sun_lux(9e4, 8.8e4, 8.5e4);
  std::vector<double> image_errors[2], include_errors[2], bounce_diffs;
  double at_fit_worst = 0.0;
  for (const OcclusionConfig& c : occlusion_configs()) {
    const Configured k = configure(c, sun, sun_lux);
    const shadows::OcclusionFrame& frame = k.frame;
    const Scene& scene = k.scene;
    for (const Receiver& r : c.receivers) {
      const glm::vec3 rel_eye = glm::vec3(r.position_m + glm::dvec3(0, 60, -3));
      shadows::twin::AtmoOccFit fit;
      const shadows::twin::AtmoSkyOcclusion at_fit = shadows::twin::evaluate_fit(frame, rel_eye, glm::vec3(r.normal), &fit);
      const shadows::twin::AtmoSkyOcclusion read = shadows::twin::from_fit(frame, fit, glm::vec3(r.normal));
      const double open0 = std::max<double>(shadows::twin::from_fit(frame, shadows::twin::AtmoOccFit{}, glm::vec3(r.normal)).sky_lux.y, 1.0);
      at_fit_worst = std::max({at_fit_worst, std::abs(double(read.sky_lux.y) - at_fit.sky_lux.y) / open0,
                               std::abs(double(read.bounce_lux.y) - at_fit.bounce_lux.y) / open0,
                               std::abs(double(read.sun_visibility) - at_fit.sun_visibility)});
      // Two unit vectors across the normal.
      const glm::dvec3 a = glm::normalize(glm::cross(r.normal, std::abs(r.normal.z) < 0.9 ? glm::dvec3(0, 0, 1)
                                                                                         : glm::dvec3(1, 0, 0)));
      const glm::dvec3 b = glm::cross(r.normal, a);
      for (int t = 0; t < 2; ++t) {
        const double tilt = glm::radians(t == 0 ? 20.0 : 45.0);
        for (int k = 0; k < 4; ++k) {
          const double az = k * 0.5 * glm::pi<double>();
          const glm::dvec3 n = std::cos(tilt) * r.normal + std::sin(tilt) * (std::cos(az) * a + std::sin(az) * b);
          const Estimate open = sky_irradiance(scene, r.position_m, n, false, 20000);
          const Estimate shut = sky_irradiance(scene, r.position_m, n, true, 40000);
          if (!(open.value.y > 0.0)) continue;
          const shadows::twin::AtmoSkyOcclusion image = shadows::twin::from_fit(frame, fit, glm::vec3(n));
          const shadows::twin::AtmoSkyOcclusion exact = shadows::twin::evaluate(frame, rel_eye, glm::vec3(n));
          image_errors[t].push_back(std::abs(image.sky_lux.y - shut.value.y) / open.value.y);
          include_errors[t].push_back(std::abs(exact.sky_lux.y - shut.value.y) / open.value.y);
          bounce_diffs.push_back(std::abs(double(image.bounce_lux.y) - exact.bounce_lux.y) / open.value.y);
          EXPECT_TRUE(std::isfinite(image.sky_lux.y) && image.sky_lux.y >= 0.0f && image.bounce_lux.y >= 0.0f);
        }
      }
    }
  }
  std::printf("[ measured ] the image's fit read at the normal it was fitted at: worst %.2e of the open sky\n",
              at_fit_worst);
  // Not 0: the image takes the sky's light in the open sky's colour, the include per channel (a 0.1 % shift in green).
  EXPECT_LE(at_fit_worst, 2e-3);
  const char* tilt_name[2] = {"20", "45"};
  double medians[2], worsts[2];
  for (int t = 0; t < 2; ++t) {
    for (auto* v : {&image_errors[t], &include_errors[t]}) std::sort(v->begin(), v->end());
    medians[t] = image_errors[t][image_errors[t].size() / 2];
    worsts[t] = image_errors[t].back();
    std::printf("[ measured ] normals tilted %s deg (%zu): the image's sky irradiance error median %.2f %%, p90 %.2f %%, "
                "worst %.2f %% of the unoccluded (the include at those normals: median %.2f %%, worst %.2f %%)\n",
                tilt_name[t], image_errors[t].size(), 100.0 * medians[t],
                100.0 * image_errors[t][image_errors[t].size() * 9 / 10], 100.0 * worsts[t],
                100.0 * include_errors[t][include_errors[t].size() / 2], 100.0 * include_errors[t].back());
  }
  // Measured 1.3 / 10.5 % at 20 degrees, 2.7 / 34 % at 45 (bands 0 and 1 of the light by normal:
  // docs/SKY_OCCLUSION.md, "The image").
  EXPECT_LE(medians[0], 0.03);
  EXPECT_LE(worsts[0], 0.15);
  EXPECT_LE(medians[1], 0.05);
  EXPECT_LE(worsts[1], 0.40);
  std::sort(bounce_diffs.begin(), bounce_diffs.end());
  std::printf("[ measured ] the image's bounce against the include's at the tilted normals: median %.2f %%, worst %.2f %% "
              "of the unoccluded sky\n", 100.0 * bounce_diffs[bounce_diffs.size() / 2], 100.0 * bounce_diffs.back());
}

}  // namespace
}  // namespace atmo::shadow_reference
