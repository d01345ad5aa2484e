// The plugin's model of fog lit by a point light — the glow pass's single-scattering airlight plus the fog
// pass's diffusion (P1) term with its handover (atmo_fog_diffusion_light, host_sdk/include/atmo/
// atmo_fog_lights.glsl, through the C++ twin) — against the all-orders Monte Carlo of tools/fog_reference.
// Unbounded fog, g = 0.85, albedo 0.99, an omnidirectional 1 cd light at distance D from the eye, no surface
// on the view ray. Prints the relative error of single scattering alone and of the model per optical-
// thickness band, and checks that single scattering fails in thick fog and that the handover recovers most
// of it. The full grid, the fit of the handover and where the model stays off:
// docs/measurements/fog_multiple_scattering.md (tools/fog_reference/fog_handover_fit.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "core/fog/fog_model.h"
#include "core/fog/fog_twin.h"
#include "fog_reference.h"

namespace fr = atmo::fog_reference;
namespace fog = atmo::fog;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kBeta = 0.01;  // 1/m
constexpr double kG = 0.85;
constexpr double kAlbedo = 0.99;  // < 1: the Monte Carlo's multiple part converges (docs/measurements)
// The Monte Carlo's seeds (per case: kSeed + 1000 * (100 T) + gamma). The bounds were checked with 7001, 9001
// and 31337 (-DATMO_FOG_MS_SEED=...).
#ifndef ATMO_FOG_MS_SEED
#define ATMO_FOG_MS_SEED 7001
#endif
constexpr uint64_t kSeed = ATMO_FOG_MS_SEED;

struct Case {
  double thickness, gamma_deg;
  uint64_t paths;
};

struct Row {
  Case c;
  double mc = 0, mc_se = 0, ss = 0, model = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The signed value of largest magnitude.
double worst(const std::vector<double>& v) {
  double w = 0;
  for (double x : v)
    if (std::abs(x) > std::abs(w)) w = x;
  return w;
}

}  // namespace

