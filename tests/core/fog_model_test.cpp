// The fog model's special functions and tables (core/fog) against values
// computed independently (the digest of Sun et al. 2005, double precision
// SciPy: F(u, v) and G_0, G_20), and the float twin of the shared GLSL
// (atmo_fog_lights.glsl) against the same formula in double with exact Ghat.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/fog/fog_model.h"
#include "core/fog/fog_twin.h"

namespace {

using namespace atmo::fog;
constexpr double kPi = 3.14159265358979323846;

// The paper's F(u, v) from Ghat: F(u, pi/2) - F(u, v) = exp(-u tan v) Ghat(u, v), F(u, 0) = 0.
double paper_f(double u, double v) { return ghat(u, 0.0, 0.0) - std::exp(-u * std::tan(v)) * ghat(u, v, 0.0); }

TEST(FogSpecialFunction, MatchesTheDigestsGoldenValuesOfF) {
  struct Case { double u, v, f; };
  const Case cases[] = {{0.1, kPi / 2, 1.2910047283}, {1.0, kPi / 2, 0.6214496242}, {10.0, kPi / 2, 0.0981910350},
                        {1.0, 1.2, 0.6150868050},     {3.0, 1.2, 0.2919415871},   {0.5, 0.3, 0.2782776998},
                        {5.0, 0.8, 0.1876710613}};
  for (const Case& c : cases) {
    const double f = paper_f(c.u, c.v);
    std::printf("F(%g, %g) = %.10f, expected %.10f, rel. error %.2e\n", c.u, c.v, f, c.f, std::abs(f / c.f - 1.0));
    EXPECT_NEAR(f, c.f, 1e-8 * c.f);
  }
}

TEST(FogSpecialFunction, IsotropicLimitsAndPhaseNormalisation) {
  for (double v : {0.0, 0.3, 1.0, 1.5}) EXPECT_NEAR(ghat(0.0, v, 0.0), kPi / 2 - v, 1e-9);
  // Ghat(0, 0) = integral_0^{pi/2} 4 pi p(2 xi) d xi = (1/2) integral_0^pi 4 pi p(a) da — not 1; but the
  // phase integrates to 1 over the sphere for any g: 2 pi int p(a) sin a da = 1.
  for (double g : {0.0, 0.5, 0.85, 0.95}) {
    double sum = 0.0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
      const double a = kPi * (i + 0.5) / n;
      sum += 2.0 * kPi * henyey_greenstein(std::cos(a), g) * std::sin(a) * kPi / n;
    }
    EXPECT_NEAR(sum, 1.0, 2e-4) << "g = " << g;
  }
  // Ghat falls with u and with v, and u Ghat reaches its limit.
  EXPECT_GT(ghat(0.5, 0.2, 0.85), ghat(1.0, 0.2, 0.85));
  EXPECT_GT(ghat(0.5, 0.2, 0.85), ghat(0.5, 0.4, 0.85));
  EXPECT_NEAR(1e5 * ghat(1e5, 0.7, 0.85), ghat_u_limit(0.7, 0.85), 1e-3 * ghat_u_limit(0.7, 0.85));
  EXPECT_EQ(ghat(3.0, kPi / 2, 0.85), 0.0);
}

TEST(FogSurfaceFunction, MatchesTheDigestsValuesOfG0AndG20) {
  struct Case { double t, theta, n, g; };
  const Case cases[] = {{0.0, 0.0, 1, 8.0763949},    {1.0, 0.0, 1, 1.76668},       {1.0, kPi / 4, 1, 1.34469},
                        {1.0, kPi / 2, 1, 0.466512}, {1.0, 3 * kPi / 4, 1, 0.232498}, {1.0, kPi, 1, 0.193805},
                        {0.1, 0.0, 1, 6.51274},      {2.0, 0.0, 1, 0.510392},      {5.0, 0.0, 1, 0.0165913},
                        {10.0, 0.0, 1, 7.49756e-5},  {1.0, 0.0, 20, 0.734079},     {1.0, kPi / 4, 20, 0.0941385},
                        {1.0, kPi / 2, 20, 0.0300951}, {0.1, 0.0, 20, 2.22461}};
  for (const Case& c : cases) {
    const double g = surface_g(c.t, c.theta, c.n, 0.0);
    std::printf("G_%g(%g, %.4f) = %.6g, expected %.6g, rel. error %.1e\n", c.n, c.t, c.theta, g, c.g,
                std::abs(g / c.g - 1.0));
    EXPECT_NEAR(g, c.g, 2e-4 * c.g);
  }
}

