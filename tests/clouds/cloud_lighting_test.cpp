// The cloud lighting core (core/clouds/cloud_lighting, the twin of
// cloud_march.glsl) against independent quadrature: optical depths of known
// grids, the march's transmittance and its single-scattering radiance against
// a double-precision fine-step integral of the model written out here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "core/clouds/cloud_lighting.h"
#include "core/clouds/cloud_optics.h"

namespace {

using namespace atmo::clouds;

// A cloud with one voxel of zero padding round a random interior, so the
// trilinear density integrates exactly to the voxel sum along axis rays.
CloudVolume random_cloud(int n, float voxel_m, unsigned seed) {
  CloudVolume c;
  c.name = "random";
  c.voxel_size_m = voxel_m;
  c.density = DenseGrid(n, n, n);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int z = 1; z < n - 1; ++z)
    for (int y = 1; y < n - 1; ++y)
      for (int x = 1; x < n - 1; ++x) c.density.at(x, y, z) = u(rng);
  return c;
}

TEST(CloudLighting, OpticalDepthAlongAxesIsTheVoxelSum) {
  const CloudVolume c = random_cloud(12, 25.0f, 3);
  double worst = 0.0;
  for (int y = 1; y < 11; ++y)
    for (int x = 1; x < 11; ++x) {
      // Up from the centre of voxel (x, y, 2): half of voxel 2, then 3..10.
      double sum = 0.5 * c.density.at(x, y, 2);
      for (int z = 3; z < 12; ++z) sum += c.density.at(x, y, z);
      const double expected = sum * c.voxel_size_m * c.optics.extinction_per_m;
      const double got = optical_depth_to_exit(c, glm::vec3(x + 0.5f, y + 0.5f, 2.5f), glm::vec3(0, 0, 1));
      worst = std::max(worst, std::abs(got - expected) / expected);
    }
  std::printf("optical depth up, worst relative error %.2e\n", worst);
  EXPECT_LT(worst, 1e-5);
}

// tau_up / tau_down (hemispherical, computed by sweeping the grid once per
// direction) against the same mean of escape conductances over the same
// directions, each direction's optical depth marched exactly.
TEST(CloudLighting, HemisphericalDepthsMatchAnExactMarch) {
  CloudVolume c = random_cloud(14, 25.0f, 5);
  c.rotation = glm::angleAxis(0.4, glm::dvec3(0.0, 0.0, 1.0));  // turned about the vertical, as the plugin allows
  const LightDepths d = compute_light_depths(c, glm::dvec3(0, 0, 1));
  double worst = 0.0, mean = 0.0;
  int n = 0;
  for (int z = 0; z < 14; z += 2)
    for (int y = 0; y < 14; y += 3)
      for (int x = 0; x < 14; x += 3) {
        double conductance[2] = {0.0, 0.0};
        for (int h = 0; h < 2; ++h)
          for (int k = 0; k < kAmbientDirections; ++k) {
            const double ct = 1.0 - (k + 0.5) / kAmbientDirections, st = std::sqrt(1.0 - ct * ct);
            const double phi = 2.399963229728653 * k;
            const glm::vec3 dir = grid_direction(c, glm::dvec3(st * std::cos(phi), st * std::sin(phi), h ? -ct : ct));
            const float tau = optical_depth_to_exit(c, glm::vec3(x + 0.5f, y + 0.5f, z + 0.5f), dir, 0.1f);
            conductance[h] += 1.0 / (1.0 + tau / kAmbientEscapeDepth);
          }
        for (int h = 0; h < 2; ++h) {
          const double exact = kAmbientEscapeDepth * (kAmbientDirections / conductance[h] - 1.0);
          const glm::vec3& t = d.tau[d.index(x, y, z)];
          const double e = std::abs((h ? t.z : t.y) - exact) / (exact + 1.0);
          worst = std::max(worst, e);
          mean += e;
          ++n;
        }
      }
  mean /= n;
  std::printf("hemispherical depths against an exact march: mean error %.3f, worst %.3f (relative to 1 + tau)\n", mean,
              worst);
  EXPECT_LT(mean, 0.03);
  EXPECT_LT(worst, 0.15);
}

TEST(CloudLighting, HemisphericalDepthsAreMirrorSymmetricAndZeroAboveTheCloud) {
  CloudVolume c = random_cloud(10, 30.0f, 11);
  for (int z = 0; z < 5; ++z)  // mirror the column in z
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 10; ++x) c.density.at(x, y, 9 - z) = c.density.at(x, y, z);
  const LightDepths d = compute_light_depths(c, glm::dvec3(0.3, 0.2, 0.9));
  double worst = 0.0;
  for (int z = 0; z < 10; ++z)
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 10; ++x)
        worst = std::max(worst, double(std::abs(d.tau[d.index(x, y, z)].y - d.tau[d.index(x, y, 9 - z)].z)));
  EXPECT_LT(worst, 1e-4);
  // The empty top layer sees nothing above it, the bottom one nothing below;
  // each sees the cloud the other way.
  EXPECT_NEAR(d.tau[d.index(5, 5, 9)].y, 0.0f, 1e-6f);
  EXPECT_NEAR(d.tau[d.index(5, 5, 0)].z, 0.0f, 1e-6f);
  EXPECT_GT(d.tau[d.index(5, 5, 0)].y, 1.0f);
}

