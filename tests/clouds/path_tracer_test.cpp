// The cloud path tracer (tools/cloud_reference) against what must hold for
// any correct light transport: the white furnace, Beer-Lambert, the optically
// thin limit, single scattering against quadrature, absorption, determinism,
// and its phase-function sampler against twin::cloud_phase.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

#include <glm/gtc/quaternion.hpp>

#include "cloud_path_tracer.h"
#include "core/clouds/cloud_optics.h"

namespace {

using namespace atmo::clouds;
using namespace atmo::clouds::reference;

constexpr double kPi = 3.14159265358979323846;

// A dense heterogeneous blob: a sphere of radius ~10 voxels fading out, with
// lumpy density; tau through the centre ~7. Rotated and moved off the origin
// so the frame transforms are exercised.
CloudVolume blob(float albedo) {
  const int n = 24;
  CloudVolume c;
  c.name = "blob";
  c.voxel_size_m = 10.0f;
  c.density = DenseGrid(n, n, n);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double px = x + 0.5 - 12, py = y + 0.5 - 12, pz = z + 0.5 - 12;
        const double r = std::sqrt(px * px + py * py + pz * pz) / 10.5;
        const double fade = std::clamp((1.0 - r) * 4.0, 0.0, 1.0);
        const double lumps = 0.6 + 0.4 * std::sin(0.9 * x + 0.3) * std::cos(0.7 * y - 0.2 * z) * std::sin(0.5 * z + 1.1);
        c.density.at(x, y, z) = static_cast<float>(fade * lumps);
      }
  c.optics.extinction_per_m = 0.06f;
  c.optics.albedo = albedo;
  c.optics.droplet_diameter_um = 20.0f;
  c.origin_enu_m = glm::dvec3(1200.0, -300.0, 1500.0);
  c.rotation = glm::angleAxis(0.5, glm::normalize(glm::dvec3(0.2, 0.3, 1.0)));
  return c;
}