// The stable closed form in double with exact Ghat: the twin's formula without tables or float.
double airlight_exact(double beta, double distance, double cos_gamma, double d_vp, double g) {
  const double sg = std::sqrt(std::max(1.0 - cos_gamma * cos_gamma, 0.0));
  const double gamma = std::atan2(sg, cos_gamma);
  const double h = distance * sg;
  const double near_term = std::exp(-beta * distance) * ghat(beta * h, 0.5 * gamma, g);
  double far_term = 0.0;
  if (std::isfinite(d_vp)) {
    const double along = d_vp - distance * cos_gamma;
    const double v1 = 0.25 * kPi + 0.5 * std::atan2(along, h);
    far_term = std::exp(-beta * (d_vp + std::hypot(along, h))) * ghat(beta * h, v1, g);
  }
  return beta / (2.0 * kPi * h) * (near_term - far_term);
}

TEST(FogAirlight, TheStableFormMatchesTheDigestsBruteForceValues) {
  struct Case { double beta, d, gamma_deg, d_vp, la; };
  const Case cases[] = {{0.05, 20, 30, INFINITY, 2.05958400e-4}, {0.05, 20, 30, 10, 5.73821770e-5},
                        {0.1, 10, 90, INFINITY, 1.53827201e-4},  {0.02, 100, 5, 150, 5.60245729e-5},
                        {0.2, 10, 150, INFINITY, 4.02228292e-5}, {0.01, 50, 1, INFINITY, 1.67822825e-3},
                        {0.5, 10, 60, 4, 7.14385933e-6}};
  for (const Case& c : cases) {
    const double la = airlight_exact(c.beta, c.d, std::cos(c.gamma_deg * kPi / 180), c.d_vp, 0.0);
    std::printf("La(beta %g, D %g, gamma %g, Dvp %g) = %.8e, expected %.8e, rel. error %.1e\n", c.beta, c.d,
                c.gamma_deg, c.d_vp, la, c.la, std::abs(la / c.la - 1.0));
    EXPECT_NEAR(la, c.la, 1e-6 * c.la);
  }
}

// The float twin with the 64 x 64 table against the exact stable form, over
// optical thickness 0.01..20 and the whole sphere of angles, with and without
// a surface on the ray: finite, non-negative, and within the table's error.
TEST(FogAirlight, TheTwinWithTheDefaultTableIsStableOverTheWholeSphere) {
  const double g = 0.85;
  const FogTable table = build_airlight_table(64, g);
  double worst_front = 0.0, worst_back = 0.0;
  for (double t_sv : {0.01, 0.1, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0}) {
    for (double gamma_deg : {0.5, 2.0, 10.0, 45.0, 90.0, 135.0, 170.0, 178.0, 179.9}) {
      for (double d_vp_factor : {double(INFINITY), 2.0, 0.5}) {
        const double beta = 0.01, d = t_sv / beta, cg = std::cos(gamma_deg * kPi / 180);
        const double d_vp = d * d_vp_factor;
        const double exact = airlight_exact(beta, d, cg, d_vp, g);
        const float twin = twin::atmo_fog_airlight(table, 64.0f, float(beta), float(d), float(cg),
                                                   std::isfinite(d_vp) ? float(d_vp) : twin::ATMO_FOG_FAR, 0.0f);
        ASSERT_TRUE(std::isfinite(twin) && twin >= 0.0f) << t_sv << " " << gamma_deg;
        const double rel = std::abs(twin / exact - 1.0);
        (gamma_deg <= 90 ? worst_front : worst_back) = std::max(gamma_deg <= 90 ? worst_front : worst_back, rel);
      }
    }
  }
  std::printf("64x64 twin vs exact stable form: worst relative error %.2f %% (gamma <= 90 deg), %.2f %% (> 90 deg)\n",
              100 * worst_front, 100 * worst_back);
  EXPECT_LT(worst_front, 0.05);
  EXPECT_LT(worst_back, 0.05);  // the paper's form is wrong by 20x-175x here (docs/FOG.md)
}

