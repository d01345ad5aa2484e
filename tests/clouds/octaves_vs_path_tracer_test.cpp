// The real-time lighting approximation (octaves of multiple forward
// scattering + ambient through optical depth, cloud_march.glsl's twin)
// against the Monte Carlo path tracer (all orders, tools/cloud_reference) on
// the same cloud: mean relative luminance error over the cloud's pixels,
// printed for several sun angles, with single scattering alongside to show
// what the octaves buy. The target is <= 15 %; the model does not
// meet it yet (33-36 %, mostly missing diffuse light deep in the cloud: the
// biases printed are negative), so this test guards against regressions at
// the measured level and docs/CLOUDS.md says so.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <cstdio>

#include "cloud_path_tracer.h"
#include "core/clouds/cloud_lighting.h"
#include "core/clouds/cloud_optics.h"

namespace {

using namespace atmo::clouds;

// A cumulus-like blob: a flattened sphere with a flat base and noisy edges,
// 600 m across at 20 m voxels, peak optical depth through the centre ~20.
CloudVolume blob() {
  CloudVolume c;
  c.name = "blob";
  c.voxel_size_m = 20.0f;
  const int n = 32;
  c.density = DenseGrid(n, n, n);
  for (int z = 1; z < n - 1; ++z)
    for (int y = 1; y < n - 1; ++y)
      for (int x = 1; x < n - 1; ++x) {
        const glm::vec3 p = (glm::vec3(x, y, z) + 0.5f - 0.5f * n) / (0.5f * n - 1.5f);
        const float r = glm::length(glm::vec3(p.x, p.y, p.z * 1.3f + 0.25f));
        const float wobble = 0.12f * std::sin(7.0f * p.x) * std::sin(5.0f * p.y + 1.0f) * std::cos(6.0f * p.z);
        const float d = std::clamp((1.0f - r + wobble) * 4.0f, 0.0f, 1.0f);
        c.density.at(x, y, z) = z > 4 ? d : 0.0f;
      }
  c.optics.extinction_per_m = 0.06f;
  return c;
}

struct Errors {
  double octaves = 0.0, single = 0.0;
  double octaves_bias = 0.0;  // mean of (approximation / truth - 1)
  int pixels = 0;
};

Errors compare(const CloudVolume& cloud, const glm::dvec3& sun, const glm::dvec3& eye, int spp,
               const twin::CloudOctaves& octaves = default_octaves()) {
  reference::CloudEnvironment env;
  env.light_direction = sun;
  env.light_illuminance_lux = glm::dvec3(100000.0);
  env.sky_radiance = glm::dvec3(4000.0);
  env.ground_radiance = glm::dvec3(1500.0);
  reference::PinholeCamera cam;
  cam.position_enu_m = eye;
  cam.forward = cloud.centre_enu_m() - eye;
  cam.up = glm::dvec3(0, 0, 1);
  cam.vertical_fov_rad = 2.0 * std::atan(cloud.bounding_radius_m() / glm::length(cam.forward)) * 0.9;
  cam.width = cam.height = 20;
  reference::PathTraceSettings s;
  s.samples_per_pixel = spp;
  s.seed = 11;
  const reference::CloudImage ref = reference::path_trace(cloud, env, cam, s);

  CloudLight light;
  light.direction_enu = sun;
  light.illuminance_lux = env.light_illuminance_lux;
  light.sky_radiance = env.sky_radiance;
  light.ground_radiance = env.ground_radiance;
  const LightDepths depths = compute_light_depths(cloud, sun);
  const twin::CloudMarch m = make_cloud_march(cloud, light, 0.5f, 2048);
  const twin::CloudPhase phase = phase_for_droplet(cloud.optics.droplet_diameter_um);
  // The same pixel-centre rays as the path tracer.
  const glm::dvec3 fwd = glm::normalize(cam.forward);
  const glm::dvec3 right = glm::normalize(glm::cross(fwd, cam.up));
  const glm::dvec3 up = glm::cross(right, fwd);
  const double th = std::tan(0.5 * cam.vertical_fov_rad);
  Errors e;
  for (int row = 0; row < cam.height; ++row)
    for (int col = 0; col < cam.width; ++col) {
      const size_t i = static_cast<size_t>(row) * cam.width + col;
      if (ref.transmittance[i] > 0.5f) continue;  // the cloud's body only: edges are noise-dominated
      const double y = (1.0 - 2.0 * (row + 0.5) / cam.height) * th;
      const double x = (2.0 * (col + 0.5) / cam.width - 1.0) * th;
      const glm::dvec3 d = glm::normalize(fwd + x * right + y * up);
      const double truth = ref.radiance[i].g;
      const twin::CloudSample oc = march_cloud_ray(cloud, depths, m, phase, octaves, eye, d, 1e9);
      const twin::CloudSample ss = march_cloud_ray(cloud, depths, m, phase, single_scattering_octaves(), eye, d, 1e9);
      e.octaves += std::abs(oc.radiance.g - truth) / truth;
      e.octaves_bias += oc.radiance.g / truth - 1.0;
      e.single += std::abs(ss.radiance.g - truth) / truth;
      ++e.pixels;
    }
  if (e.pixels) {
    e.octaves /= e.pixels;
    e.octaves_bias /= e.pixels;
    e.single /= e.pixels;
  }
  return e;
}

TEST(CloudOctaves, MultipleScatteringApproximationAgainstPathTracer) {
  const CloudVolume cloud = blob();
  const glm::dvec3 c = cloud.centre_enu_m();
  struct Case {
    const char* name;
    glm::dvec3 sun;
    glm::dvec3 eye_offset;
  };
  const Case cases[] = {
      {"sun behind the eye, 45 deg up", glm::normalize(glm::dvec3(0, -1, 1)), glm::dvec3(0, -2000, 0)},
      {"sun to the side, 30 deg up", glm::normalize(glm::dvec3(1, 0, 0.58)), glm::dvec3(0, -2000, 0)},
      {"sun behind the cloud, 20 deg up (silver lining)", glm::normalize(glm::dvec3(0, 1, 0.36)), glm::dvec3(0, -2000, 0)},
      {"from below, sun overhead", glm::dvec3(0, 0, 1), glm::dvec3(0, -300, -1500)},
  };
  double worst = 0.0, mean = 0.0;
  for (const Case& k : cases) {
    const Errors e = compare(cloud, k.sun, c + k.eye_offset, 96);
    std::printf("%-48s %3d px: octaves %5.1f %% (bias %+5.1f %%), single scattering %5.1f %% (mean relative "
                "luminance error)\n", k.name, e.pixels, 100.0 * e.octaves, 100.0 * e.octaves_bias, 100.0 * e.single);
    ASSERT_GT(e.pixels, 20);
    worst = std::max(worst, e.octaves);
    mean += e.octaves / std::size(cases);
    // The octaves must beat single scattering, which misses most of the light.
    EXPECT_LT(e.octaves, e.single) << k.name;
  }
  std::printf("octaves: mean %.1f %%, worst %.1f %% (target <= 15 %%)\n", 100.0 * mean, 100.0 * worst);
  EXPECT_LE(mean, 0.40);  // measured 0.33-0.36; the target 0.15 is not met yet
}

// Not part of the suite: the sweep the default octaves were chosen with
// (run with --gtest_also_run_disabled_tests; docs/CLOUDS.md).
TEST(CloudOctaves, DISABLED_Sweep) {
  const CloudVolume cloud = blob();
  const glm::dvec3 c = cloud.centre_enu_m();
  const glm::dvec3 suns[] = {glm::normalize(glm::dvec3(0, -1, 1)), glm::normalize(glm::dvec3(1, 0, 0.58)),
                             glm::normalize(glm::dvec3(0, 1, 0.36)), glm::dvec3(0, 0, 1)};
  const glm::dvec3 eyes[] = {c + glm::dvec3(0, -2000, 0), c + glm::dvec3(0, -2000, 0), c + glm::dvec3(0, -2000, 0),
                             c + glm::dvec3(0, -300, -1500)};
  double best = 1e9;
  for (float a : {0.1f, 0.2f, 0.3f, 0.5f})
    for (float b : {0.5f, 0.7f, 0.85f})
      for (float cc : {0.3f, 0.5f, 0.8f})
        for (float k : {0.1f, 0.25f, 0.5f}) {
          twin::CloudOctaves o = default_octaves();
          o.count = 8;
          o.extinction_scale = a;
          o.scattering_scale = b;
          o.eccentricity_scale = cc;
          o.ambient_extinction = k;
          double mean = 0.0, worst = 0.0;
          for (int i = 0; i < 4; ++i) {
            const Errors e = compare(cloud, suns[i], eyes[i], 24, o);
            mean += e.octaves / 4;
            worst = std::max(worst, e.octaves);
          }
          if (mean < best) {
            best = mean;
            std::printf("a %.2f b %.2f c %.2f k %.2f: mean %.1f %% worst %.1f %%\n", a, b, cc, k, 100 * mean, 100 * worst);
          }
        }
}

}  // namespace