TEST(FogMultipleScattering, ModelAgainstMonteCarlo) {
  // Paths per case: ~3-12 % standard error, ~2.3e6 paths in all. Off-axis radiance in thick fog comes from
  // rare paths passing near the light and converges slowly: the cases are those where the Monte Carlo
  // converges within the budget (the full grid: docs/measurements/fog_multiple_scattering.csv).
  const Case cases[] = {
      {0.5, 10, 16384},  {0.5, 30, 16384},  {0.5, 60, 65536},   {0.5, 90, 65536},
      {1, 2, 16384},     {1, 30, 16384},    {1, 90, 131072},
      {2, 2, 16384},     {2, 10, 16384},    {2, 30, 131072},    {2, 150, 196608},
      {4, 10, 65536},    {4, 30, 131072},   {4, 90, 196608},
      {8, 2, 32768},     {8, 30, 196608},   {8, 60, 262144},
      {16, 2, 393216},   {16, 60, 393216},
  };
  fog::FogOptics optics;
  optics.extinction_per_m = kBeta;
  optics.albedo = kAlbedo;
  optics.phase_g = kG;
  const fog::FogTable table = fog::build_airlight_table(64, kG);  // the plugin's default size
  // make_fog_frame's diffusion vector for an unbounded fog (no cap).
  const glm::vec4 diffusion(static_cast<float>(optics.transport_per_m()),
                            static_cast<float>(optics.diffusion_decay_per_m(INFINITY)),
                            static_cast<float>(fog::kHandoverRate), 1.0e30f);
  fr::Medium medium;
  medium.extinction_per_m = kBeta;
  medium.albedo = kAlbedo;
  medium.hg_g = kG;
  const fr::Light light;  // 1 cd at the origin, omnidirectional

  const auto t0 = std::chrono::steady_clock::now();
  std::vector<Row> rows;
  std::printf("[ measured ]     T  gamma     paths   mc_total  se/mc   ss/mc  model/mc\n");
  for (const Case& c : cases) {
    Row r{c};
    const double D = c.thickness / kBeta, gamma = c.gamma_deg * kPi / 180.0;
    const glm::dvec3 eye(D, 0, 0), dir(-std::cos(gamma), std::sin(gamma), 0);
    const fr::MonteCarloResult mc = fr::monte_carlo_radiance(
        medium, light, eye, dir, INFINITY, c.paths, kSeed + static_cast<uint64_t>(c.thickness * 100) * 1000 +
                                                       static_cast<uint64_t>(c.gamma_deg), 2000, 2);
    r.mc = mc.total;
    r.mc_se = mc.total_std_error;
    r.ss = fr::single_scattering_radiance(medium, light, eye, dir, INFINITY, 1e-8);
    // The glow pass: the airlight per cd times albedo (and intensity 1).
    const double airlight = kAlbedo * fog::twin::atmo_fog_airlight(table, 64.0f, static_cast<float>(kBeta),
                                                                   static_cast<float>(D),
                                                                   static_cast<float>(std::cos(gamma)), fog::kNoTop,
                                                                   0.0f);
    // The fog pass: the field at the eye seen along the ray through the whole visible depth (the twin).
    const double medium_radiance = fog::twin::atmo_fog_pass_one_light(
        diffusion, static_cast<float>(kBeta), static_cast<float>(D), static_cast<float>(std::cos(gamma)));
    r.model = airlight + medium_radiance;
    std::printf("[ measured ] %5g  %5g  %8llu  %.3e  %5.3f  %6.3f  %6.3f\n", c.thickness, c.gamma_deg,
                static_cast<unsigned long long>(c.paths), r.mc, r.mc_se / r.mc, r.ss / r.mc, r.model / r.mc);
    rows.push_back(r);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  struct Band {
    const char* name;
    double lo, hi;
    std::vector<double> ss, model, se;
  };
  Band bands[] = {{"thin   T <= 1    ", 0, 1, {}, {}, {}},
                  {"medium 1 < T <= 4", 1, 4, {}, {}, {}},
                  {"thick  T > 4     ", 4, 1e9, {}, {}, {}}};
  for (const Row& r : rows) {
    for (Band& b : bands) {
      if (r.c.thickness > b.lo && r.c.thickness <= b.hi) {
        b.ss.push_back(r.ss / r.mc - 1.0);
        b.model.push_back(r.model / r.mc - 1.0);
        b.se.push_back(r.mc_se / r.mc);
      }
    }
  }
  std::printf("[ measured ] relative error vs the Monte Carlo total (handover rate %.4g; %.1f s)\n",
              fog::kHandoverRate, seconds);
  std::printf("[ measured ] band               n   SS alone: median  worst   SS+diffusion: median  worst   "
              "MC se: median  worst\n");
  for (const Band& b : bands) {
    std::printf("[ measured ] %s  %2zu          %+6.3f  %+6.3f               %+6.3f  %+6.3f          %5.3f  %5.3f\n",
                b.name, b.ss.size(), median(b.ss), worst(b.ss), median(b.model), worst(b.model), median(b.se),
                *std::max_element(b.se.begin(), b.se.end()));
  }

  // The Monte Carlo's own precision. Its error has a heavy tail (a rare path passing near the light can
  // double a case's estimate, and its standard error with it), so the checks below are on band medians, and
  // the per-case envelope allows for 2 standard errors.
  std::vector<double> se_rel;
  for (const Row& r : rows) se_rel.push_back(r.mc_se / r.mc);
  EXPECT_LT(median(se_rel), 0.12);

  // |ln(model / mc)| and |ln(ss / mc)| per band.
  std::vector<double> log_model[3], log_ss[3];
  for (const Row& r : rows) {
    const int b = r.c.thickness > 4 ? 2 : r.c.thickness > 1 ? 1 : 0;
    log_model[b].push_back(std::abs(std::log(r.model / r.mc)));
    log_ss[b].push_back(std::abs(std::log(r.ss / r.mc)));
  }
  auto largest = [](const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); };
  for (int b = 0; b < 3; ++b)
    std::printf("[ measured ] %s  |ln(x / mc)|: SS median %.3f, model median %.3f worst %.3f\n", bands[b].name,
                median(log_ss[b]), median(log_model[b]), largest(log_model[b]));

  // Single scattering alone misses most of the light beyond T ~ 2 (the multiple part grows with T, the single
  // part falls like e^{-T}): below 10 % of the total at every thick case, and the medium band's median error
  // is beyond -80 %.
  for (double e : bands[2].ss) EXPECT_LT(e, -0.9);
  EXPECT_LT(median(bands[1].ss), -0.8);
  // The model (SS + the diffusion term with the fitted handover) recovers most of it. The bounds are the
  // figures measured on these cases with three seeds (docs/measurements/fog_multiple_scattering.md, "Test":
  // median |ln(model / mc)| thick 0.41 / 0.41 / 0.30, medium 0.61 / 0.50 / 0.60, thin 0.25 / 0.40 / 0.29 with
  // seeds 7001 / 9001 / 31337), each seed's largest plus 0.05. Rate 0 fails the thick band; the former handover
  // (fluence and flux both 1 - exp(-0.5 T)) fails the T = 2, 150 deg case (0.014).
  const double max_median_log[3] = {0.40 + 0.05, 0.61 + 0.05, 0.41 + 0.05};
  for (int b = 0; b < 3; ++b) {
    std::printf("[ measured ] %s  median |ln(model / mc)| %.3f <= %.2f\n", bands[b].name, median(log_model[b]),
                max_median_log[b]);
    EXPECT_LT(median(log_model[b]), max_median_log[b]) << bands[b].name;
  }
  EXPECT_LT(median(log_model[1]), 0.5 * median(log_ss[1]));
  EXPECT_LT(median(log_model[0]), median(log_ss[0]));
  // Every case within the envelope measured with seed 7001, model / mc from 0.204 (T = 4, 10 deg: the forward
  // lobe of the multiple scattering, which P1 cannot hold) to 2.43 (T = 4, 90 deg: the P1 cosine lobe spreads
  // that light sideways), widened to [0.18, 2.6] and by 2 standard errors of the Monte Carlo.
  double lowest = 1e30, highest = 0.0;
  for (const Row& r : rows) {
    lowest = std::min(lowest, r.model / r.mc);
    highest = std::max(highest, r.model / r.mc);
    EXPECT_GT(r.model, 0.18 * (r.mc - 2.0 * r.mc_se)) << "T " << r.c.thickness << " gamma " << r.c.gamma_deg;
    EXPECT_LT(r.model, 2.6 * (r.mc + 2.0 * r.mc_se)) << "T " << r.c.thickness << " gamma " << r.c.gamma_deg;
  }
  std::printf("[ measured ] model / mc over the cases: %.3f .. %.3f (envelope [0.18, 2.6] +- 2 se)\n", lowest,
              highest);
}