TEST(FogAirlight, LimitsNoFogNoSurfaceDistanceAndAngle) {
  const FogTable table = build_airlight_table(64, 0.85);
  using twin::atmo_fog_airlight;
  EXPECT_EQ(atmo_fog_airlight(table, 64.f, 0.f, 100.f, 0.9f, twin::ATMO_FOG_FAR, 0.f), 0.f);  // no fog, no glow
  EXPECT_EQ(atmo_fog_airlight(table, 64.f, 0.01f, 100.f, 0.9f, 0.f, 0.f), 0.f);              // surface at the eye
  float previous = 0.f;
  for (float d_vp : {10.f, 50.f, 100.f, 200.f, 1000.f, twin::ATMO_FOG_FAR}) {  // grows with the open ray
    const float la = atmo_fog_airlight(table, 64.f, 0.01f, 100.f, 0.9f, d_vp, 0.f);
    EXPECT_GE(la, previous);
    previous = la;
  }
  previous = INFINITY;
  for (float deg : {0.1f, 1.f, 5.f, 20.f, 60.f, 120.f, 179.f}) {  // falls off with angle from the light
    const float la = atmo_fog_airlight(table, 64.f, 0.01f, 100.f, std::cos(deg * 3.14159265f / 180), twin::ATMO_FOG_FAR, 0.f);
    EXPECT_LT(la, previous) << deg;
    previous = la;
  }
  // Exactly on the light, and very dense or very thin fog: finite, non-negative.
  for (float beta : {1e-7f, 1e-3f, 0.1f, 10.f, 1000.f}) {
    for (float cg : {1.f, -1.f, 0.f}) {
      const float la = atmo_fog_airlight(table, 64.f, beta, 100.f, cg, twin::ATMO_FOG_FAR, 1e-4f);
      EXPECT_TRUE(std::isfinite(la) && la >= 0.f) << beta << " " << cg;
    }
  }
}

TEST(FogGlowBound, BoundsTheAirlightAndShrinksWithDistance) {
  const double g = 0.85, beta = 0.0075, albedo = 0.999;
  const GlowBound bound(g);
  const FogTable table = build_airlight_table(64, g);
  for (double d : {30.0, 300.0, 1000.0}) {
    const double threshold = 1e-3, intensity = 2000.0;
    const double r = bound.radius_rad(beta, albedo, d, intensity, threshold);
    // Outside the radius the (table) airlight is below the threshold.
    for (double gamma = r + 1e-3; gamma < kPi; gamma += 0.01) {
      const double la = albedo * intensity *
                        twin::atmo_fog_airlight(table, 64.f, float(beta), float(d), float(std::cos(gamma)),
                                                twin::ATMO_FOG_FAR, 0.f);
      ASSERT_LT(la, threshold * 1.02) << "D " << d << " gamma " << gamma << " radius " << r;
    }
  }
  EXPECT_GT(bound.radius_rad(beta, albedo, 100, 2000, 1e-3), bound.radius_rad(beta, albedo, 1000, 2000, 1e-3));
  EXPECT_EQ(bound.radius_rad(0.0, albedo, 100, 2000, 1e-3), 0.0);
}

}  // namespace

