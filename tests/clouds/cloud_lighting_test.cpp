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

TEST(CloudLighting, AmbientAndLightDepthsAgreeForTheSameDirection) {
  const CloudVolume c = random_cloud(10, 30.0f, 5);
  const LightDepths d = compute_light_depths(c, glm::dvec3(0, 0, 1));  // the Sun at the zenith
  double worst = 0.0;
  for (size_t i = 0; i < d.tau.size(); ++i) worst = std::max(worst, double(std::abs(d.tau[i].x - d.tau[i].y)));
  EXPECT_LT(worst, 1e-6);
  // Down from the top layer's centre crosses the whole column.
  EXPECT_GT(d.tau[d.index(5, 5, 8)].z, d.tau[d.index(5, 5, 2)].z);
}

TEST(CloudLighting, RotatedGridSeesTheLightInItsOwnAxes) {
  CloudVolume c = random_cloud(10, 30.0f, 7);
  c.rotation = glm::angleAxis(glm::radians(90.0), glm::dvec3(1, 0, 0));  // grid y -> ENU up
  const glm::vec3 g = grid_direction(c, glm::dvec3(0, 0, 1));
  EXPECT_NEAR(g.y, 1.0f, 1e-6f);
  EXPECT_NEAR(std::abs(g.x) + std::abs(g.z), 0.0f, 1e-6f);
}

// A homogeneous slab: transmittance through it and the single-scattered light
// against a fine double-precision integral of the model (same phase, same
// optical depths computed analytically for the slab).
TEST(CloudLighting, MarchMatchesFineQuadratureOfTheModel) {
  const int n = 16;
  CloudVolume c;
  c.voxel_size_m = 10.0f;
  c.density = DenseGrid(n, n, n);
  for (int z = 1; z < n - 1; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) c.density.at(x, y, z) = 0.5f;
  c.optics.extinction_per_m = 0.02f;
  const LightDepths depths = compute_light_depths(c, glm::dvec3(0, 0, 1));
  CloudLight light;
  light.direction_enu = glm::dvec3(0, 0, 1);
  light.illuminance_lux = glm::dvec3(1e5);
  light.sky_radiance = glm::dvec3(5000.0);
  light.ground_radiance = glm::dvec3(1000.0);
  const twin::CloudPhase phase = phase_for_droplet(20.0f);
  for (const twin::CloudOctaves& oc : {single_scattering_octaves(), default_octaves()}) {
    const twin::CloudMarch m = make_cloud_march(c, light, 0.25f, 4096);
    // Looking up from below the centre: through the slab towards the Sun.
    const glm::dvec3 eye(80.0, 80.0, -100.0);
    const twin::CloudSample s = march_cloud_ray(c, depths, m, phase, oc, eye, glm::dvec3(0, 0, 1), 1e9);
    // The model along z (density as the trilinear interpolant of the grid:
    // 0 at z=0.5 voxels... constant 0.5 between centres 1.5 and 14.5).
    auto rho = [&](double z_vox) {
      const double p = z_vox - 0.5;
      const double a = std::clamp(p - 0.0, 0.0, 1.0), b = std::clamp(p - (n - 2), 0.0, 1.0);
      return 0.5 * (a - b);
    };
    const int fine = 200000;
    const double dz = n / double(fine);
    double tau_eye = 0.0, L = 0.0;
    std::vector<double> rho_z(fine);
    for (int i = 0; i < fine; ++i) rho_z[i] = rho((i + 0.5) * dz);
    std::vector<double> tau_above(fine);
    double acc = 0.0;
    for (int i = fine - 1; i >= 0; --i) {
      tau_above[i] = acc + 0.5 * rho_z[i] * dz * c.voxel_size_m * c.optics.extinction_per_m;
      acc += rho_z[i] * dz * c.voxel_size_m * c.optics.extinction_per_m;
    }
    const double tau_total = acc;
    double acc_below = 0.0;
    for (int i = 0; i < fine; ++i) {
      const double sigma_t = rho_z[i] * c.optics.extinction_per_m;
      const double tau_below = acc_below + 0.5 * rho_z[i] * dz * c.voxel_size_m * c.optics.extinction_per_m;
      const double J = twin::cloud_light_octaves(phase, oc, float(tau_above[i]), 1.0f);
      const glm::vec3 amb = twin::cloud_ambient(oc, glm::vec3(light.sky_radiance), glm::vec3(light.ground_radiance),
                                                float(tau_above[i]), float(tau_below));
      const double source = c.optics.albedo * sigma_t * (1e5 * J + amb.x);
      L += std::exp(-tau_eye) * source * dz * c.voxel_size_m;
      tau_eye += sigma_t * dz * c.voxel_size_m;
      acc_below += rho_z[i] * dz * c.voxel_size_m * c.optics.extinction_per_m;
    }
    const double rel = std::abs(s.radiance.x - L) / L;
    std::printf("octaves %d: march %.6g cd/m2, quadrature %.6g, rel %.2e; T %.6f vs %.6f\n", oc.count,
                double(s.radiance.x), L, rel, double(s.transmittance), std::exp(-tau_total));
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