TEST(CloudLighting, RotatedGridSeesTheLightInItsOwnAxes) {
  CloudVolume c = random_cloud(10, 30.0f, 7);
  c.rotation = glm::angleAxis(glm::radians(90.0), glm::dvec3(1, 0, 0));  // grid y -> ENU up
  const glm::vec3 g = grid_direction(c, glm::dvec3(0, 0, 1));
  EXPECT_NEAR(g.y, 1.0f, 1e-6f);
  EXPECT_NEAR(std::abs(g.x) + std::abs(g.z), 0.0f, 1e-6f);
}

// A homogeneous slab under an overhead Sun: transmittance through it and the
// radiance (single scattering; the default model: octaves, diffusion term,
// ambient, with the diffuse part taken from further along the view ray)
// against a fine double-precision integral of the model (same phase, optical
// depths computed analytically for the slab), looking up through the slab
// towards the Sun and down onto it, optically thin (1.4) and thick (7).
TEST(CloudLighting, MarchMatchesFineQuadratureOfTheModel) {
  const int n = 16;
  CloudLight light;
  light.direction_enu = glm::dvec3(0, 0, 1);
  light.illuminance_lux = glm::dvec3(1e5);
  light.sky_radiance = glm::dvec3(5000.0);
  light.ground_radiance = glm::dvec3(1000.0);
  const twin::CloudPhase phase = phase_for_droplet(20.0f);
  for (const float extinction : {0.02f, 0.1f})
    for (const bool up : {true, false})
      for (const twin::CloudOctaves& oc : {single_scattering_octaves(), default_octaves()}) {
        CloudVolume c;
        c.voxel_size_m = 10.0f;
        c.density = DenseGrid(n, n, n);
        for (int z = 1; z < n - 1; ++z)
          for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) c.density.at(x, y, z) = 0.5f;
        c.optics.extinction_per_m = extinction;
        const LightDepths depths = compute_light_depths(c, glm::dvec3(0, 0, 1));
        const twin::CloudMarch m = make_cloud_march(c, light, 0.25f, 4096);
        // From below the centre looking up (towards the Sun), or from above looking down.
        const glm::dvec3 eye(80.0, 80.0, up ? -100.0 : 260.0);
        const glm::dvec3 dir(0.0, 0.0, up ? 1.0 : -1.0);
        const twin::CloudSample s = march_cloud_ray(c, depths, m, phase, oc, eye, dir, 1e9);
        // The model along z (density as the trilinear interpolant of the grid:
        // 0 at z=0.5 voxels... constant 0.5 between centres 1.5 and 14.5).
        auto rho = [&](double z_vox) {
          const double p = z_vox - 0.5;
          const double a = std::clamp(p - 0.0, 0.0, 1.0), b = std::clamp(p - (n - 2), 0.0, 1.0);
          return 0.5 * (a - b);
        };
        const int fine = 200000;
        const double dz = n / double(fine);
        const double per_m = c.optics.extinction_per_m, dz_m = dz * c.voxel_size_m;
        std::vector<double> rho_z(fine), tau_above(fine), tau_below(fine);
        for (int i = 0; i < fine; ++i) rho_z[i] = rho((i + 0.5) * dz);
        double acc = 0.0;
        for (int i = fine - 1; i >= 0; --i) {
          tau_above[i] = acc + 0.5 * rho_z[i] * dz_m * per_m;
          acc += rho_z[i] * dz_m * per_m;
        }
        const double tau_total = acc;
        acc = 0.0;
        for (int i = 0; i < fine; ++i) {
          tau_below[i] = acc + 0.5 * rho_z[i] * dz_m * per_m;
          acc += rho_z[i] * dz_m * per_m;
        }
        const float cos_theta = up ? 1.0f : -1.0f;
        // The hemispherical depths at a fine step's height: the grid's, at the
        // column's centre, interpolated in z as the march's fetch does.
        auto hemi = [&](int i, int channel) {
          const float z = static_cast<float>((i + 0.5) * dz);
          return double(fetch_cloud_volume(CpuCloudVolume{&c.density, &depths}, glm::vec3(8.0f, 8.0f, z))[channel]);
        };
        auto hemi_up = [&](int i) { return hemi(i, 2); };
        auto hemi_down = [&](int i) { return hemi(i, 3); };
        // Along the view ray: the octaves' source integrated exactly per fine
        // step; the diffusion and ambient terms owed to each step's scattering
        // and paid from the steps beyond with weight exp(-delta tau / Lambda) /
        // Lambda, the rest at the last step that holds cloud.
        double T = 1.0, L = 0.0, owed = 0.0, diffuse = 0.0;
        for (int k = 0; k < fine; ++k) {
          const int i = up ? k : fine - 1 - k;
          const double sigma_t = rho_z[i] * per_m;
          if (sigma_t <= 0.0) continue;
          // Sun overhead: the light's axis is the vertical, so tau_back (behind
          // the point, away from the light) and tau_down are both the depth below.
          // tau_up and tau_down: hemispherical (cloud_lighting.h), for a slab
          // the vertical depth over the mean |cos| of the directions, here
          // taken from the grid as the march does (its own test is below).
          // The march fetches tau_back only for orders >= 2 (cloud_march.glsl).
          const double tau_back = oc.count > 1 && oc.diffusion_strength > 0.0f ? tau_below[i] : 0.0;
          const double around = 0.5 * (tau_above[i] + tau_back + hemi_up(i) + hemi_down(i));
          const double multiple = twin::cloud_multiple_share(oc, float(around));
          const double J = twin::cloud_light_octaves(phase, oc, float(tau_above[i]), cos_theta, float(multiple));
          const double step_t = std::exp(-sigma_t * dz_m);
          L += T * c.optics.albedo * (1.0 - step_t) * 1e5 * J;
          const glm::vec3 amb =
              twin::cloud_ambient(phase, oc, glm::vec3(light.sky_radiance), glm::vec3(light.ground_radiance),
                                  float(hemi_up(i)), float(hemi_down(i)), float(around), float(dir.z));
          diffuse = 1e5 * multiple *
                        twin::cloud_light_diffusion(oc, float(tau_above[i]), float(tau_below[i]), float(hemi_up(i)),
                                                    float(hemi_down(i)), cos_theta) +
                    amb.x;
          owed += T * c.optics.albedo * (1.0 - step_t);
          const double share = owed * (oc.diffusion_lookahead > 0.0f
                                           ? 1.0 - std::exp(-sigma_t * dz_m / oc.diffusion_lookahead)
                                           : 1.0);
          L += share * diffuse;
          owed -= share;
          T *= step_t;
          if (T < 1e-4) break;  // as the march
        }
        L += owed * diffuse;
        const double rel = std::abs(s.radiance.x - L) / L;
        std::printf("tau %.1f, looking %s, octaves %d: march %.6g cd/m2, quadrature %.6g, rel %.2e; T %.6f vs %.6f\n",
                    tau_total, up ? "up" : "down", oc.count, double(s.radiance.x), L, rel, double(s.transmittance),
                    std::exp(-tau_total));
        EXPECT_LT(rel, 0.02);
        EXPECT_NEAR(s.transmittance, std::exp(-tau_total), 2e-3);
        EXPECT_GT(s.depth_m, 100.0);
        EXPECT_LT(s.depth_m, 100.0 + n * c.voxel_size_m);
      }
}