// The fog pass's per-ray functions (fog_medium.frag calls them from atmo_fog_lights.glsl), through the twin:
// the length below the fog top against a midpoint count along the ray, the transmittance and the P1 radiance
// against their formulas written out here.
TEST(FogPassTwin, RayLengthBelowTheTopMatchesACountAlongTheRay) {
  struct Case { float d, dir_z, top; };
  const Case cases[] = {{1000, 0.5f, 100},  {150, 0.5f, 100},    {1000, -0.3f, 100}, {1000, 0.0f, 100},
                        {1000, -0.5f, -100}, {150, -0.5f, -100}, {1000, 0.4f, -100}, {1000, 0.0f, -100},
                        {500, 1.0f, 20},    {500, -1.0f, -499},  {500, -1.0f, -501}};
  for (const Case& c : cases) {
    const int n = 200000;
    int below = 0;
    for (int i = 0; i < n; ++i) below += (i + 0.5) / n * c.d * c.dir_z < c.top;
    const double counted = c.d * below / n;
    const float got = twin::atmo_fog_ray_length(c.d, c.dir_z, c.top);
    std::printf("[ fog pass ] d %6.0f m, dir_z %+5.2f, top %+5.0f m: length below the top %8.3f m (count %8.3f m)\n",
                c.d, c.dir_z, c.top, got, counted);
    EXPECT_NEAR(got, counted, 1e-5 * c.d + 1e-3);
  }
  EXPECT_EQ(twin::atmo_fog_ray_length(1234.0f, 0.7f, kNoTop), 1234.0f);  // no top: the whole ray
  EXPECT_EQ(twin::atmo_fog_ray_length(twin::ATMO_FOG_FAR, 0.7f, kNoTop), twin::ATMO_FOG_FAR);
}

TEST(FogPassTwin, TransmittanceAndDiffusionRadiance) {
  EXPECT_NEAR(twin::atmo_fog_transmittance(0.01f, 100.0f), std::exp(-1.0), 1e-7);
  EXPECT_EQ(twin::atmo_fog_transmittance(0.0f, twin::ATMO_FOG_FAR), 1.0f);   // no fog, open sky: not NaN
  EXPECT_EQ(twin::atmo_fog_transmittance(1e-3f, twin::ATMO_FOG_FAR), 0.0f);  // 1e6 m of it
  // (F + 3 flux . dir) / 4 pi per channel, floored at 0: channel 0 sees the light ahead, channel 1 behind it.
  const glm::vec3 fluence(1.0f, 2.0f, 0.5f);
  const glm::mat3 flux(glm::vec3(0.2f, 0.0f, 0.0f), glm::vec3(-0.8f, 0.0f, 0.0f), glm::vec3(0.0f, 0.1f, 0.0f));
  const glm::vec3 dir(0.6f, 0.8f, 0.0f);
  const glm::vec3 l = twin::atmo_fog_diffusion_radiance(fluence, flux, dir);
  const double expected[3] = {(1.0 + 3.0 * 0.2 * 0.6) / (4.0 * kPi), std::max((2.0 - 3.0 * 0.8 * 0.6) / (4.0 * kPi), 0.0),
                              (0.5 + 3.0 * 0.1 * 0.8) / (4.0 * kPi)};
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(l[c], expected[c], 1e-6) << "channel " << c;
  const glm::mat3 against(glm::vec3(-1.0f, 0.0f, 0.0f), glm::vec3(0.0f), glm::vec3(0.0f));
  EXPECT_EQ(twin::atmo_fog_diffusion_radiance(glm::vec3(1.0f, 0.0f, 0.0f), against, glm::vec3(1.0f, 0.0f, 0.0f)).x, 0.0f);
  const glm::vec3 m = twin::atmo_fog_medium_light(0.25f, glm::vec3(10.0f), fluence, flux, dir);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(m[c], 0.75 * (10.0 + expected[c]), 1e-5) << "channel " << c;
}