CloudVolume box(int nx, int ny, int nz, float density, float voxel_m, float extinction) {
  CloudVolume c;
  c.name = "box";
  c.voxel_size_m = voxel_m;
  c.density = DenseGrid(nx, ny, nz, density);
  c.optics.extinction_per_m = extinction;
  return c;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

TEST(PathTracerFurnace, WhiteFurnaceConservesRadiance) {
  const CloudVolume c = blob(1.0f);
  const double L = 1000.0;
  CloudEnvironment env;
  env.sky_radiance = env.ground_radiance = glm::dvec3(L);
  const glm::dvec3 centre = c.centre_enu_m();
  const glm::dvec3 d = glm::normalize(glm::dvec3(1.0, 0.3, -0.2));
  const glm::dvec3 side = glm::normalize(glm::cross(d, glm::dvec3(0, 0, 1)));
  struct Case {
    const char* name;
    glm::dvec3 origin, dir;
  };
  const Case cases[] = {
      {"centre", centre - 600.0 * d, d},
      {"grazing", centre - 600.0 * d + 95.0 * side, d},
      {"inside, up", centre, glm::dvec3(0, 0, 1)},
      {"inside, down", centre + glm::dvec3(20, -10, 0), glm::dvec3(0.1, 0.2, -1)},
  };
  const int samples = 65536;
  for (const Case& k : cases) {
    const auto t = std::chrono::steady_clock::now();
    const RayEstimate e = path_trace_ray(c, env, k.origin, k.dir, samples, 11, 100000);
    const double total = e.mean.x + e.transmittance * L;
    std::printf("furnace %-12s: in-scattered %8.3f +- %.3f, T %.5f, total %8.3f (expect %.0f, %+.3f %%, %.1f SE) %.2f s\n",
                k.name, e.mean.x, e.standard_error.x, e.transmittance, total, L, 100.0 * (total - L) / L,
                (total - L) / std::max(e.standard_error.x, 1e-12), seconds_since(t));
    EXPECT_LT(e.transmittance, 0.9) << k.name;  // the ray does cross cloud
    EXPECT_LT(std::abs(total - L), 3.0 * e.standard_error.x) << k.name;
    EXPECT_LT(std::abs(total - L), 0.01 * L) << k.name;
    EXPECT_EQ(e.mean.x, e.mean.y);  // a grey source gives grey light
  }
  // A ray that misses the grid box: nothing scattered, everything transmitted.
  const RayEstimate miss = path_trace_ray(c, env, centre - 600.0 * d + 400.0 * side, d, 1000, 11);
  std::printf("furnace miss        : in-scattered %g, T %g\n", miss.mean.x, miss.transmittance);
  EXPECT_EQ(miss.mean.x, 0.0);
  EXPECT_EQ(miss.transmittance, 1.0);
}

TEST(PathTracerTransmittance, HomogeneousBoxMatchesBeerLambert) {
  // Trilinear density fades to the zero border over the outer half voxel: an
  // axis ray through the interior sees density (c + 0.5) for c in [0, 0.5] at
  // each face, so its effective length is n - 0.25 voxels.
  CloudVolume c = box(10, 7, 9, 0.7f, 5.0f, 0.04f);
  c.origin_enu_m = glm::dvec3(-40.0, 25.0, 800.0);
  c.rotation = glm::angleAxis(0.7, glm::normalize(glm::dvec3(1.0, -0.4, 0.5)));
  const double sigma = 0.7 * 0.04;
  struct Case {
    const char* name;
    glm::dvec3 origin_index, dir_grid;
    double length_m;
  };
  const Case cases[] = {
      {"grid +x", {-3.0, 3.2, 4.7}, {1, 0, 0}, (10 - 0.25) * 5.0},
      {"grid -z", {6.1, 2.4, 20.0}, {0, 0, -1}, (9 - 0.25) * 5.0},
  };
  for (const Case& k : cases) {
    const glm::dvec3 o = c.origin_enu_m + c.rotation * (k.origin_index * double(c.voxel_size_m));
    const glm::dvec3 d = c.rotation * k.dir_grid;
    const double expected = std::exp(-sigma * k.length_m);
    const RayEstimate e = path_trace_ray(c, CloudEnvironment{}, o, d, 0, 1);
    const TransmittanceEstimate rt = ratio_tracking_transmittance(c, o, d, 2000000, 5);
    std::printf("transmittance %s: expected %.6f, path_trace_ray %.6f (%+.1e), ratio tracking %.6f +- %.6f (%+.1e)\n",
                k.name, expected, e.transmittance, e.transmittance - expected, rt.mean, rt.standard_error,
                rt.mean - expected);
    EXPECT_NEAR(e.transmittance, expected, 1e-6 * expected) << k.name;
    EXPECT_NEAR(rt.mean, expected, 1e-3) << k.name;
    EXPECT_NEAR(rt.mean, expected, 4.0 * rt.standard_error) << k.name;
  }
}

TEST(PathTracerThinLimit, MatchesSingleScatteringIntegral) {
  // tau = 0.005 along the ray: T ~ 1 and higher orders ~ tau, so the radiance is
  // E sigma_s phase(cos) times the effective length (n - 0.25 voxels, above).
  const int n = 16;
  const double length_m = n - 0.25;
  const float ext = static_cast<float>(0.005 / length_m);
  const CloudVolume c = box(n, n, n, 1.0f, 1.0f, ext);
  const twin::CloudPhase ph = phase_for_droplet(c.optics.droplet_diameter_um);
  const glm::dvec3 origin(-10.0, 8.0, 8.0), dir(1, 0, 0);
  for (double angle_deg : {30.0, 150.0}) {
    const double th = angle_deg * kPi / 180.0;
    CloudEnvironment env;
    env.light_direction = glm::dvec3(std::cos(th), 0.0, std::sin(th));
    env.light_illuminance_lux = glm::dvec3(1e5, 2e5, 5e4);
    const double expected = 1e5 * c.optics.albedo * double(ext) * twin::cloud_phase(ph, float(std::cos(th)), 1.0f) * length_m;
    const auto t = std::chrono::steady_clock::now();
    const RayEstimate e = path_trace_ray(c, env, origin, dir, 24000000, 3);
    std::printf("thin limit %5.1f deg: %.5f +- %.5f cd/m^2, single-scattering integral %.5f (%+.2f %%) T %.5f, %.2f s\n",
                angle_deg, e.mean.x, e.standard_error.x, expected, 100.0 * (e.mean.x / expected - 1.0), e.transmittance,
                seconds_since(t));
    EXPECT_NEAR(e.mean.x, expected, 0.02 * expected) << angle_deg;
    EXPECT_NEAR(e.mean.y / e.mean.x, 2.0, 1e-9);  // colour follows the light's
  }
}

TEST(PathTracerSingleScattering, MatchesQuadratureThroughThickCloud) {
  // max_scattering_orders = 1 on the dense blob: the light attenuated towards
  // the light (ratio tracking in next-event estimation) and along the eye ray
  // (delta tracking), against a fine quadrature of sigma_s T_eye T_light phase.
  const CloudVolume c = blob(0.95f);
  const twin::CloudPhase ph = phase_for_droplet(c.optics.droplet_diameter_um);
  CloudEnvironment env;
  env.light_direction = glm::normalize(glm::dvec3(-0.3, 0.5, 0.8));
  env.light_illuminance_lux = glm::dvec3(1e5);
  const glm::dvec3 d = glm::normalize(glm::dvec3(1.0, 0.3, -0.2));
  const glm::dvec3 side = glm::normalize(glm::cross(d, glm::dvec3(0, 0, 1)));
  const glm::dvec3 o = c.centre_enu_m() - 600.0 * d + 40.0 * side;
  const double phase = twin::cloud_phase(ph, float(glm::dot(env.light_direction, d)), 1.0f);
  // Quadrature: midpoints every 0.25 m over the 1200 m that cover the box.
  const glm::dquat to_grid = glm::conjugate(c.rotation);
  double sum = 0.0;
  const double dt = 0.25;
  for (double t = 0.5 * dt; t < 1200.0; t += dt) {
    const glm::dvec3 x = o + t * d;
    const glm::dvec3 p = (to_grid * (x - c.origin_enu_m)) / double(c.voxel_size_m);
    if (p.x < 0 || p.y < 0 || p.z < 0 || p.x > 24 || p.y > 24 || p.z > 24) continue;
    const double rho = c.density.sample(glm::vec3(p));
    if (rho <= 0.0) continue;
    const double t_eye = std::exp(-optical_depth(c, x, -d));
    const double t_light = std::exp(-optical_depth(c, x, env.light_direction));
    sum += c.optics.albedo * c.optics.extinction_per_m * rho * t_eye * t_light * dt;
  }
  const double expected = 1e5 * phase * sum;
  const RayEstimate e = path_trace_ray(c, env, o, d, 400000, 8, 1);
  std::printf("single scattering, thick: %.4f +- %.4f cd/m^2, quadrature %.4f (%+.2f %%, %.1f SE), T %.4f\n", e.mean.x,
              e.standard_error.x, expected, 100.0 * (e.mean.x / expected - 1.0),
              (e.mean.x - expected) / e.standard_error.x, e.transmittance);
  EXPECT_NEAR(e.mean.x, expected, std::max(3.0 * e.standard_error.x, 0.002 * expected));
  EXPECT_LT(e.standard_error.x, 0.01 * expected);
}

TEST(PathTracerEnergy, AbsorptionRemovesLight) {
  CloudEnvironment env;
  env.sky_radiance = env.ground_radiance = glm::dvec3(1000.0);
  const CloudVolume white = blob(1.0f), grey = blob(0.9f);
  const glm::dvec3 d = glm::normalize(glm::dvec3(1.0, 0.3, -0.2));
  const glm::dvec3 o = white.centre_enu_m() - 600.0 * d;
  const RayEstimate a = path_trace_ray(white, env, o, d, 8192, 21);
  const RayEstimate b = path_trace_ray(grey, env, o, d, 8192, 21);
  std::printf("energy: albedo 1 -> %.2f +- %.2f, albedo 0.9 -> %.2f +- %.2f cd/m^2 (T %.4f)\n", a.mean.x,
              a.standard_error.x, b.mean.x, b.standard_error.x, a.transmittance);
  EXPECT_LT(b.mean.x + 3.0 * (a.standard_error.x + b.standard_error.x), a.mean.x);
  EXPECT_EQ(a.transmittance, b.transmittance);
}

TEST(PathTracerDeterminism, SameSeedSameImageWhateverTheThreads) {
  // Rows are seeded by their index, so the thread count does not change the
  // image either: bit-identical for 1 and 2 threads; a new seed changes it.
  const CloudVolume c = blob(0.999f);
  CloudEnvironment env;
  env.light_direction = glm::normalize(glm::dvec3(0.4, -0.2, 0.9));
  env.light_illuminance_lux = glm::dvec3(1e5, 9e4, 8e4);
  env.sky_radiance = glm::dvec3(4000, 5000, 7000);
  env.ground_radiance = glm::dvec3(1500);
  PinholeCamera cam;
  cam.position_enu_m = c.centre_enu_m() + glm::dvec3(0.0, -600.0, 50.0);
  cam.forward = glm::dvec3(0, 1, -0.08);
  cam.up = glm::dvec3(0, 0, 1);
  cam.vertical_fov_rad = 0.45;
  cam.width = 32;
  cam.height = 24;
  PathTraceSettings s;
  s.samples_per_pixel = 16;
  s.threads = 2;
  const auto t = std::chrono::steady_clock::now();
  const CloudImage a = path_trace(c, env, cam, s);
  const double dt = seconds_since(t);
  const CloudImage b = path_trace(c, env, cam, s);
  s.threads = 1;
  const CloudImage one = path_trace(c, env, cam, s);
  s.threads = 2;
  s.seed = 2;
  const CloudImage other = path_trace(c, env, cam, s);
  const size_t bytes = a.radiance.size() * sizeof(glm::vec3);
  ASSERT_EQ(a.radiance.size(), 32u * 24u);
  EXPECT_EQ(std::memcmp(a.radiance.data(), b.radiance.data(), bytes), 0);
  EXPECT_EQ(std::memcmp(a.radiance.data(), one.radiance.data(), bytes), 0);
  EXPECT_EQ(a.transmittance, one.transmittance);
  EXPECT_NE(std::memcmp(a.radiance.data(), other.radiance.data(), bytes), 0);
  EXPECT_EQ(a.transmittance, other.transmittance);  // exact, not sampled
  double lit = 0.0, t_min = 1.0;
  for (size_t i = 0; i < a.radiance.size(); ++i) {
    lit = std::max(lit, double(a.radiance[i].x));
    t_min = std::min(t_min, double(a.transmittance[i]));
  }
  std::printf("determinism: 32x24 x 16 spp in %.3f s, brightest %.1f cd/m^2, min T %.4f\n", dt, lit, t_min);
  EXPECT_GT(lit, 0.0);
  EXPECT_LT(t_min, 0.1);
}

TEST(PathTracerPhase, SamplerMatchesCloudPhaseOverCosineBins) {
  // The sampler draws exactly from the phase function (no weights): the share
  // of directions in each cos-theta bin is 2 pi times cloud_phase's integral over it.
  const twin::CloudPhase ph = phase_for_droplet(20.0f);
  const glm::dvec3 fwd = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  constexpr int kBins = 20;
  const int n = 32000000;  // the smallest bin (7e-4) then has a 0.5 % standard error
  long count[kBins] = {};
  PathRng rng(99, 0);
  double worst_dir = 0.0;
  const auto t = std::chrono::steady_clock::now();
  for (int i = 0; i < n; ++i) {
    const PhaseSample s = sample_cloud_phase(ph, fwd, rng);
    worst_dir = std::max(worst_dir, std::abs(glm::dot(s.direction, fwd) - s.cos_theta) +
                                        std::abs(glm::length(s.direction) - 1.0));
    ++count[std::clamp(static_cast<int>((s.cos_theta + 1.0) * 0.5 * kBins), 0, kBins - 1)];
  }
  const double dt = seconds_since(t);
  EXPECT_LT(worst_dir, 1e-9);
  // cloud_phase's formula in double: the twin evaluates it in float, which
  // near the diffraction peak (1 + g^2 - 2 g cos ~ 3e-5) loses ~0.2 %, enough
  // for 32M samples to see in the last bin; the chi-square uses this one.
  auto hg = [](double g, double c) {
    const double d = 1.0 + g * g - 2.0 * g * c;
    return (1.0 - g * g) / (4.0 * kPi * d * std::sqrt(d));
  };
  auto phase_double = [&](double c) {
    const double g = ph.g_draine, a = ph.alpha_draine;
    return (1.0 - ph.w_draine) * hg(ph.g_hg, c) +
           ph.w_draine * hg(g, c) * (1.0 + a * c * c) / (1.0 + a * (1.0 + 2.0 * g * g) / 3.0);
  };
  std::printf("phase at cos 1: twin (float) %.3f, double %.3f /sr\n", twin::cloud_phase(ph, 1.0f, 1.0f), phase_double(1.0));
  double total = 0.0, chi2 = 0.0, worst = 0.0;
  for (int b = 0; b < kBins; ++b) {
    const double lo = -1.0 + 2.0 * b / kBins, width = 2.0 / kBins;
    // 2 pi times the integral of cloud_phase over the bin: midpoint rule on a
    // mesh graded towards the bin's top, mu = hi - width v^4, which resolves the
    // diffraction peak (width (1 - g_hg)^2 ~ 3e-5 in mu) in the last bin.
    const int m = 200000;
    double integral = 0.0, integral_double = 0.0;
    for (int j = 0; j < m; ++j) {
      const double v = (j + 0.5) / m, mu = lo + width - width * v * v * v * v, jac = 4.0 * v * v * v;
      integral += twin::cloud_phase(ph, float(mu), 1.0f) * jac;
      integral_double += phase_double(mu) * jac;
    }
    integral *= 2.0 * kPi * width / m;
    integral_double *= 2.0 * kPi * width / m;
    total += integral;
    const double est = double(count[b]) / n;
    const double expected_se = std::sqrt(integral_double * (1.0 - integral_double) / n);
    const double rel = est / integral - 1.0;
    chi2 += (est - integral_double) * (est - integral_double) / (expected_se * expected_se);
    worst = std::max(worst, std::abs(rel));
    std::printf("phase bin [%+.1f, %+.1f): sampled %.6f +- %.6f, cloud_phase %.6f (%+.2f %%), in double %.6f (%+.1f SE)\n",
                lo, lo + width, est, expected_se, integral, 100.0 * rel, integral_double,
                (est - integral_double) / expected_se);
    EXPECT_NEAR(est, integral, 0.02 * integral) << b;
  }
  std::printf("phase: %d samples in %.2f s, cloud_phase integrates to %.5f, worst bin %.2f %%, chi2 (vs double) %.1f over %d bins\n",
              n, dt, total, 100.0 * worst, chi2, kBins);
  EXPECT_NEAR(total, 1.0, 1e-3);
  EXPECT_LT(chi2, 45.0);  // 19 degrees of freedom: p ~ 1e-3
}

}  // namespace