TEST(CloudLighting, RayMissingTheCloudSeesNothing) {
  const CloudVolume c = random_cloud(8, 10.0f, 9);
  const LightDepths d = compute_light_depths(c, glm::dvec3(0.3, 0.2, 0.9));
  CloudLight light;
  light.illuminance_lux = glm::dvec3(1e5);
  const twin::CloudSample s = march_cloud_ray(c, d, make_cloud_march(c, light), phase_for_droplet(20),
                                              default_octaves(), glm::dvec3(-50, -50, -50), glm::dvec3(-1, 0, 0), 1e9);
  EXPECT_EQ(s.transmittance, 1.0f);
  EXPECT_EQ(s.radiance.x, 0.0f);
  // A ray stopped by the host's surface before the cloud sees nothing either.
  const twin::CloudSample s2 = march_cloud_ray(c, d, make_cloud_march(c, light), phase_for_droplet(20),
                                               default_octaves(), glm::dvec3(40, 40, -50), glm::dvec3(0, 0, 1), 20.0);
  EXPECT_EQ(s2.transmittance, 1.0f);
}

TEST(CloudPhase, DropletPhaseIntegratesToOneAndPeaksForward) {
  for (float d : {5.0f, 12.0f, 20.0f, 50.0f}) {
    const twin::CloudPhase p = phase_for_droplet(d);
    // Quadrature in theta with points crowded at the forward peak.
    double sum = 0.0;
    const int N = 400000;
    for (int i = 0; i < N; ++i) {
      const double u = (i + 0.5) / N;
      const double theta = M_PI * u * u * u;  // dense near 0
      const double dtheta = M_PI * 3.0 * u * u / N;
      sum += twin::cloud_phase(p, float(std::cos(theta)), 1.0f) * 2.0 * M_PI * std::sin(theta) * dtheta;
    }
    std::printf("d = %4.1f um: integral %.5f, p(0) %.1f, p(180) %.4f /sr\n", d, sum,
                double(twin::cloud_phase(p, 1.0f, 1.0f)), double(twin::cloud_phase(p, -1.0f, 1.0f)));
    EXPECT_NEAR(sum, 1.0, 2e-3);
    EXPECT_GT(twin::cloud_phase(p, 1.0f, 1.0f), 100.0f * twin::cloud_phase(p, 0.0f, 1.0f));
  }
}

}  // namespace
