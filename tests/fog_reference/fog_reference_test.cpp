// Tests of the fog reference (tools/fog_reference): the airlight of Sun et al. 2005 against the
// golden values and closed-form limits of docs digest-001 (section 9), the surface term against the
// digest's G_0 / G_n values, cone and slab geometry against independent fixed-step quadrature, and the
// all-orders Monte Carlo against the deterministic single-scattering integral.
// Every test prints the error it measured ("[ measured ]" lines).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <vector>

#include "fog_reference.h"

namespace fr = atmo::fog_reference;
using glm::dvec3;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
double deg(double d) { return d * kPi / 180.0; }
double rel_err(double got, double want) { return std::abs(got - want) / std::abs(want); }

// A rotated, translated frame so that no test geometry is axis aligned (unbounded media only).
struct Frame {
  dvec3 origin{3.25, -1.5, 7.0};
  dvec3 ex, ey, ez;
  Frame() {
    const dvec3 axis = glm::normalize(dvec3(0.3, -0.8, 0.52));
    const double a = 0.9;  // Rodrigues rotation by a about axis
    auto rot = [&](const dvec3& v) {
      return v * std::cos(a) + glm::cross(axis, v) * std::sin(a) + axis * glm::dot(axis, v) * (1 - std::cos(a));
    };
    ex = rot(dvec3(1, 0, 0));
    ey = rot(dvec3(0, 1, 0));
    ez = rot(dvec3(0, 0, 1));
  }
};

// Airlight for an omni light at distance D from the eye, angle gamma between the view ray and the light.
double airlight(double beta, double D, double gamma, double d_vp, double g = 0.0, double albedo = 1.0,
                double intensity = 1.0, double rel_tol = 1e-8) {
  const Frame f;
  fr::Medium m;
  m.extinction_per_m = beta;
  m.hg_g = g;
  m.albedo = albedo;
  fr::Light light;
  light.position_m = f.origin + D * f.ex;
  light.intensity = intensity;
  const dvec3 dir = std::cos(gamma) * f.ex + std::sin(gamma) * f.ey;
  return fr::single_scattering_radiance(m, light, f.origin, dir, d_vp, rel_tol);
}

// Adaptive Simpson, relative tolerance against a first composite estimate.
double adaptive_simpson(const std::function<double(double)>& f, double a, double b, double rel) {
  double crude = 0;
  const int n = 64;
  for (int i = 0; i <= n; ++i) {
    const double x = a + (b - a) * i / n;
    crude += f(x) * ((i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2));
  }
  crude *= (b - a) / (3.0 * n);
  const double eps = rel * std::max(std::abs(crude), 1e-300);
  std::function<double(double, double, double, double, double, double, double, int)> rec =
      [&](double a0, double b0, double fa, double fm, double fb, double whole, double e, int depth) {
        const double m = 0.5 * (a0 + b0), lm = 0.5 * (a0 + m), rm = 0.5 * (m + b0);
        const double flm = f(lm), frm = f(rm);
        const double left = (m - a0) / 6 * (fa + 4 * flm + fm), right = (b0 - m) / 6 * (fm + 4 * frm + fb);
        const double delta = left + right - whole;
        if (depth <= 0 || std::abs(delta) <= 15 * e) return left + right + delta / 15;
        return rec(a0, m, fa, flm, fm, left, 0.5 * e, depth - 1) + rec(m, b0, fm, frm, fb, right, 0.5 * e, depth - 1);
      };
  double total = 0;  // 16 panels so that no feature hides between the first 5 nodes
  for (int i = 0; i < 16; ++i) {
    const double a0 = a + (b - a) * i / 16, b0 = a + (b - a) * (i + 1) / 16, m = 0.5 * (a0 + b0);
    const double fa = f(a0), fm = f(m), fb = f(b0);
    total += rec(a0, b0, fa, fm, fb, (b0 - a0) / 6 * (fa + 4 * fm + fb), eps / 16, 50);
  }
  return total;
}

// Exponential integral E_1(x), x > 0: series for x <= 1, continued fraction (modified Lentz) above.
double expint_e1(double x) {
  if (x <= 1.0) {
    double sum = 0, term = 1;
    for (int k = 1; k < 100; ++k) {
      term *= -x / k;
      sum += term / k;
      if (std::abs(term / k) < 1e-17 * std::abs(sum)) break;
    }
    return -0.57721566490153286061 - std::log(x) - sum;
  }
  double b = x + 1, c = 1e300, d = 1 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double a = -static_cast<double>(i) * i;
    b += 2;
    d = 1 / (a * d + b);
    c = b + a / c;
    const double del = c * d;
    h *= del;
    if (std::abs(del - 1) < 1e-16) break;
  }
  return h * std::exp(-x);
}

// Looking straight away from the light (gamma = pi), digest 9.B.3.
double airlight_backward_closed_form(double beta, double T, double T_vp) {
  auto h = [](double s) { return std::exp(-2 * s) / s - 2 * expint_e1(2 * s); };
  const double far = std::isinf(T_vp) ? 0.0 : std::exp(T) * h(T + T_vp);
  // e^T h(T) written without overflow: e^-T / T - 2 e^T E1(2T)
  return beta * beta / (4 * kPi) * (std::exp(-T) / T - 2 * std::exp(T) * expint_e1(2 * T) - far);
}

// Henyey-Greenstein written out here, independently of the library.
double hg(double mu, double g) { return (1 - g * g) / (4 * kPi * std::pow(1 + g * g - 2 * g * mu, 1.5)); }

// The same airlight by the paper's half-angle substitution (eq. 32; App. D with the phase function taken
// inside: the scattering angle is 2 xi), integrated independently.
double airlight_half_angle(double beta, double D, double gamma, double d_vp, double g = 0.0) {
  const double T = beta * D, sg = std::sin(gamma), cg = std::cos(gamma);
  const double v1 = std::isinf(d_vp) ? 0.5 * kPi : 0.25 * kPi + 0.5 * std::atan2(d_vp - D * cg, D * sg);
  const double A1 = T * sg;
  auto f = [&](double xi) { return 4 * kPi * hg(std::cos(2 * xi), g) * std::exp(-T * cg - A1 * std::tan(xi)); };
  return beta * beta / (2 * kPi * T * sg) * adaptive_simpson(f, 0.5 * gamma, v1, 1e-12);
}

void measured(const char* what, double value) { std::printf("[ measured ] %s = %.3e\n", what, value); }

// ------------------------------------------------------------------------------------------------
// 1. Golden airlight values, digest 9.B.1 (isotropic, I0 = 1, unbounded).
TEST(FogReferenceAirlight, GoldenValues) {
  struct Case {
    double beta, D, gamma_deg, d_vp, want;
  };
  const Case cases[] = {{0.05, 20, 30, kInf, 2.05958400e-4}, {0.05, 20, 30, 10, 5.73821770e-5},
                        {0.1, 10, 90, kInf, 1.53827201e-4},  {0.02, 100, 5, 150, 5.60245729e-5},
                        {0.2, 10, 150, kInf, 4.02228292e-5}, {0.01, 50, 1, kInf, 1.67822825e-3},
                        {0.5, 10, 60, 4, 7.14385933e-6}};
  double worst = 0;
  for (const Case& c : cases) {
    const double got = airlight(c.beta, c.D, deg(c.gamma_deg), c.d_vp);
    EXPECT_NEAR(got, c.want, 1e-6 * c.want) << "beta " << c.beta << " D " << c.D << " gamma " << c.gamma_deg;
    worst = std::max(worst, rel_err(got, c.want));
  }
  measured("golden airlight max relative error (values given to 9 digits)", worst);
}

// 2. gamma = pi against the closed form with E_1.
TEST(FogReferenceAirlight, BackwardClosedForm) {
  EXPECT_NEAR(airlight_backward_closed_form(1.0, 1.0, kInf), 8.11918612e-3, 1e-11);  // the helper itself
  double worst = 0;
  for (double beta : {0.1, 1.0}) {
    for (double T : {1e-3, 0.3, 1.0, 5.0, 20.0}) {
      for (double T_vp : {kInf, 0.1, 2.0}) {
        const double want = airlight_backward_closed_form(beta, T, T_vp);
        const double got = airlight(beta, T / beta, kPi, T_vp / beta);
        EXPECT_NEAR(got, want, 1e-7 * want) << "beta " << beta << " T " << T << " T_vp " << T_vp;
        worst = std::max(worst, rel_err(got, want));
      }
    }
  }
  EXPECT_NEAR(airlight(0.3, 1 / 0.3, kPi, kInf), 0.09 * 8.11918612e-3, 1e-6 * 0.09 * 8.11918612e-3);
  measured("gamma = pi vs closed form, max relative error", worst);
}

// 3. Total over the sphere, T_vp = inf.
TEST(FogReferenceAirlight, SphereTotal) {
  const double beta = 0.1, D = 10, T = beta * D;
  // (beta I0 / D) * integral_1^inf e^{-T mu} ln((mu+1)/(mu-1)) / mu dmu, with mu = 1 + s^2.
  auto mu_integrand = [T](double s) {
    if (s == 0) return 0.0;
    const double mu = 1 + s * s;
    return 2 * s * std::exp(-T * mu) * std::log((mu + 1) / (s * s)) / mu;
  };
  const double closed = beta / D * adaptive_simpson(mu_integrand, 0.0, 8.0, 1e-12);
  EXPECT_NEAR(closed, 4.3402016e-3, 1e-7 * 4.3402016e-3);
  // The airlight integrated over the sphere: 2 pi integral L_a(gamma) sin(gamma) dgamma.
  // gamma = u^2 smooths the gamma ln(gamma) behaviour of sin(gamma) L_a at the light.
  auto ring = [&](double u) {
    return 4 * kPi * u * std::sin(u * u) * airlight(beta, D, u * u, kInf, 0, 1, 1, 1e-11);
  };
  const double sphere = adaptive_simpson(ring, 0.0, std::sqrt(kPi), 1e-9);
  EXPECT_NEAR(sphere, closed, 1e-7 * closed);
  // The same through the library's hemisphere integral (Phong exponent 0) about +-axis.
  const Frame f;
  fr::Medium m;
  m.extinction_per_m = beta;
  fr::Light light;
  light.position_m = f.origin + D * f.ex;
  const dvec3 axis = glm::normalize(0.3 * f.ex + 0.8 * f.ey - 0.2 * f.ez);
  const double hemis = fr::surface_scattered_phong(m, light, f.origin, axis, 0.0, 1e-7) +
                       fr::surface_scattered_phong(m, light, f.origin, -axis, 0.0, 1e-7);
  EXPECT_NEAR(hemis, closed, 1e-6 * closed);
  measured("sphere total (1D gamma quadrature) relative error", rel_err(sphere, 4.3402016e-3));
  measured("sphere total (two hemispheres, library) relative error", rel_err(hemis, closed));
}

// 4. Scaling, linearity, the phase function.
TEST(FogReferenceAirlight, ScalingAndLinearity) {
  double worst = 0;
  for (double gamma : {deg(0.5), deg(40), deg(120)}) {
    for (double d_vp : {kInf, 7.0}) {
      const double base = airlight(0.2, 10, gamma, d_vp);
      for (double s : {0.1, 3.0, 250.0}) {
        const double scaled = airlight(0.2 / s, 10 * s, gamma, d_vp * s);
        EXPECT_NEAR(scaled * s * s, base, 1e-8 * base);
        worst = std::max(worst, rel_err(scaled * s * s, base));
      }
      const double bright = airlight(0.2, 10, gamma, d_vp, 0, 1, 37.5);
      EXPECT_NEAR(bright, 37.5 * base, 1e-9 * bright);
      const double half = airlight(0.2, 10, gamma, d_vp, 0, 0.5);
      EXPECT_NEAR(half, 0.5 * base, 1e-9 * base);
    }
  }
  measured("L_a(sD, beta/s) s^2 vs L_a(D, beta), max relative error", worst);
}

TEST(FogReferenceAirlight, HenyeyGreenstein) {
  double worst = 0;
  for (double g : {-0.5, 0.0, 0.85, 0.95}) {
    auto f = [g](double mu) { return 2 * kPi * fr::henyey_greenstein(mu, g); };
    const double total = adaptive_simpson(f, -1.0, 1.0, 1e-12);
    EXPECT_NEAR(total, 1.0, 1e-9) << "g " << g;
    worst = std::max(worst, std::abs(total - 1));
    // Mean cosine is g.
    auto fm = [g](double mu) { return 2 * kPi * mu * fr::henyey_greenstein(mu, g); };
    EXPECT_NEAR(adaptive_simpson(fm, -1.0, 1.0, 1e-12), g, 1e-8) << "g " << g;
  }
  EXPECT_EQ(fr::henyey_greenstein(0.3, 0.0), 1.0 / (4 * kPi));
  // g = 0 equals isotropic in the airlight, and the airlight is continuous in g.
  for (double gamma : {deg(5), deg(90), deg(170)}) {
    const double iso = airlight(0.1, 10, gamma, kInf, 0.0);
    EXPECT_NEAR(airlight(0.1, 10, gamma, kInf, 1e-9), iso, 1e-8 * iso);
    // Forward peaked phase: brighter towards the light, darker away from it.
    if (gamma < 1) {
      EXPECT_GT(airlight(0.1, 10, gamma, kInf, 0.85), 2 * iso);
    }
    if (gamma > 2) {
      EXPECT_LT(airlight(0.1, 10, gamma, kInf, 0.85), 0.5 * iso);
    }
  }
  measured("HG sphere integral, max |error|", worst);
}

// Accuracy over gamma in [0.01 deg, 179.9 deg], T_sv in [1e-3, 30], against eq. 32 integrated separately.
TEST(FogReferenceAirlight, MatchesHalfAngleFormAcrossRange) {
  double worst = 0;
  const double D = 10;
  for (double gamma_deg : {0.01, 0.1, 1.0, 10.0, 45.0, 90.0, 135.0, 170.0, 179.9}) {
    for (double T : {1e-3, 0.1, 1.0, 5.0, 30.0}) {
      for (double dvp_over_D : {kInf, 0.5, 2.0}) {
        const double beta = T / D, gamma = deg(gamma_deg), d_vp = dvp_over_D * D;
        const double want = airlight_half_angle(beta, D, gamma, d_vp);
        const double got = airlight(beta, D, gamma, d_vp);
        EXPECT_NEAR(got, want, 3e-8 * want) << "gamma " << gamma_deg << " T " << T << " D_vp/D " << dvp_over_D;
        worst = std::max(worst, rel_err(got, want));
      }
    }
  }
  measured("airlight vs half-angle form (135 cases), max relative error", worst);
}

TEST(FogReferenceAirlight, HenyeyGreensteinMatchesHalfAngleForm) {
  double worst = 0;
  const double D = 10;
  for (double g : {0.85, 0.95, -0.5}) {
    for (double gamma_deg : {0.01, 1.0, 20.0, 90.0, 160.0, 179.9}) {
      for (double T : {1e-3, 1.0, 10.0}) {
        for (double dvp_over_D : {kInf, 0.5, 1.5}) {
          const double beta = T / D, gamma = deg(gamma_deg), d_vp = dvp_over_D * D;
          const double want = airlight_half_angle(beta, D, gamma, d_vp, g);
          const double got = airlight(beta, D, gamma, d_vp, g);
          EXPECT_NEAR(got, want, 3e-8 * want) << "g " << g << " gamma " << gamma_deg << " T " << T;
          worst = std::max(worst, rel_err(got, want));
        }
      }
    }
  }
  measured("HG airlight vs half-angle form (162 cases, g = 0.85, 0.95, -0.5), max relative error", worst);
}

TEST(FogReferenceAirlight, SmallAngleLimitsAndRobustness) {
  // gamma -> 0 with T_vp > T_sv: L_a ~ beta I0 e^{-T} / (4 D gamma).
  const double beta = 0.1, D = 10, T = 1;
  double worst = 0;
  for (double gamma : {1e-4, 1e-6}) {
    const double want = beta * std::exp(-T) / (4 * D * gamma);
    const double got = airlight(beta, D, gamma, kInf);
    EXPECT_NEAR(got, want, 1e-3 * want);
    worst = std::max(worst, rel_err(got, want));
  }
  // gamma -> 0 with T_vp < T_sv: beta^2 e^{-T} T_vp / (4 pi T (T - T_vp)).
  {
    const double T_vp = 0.4, want = beta * beta * std::exp(-T) * T_vp / (4 * kPi * T * (T - T_vp));
    const double got = airlight(beta, D, 1e-7, T_vp / beta);
    EXPECT_NEAR(got, want, 1e-6 * want);
  }
  // Exactly on the view line: finite, the value at gamma = 1e-9 rad.
  fr::Medium m;
  m.extinction_per_m = beta;
  fr::Light light;
  light.position_m = dvec3(D, 0, 0);
  const double on_axis = fr::single_scattering_radiance(m, light, dvec3(0), dvec3(1, 0, 0), kInf);
  EXPECT_TRUE(std::isfinite(on_axis));
  EXPECT_NEAR(on_axis, airlight(beta, D, 1e-9, kInf), 1e-6 * on_axis);
  EXPECT_NEAR(on_axis, beta * std::exp(-T) / (4 * D * 1e-9), 1e-4 * on_axis);
  // Degenerate input: zeros, never NaN.
  fr::Medium vacuum;
  EXPECT_EQ(fr::single_scattering_radiance(vacuum, light, dvec3(0), dvec3(0, 1, 0), kInf), 0.0);
  EXPECT_EQ(fr::single_scattering_radiance(m, light, dvec3(0), dvec3(0, 1, 0), 0.0), 0.0);
  EXPECT_EQ(fr::single_scattering_radiance(m, light, dvec3(0), dvec3(0), kInf), 0.0);
  EXPECT_EQ(fr::single_scattering_radiance(m, light, light.position_m, dvec3(0, 1, 0), kInf), 0.0);
  for (double T_sv : {1e-3, 10.0, 30.0}) {
    for (double gamma : {0.0, 1e-12, deg(90), kPi}) {
      for (double d_vp : {0.0, 1.0, kInf}) {
        for (double g : {0.0, 0.95, -0.9}) {
          const double v = airlight(T_sv / D, D, gamma, d_vp, g);
          EXPECT_TRUE(std::isfinite(v) && v >= 0) << T_sv << " " << gamma << " " << d_vp << " " << g;
        }
      }
    }
  }
  // L_a increases with D_vp up to the D_vp = inf value.
  double prev = 0;
  for (double d_vp : {0.5, 2.0, 9.0, 10.0, 11.0, 40.0, 80.0, kInf}) {
    const double v = airlight(beta, D, deg(20), d_vp);
    EXPECT_GT(v, prev);
    prev = v;
  }
  measured("gamma -> 0 asymptote relative deviation at 1e-4 / 1e-6 rad (max)", worst);
}

// 5. Surface term, digest 9.C.
fr::Medium unit_medium() {
  fr::Medium m;
  m.extinction_per_m = 1.0;
  return m;
}

double lambert_at(const fr::Medium& m, double D, double theta) {
  const Frame f;
  fr::Light light;
  light.position_m = f.origin + D * f.ex;
  const dvec3 normal = std::cos(theta) * f.ex + std::sin(theta) * f.ey;
  return fr::surface_scattered_lambert(m, light, f.origin, normal);
}

double phong_at(const fr::Medium& m, double D, double theta, double n) {
  const Frame f;
  fr::Light light;
  light.position_m = f.origin + D * f.ex;
  const dvec3 r = std::cos(theta) * f.ex + std::sin(theta) * f.ez;
  return fr::surface_scattered_phong(m, light, f.origin, r, n);
}

TEST(FogReferenceSurface, LambertReferenceCase) {
  fr::Medium m;
  m.extinction_per_m = 0.2;
  const double got = lambert_at(m, 5.0, 1.2);
  EXPECT_NEAR(got, 5.5697e-3, 1e-4 * 5.5697e-3);
  measured("lambert beta=0.2 D=5 theta=1.2 vs 5.5697e-3, relative error", rel_err(got, 5.5697e-3));
}

TEST(FogReferenceSurface, G0AndG20Values) {
  const fr::Medium m = unit_medium();  // beta = 1, so beta^2 G / (2 pi T) = G / (2 pi T)
  struct Case {
    double T, theta, n, G;  // n < 0: Lambert (G_0)
  };
  const Case cases[] = {{1, 0, -1, 1.76668},         {1, kPi / 4, -1, 1.34469},   {1, kPi / 2, -1, 0.466512},
                        {1, 3 * kPi / 4, -1, 0.232498}, {1, kPi, -1, 0.193805},   {0.1, 0, -1, 6.51274},
                        {2, 0, -1, 0.510392},          {5, 0, -1, 0.0165913},     {10, 0, -1, 7.49756e-5},
                        {1, 0, 20, 0.734079},          {1, kPi / 4, 20, 0.0941385}, {1, kPi / 2, 20, 0.0300951},
                        {0.1, 0, 20, 2.22461}};
  double worst = 0;
  for (const Case& c : cases) {
    const double want = c.G / (2 * kPi * c.T);
    const double got = c.n < 0 ? lambert_at(m, c.T, c.theta) : phong_at(m, c.T, c.theta, c.n);
    EXPECT_NEAR(got, want, 1e-4 * want) << "T " << c.T << " theta " << c.theta << " n " << c.n;
    worst = std::max(worst, rel_err(got, want));
  }
  measured("G_0 / G_20 (13 values given to 6 digits), max relative error", worst);
}

TEST(FogReferenceSurface, GeneralPathMatchesSymmetricPath) {
  // A slab far thicker than anything that matters forces the full 2D integral; it must agree with the
  // rotationally symmetric shortcut. The same for a cone wide enough to light every direction.
  fr::Medium wide = unit_medium();
  wide.bottom_m = -1e6;
  wide.top_m = 1e6;
  const double sym = lambert_at(unit_medium(), 1.0, 1.2), gen = lambert_at(wide, 1.0, 1.2);
  EXPECT_NEAR(gen, sym, 2e-5 * sym);
  const double sym_p = phong_at(unit_medium(), 1.0, 0.5, 20), gen_p = phong_at(wide, 1.0, 0.5, 20);
  EXPECT_NEAR(gen_p, sym_p, 2e-5 * sym_p);
  measured("lambert, 2D path vs symmetric path, relative difference", rel_err(gen, sym));
  measured("phong n=20, 2D path vs symmetric path, relative difference", rel_err(gen_p, sym_p));
  // A cone light aimed at the point keeps the problem symmetric about the light direction but takes the
  // 2D path; against a 1D polar integral assembled here, with the azimuthal Lambert weight in closed
  // form (digest section 5).
  {
    const Frame f;
    fr::Light cone;
    cone.position_m = f.origin + 1.0 * f.ex;
    cone.axis = -f.ex;
    cone.cos_inner = std::cos(deg(25));
    cone.cos_outer = std::cos(deg(40));
    const double theta = 0.7;
    const dvec3 normal = std::cos(theta) * f.ex + std::sin(theta) * f.ey;
    const double got = fr::surface_scattered_lambert(unit_medium(), cone, f.origin, normal);
    auto ring = [&](double gp) {
      const double a = std::cos(gp) * std::cos(theta), b = std::sin(gp) * std::sin(theta);
      double C;
      if (a >= b) {
        C = 2 * kPi * a;
      } else if (a <= -b) {
        C = 0;
      } else {
        const double phi0 = std::acos(-a / b);
        C = 2 * (a * phi0 + b * std::sin(phi0));
      }
      if (C == 0) return 0.0;
      const dvec3 dir = std::cos(gp) * f.ex + std::sin(gp) * f.ez;  // any azimuth: symmetric
      return std::sin(gp) * C * fr::single_scattering_radiance(unit_medium(), cone, f.origin, dir, kInf, 1e-12);
    };
    double want = 0;  // split at the horizon kinks (pi/2 -+ theta)
    const double pts[] = {0.0, 0.5 * kPi - theta, 0.5 * kPi + theta, kPi};
    for (int i = 0; i < 3; ++i) want += adaptive_simpson(ring, pts[i], pts[i + 1], 1e-7);
    EXPECT_NEAR(got, want, 2e-5 * want);
    EXPECT_LT(got, lambert_at(unit_medium(), 1.0, theta));  // the cone removes light
    measured("lambert, cone light (2D path) vs 1D polar assembly, relative error", rel_err(got, want));
  }
  // Beta -> 0 ratio check (digest 9.C.4): T = 1, theta = 0: scattered / direct = T G_0 / (2 pi e^-T) ~ 0.764.
  const double direct = std::exp(-1.0);  // I0 e^{-T} cos(0) / D^2 with D = 1
  EXPECT_NEAR(lambert_at(unit_medium(), 1.0, 0.0) / direct, 0.764, 1e-3);
}

// 6. Cone lights.
TEST(FogReferenceCone, ProfileAndBehaviour) {
  fr::Light cone;
  cone.axis = dvec3(0, 0, -1);
  cone.cos_inner = std::cos(deg(20));
  cone.cos_outer = std::cos(deg(30));
  EXPECT_EQ(fr::light_profile(cone, dvec3(0, 0, -2)), 1.0);
  EXPECT_EQ(fr::light_profile(cone, dvec3(1, 0, 0)), 0.0);
  EXPECT_NEAR(fr::light_profile(cone, dvec3(std::sin(deg(25)), 0, -std::cos(deg(25)))),
              [] {
                const double t = (std::cos(deg(25)) - std::cos(deg(30))) / (std::cos(deg(20)) - std::cos(deg(30)));
                return t * t * (3 - 2 * t);
              }(),
              1e-15);
  fr::Medium m;
  m.extinction_per_m = 0.05;
  const dvec3 eye(0, 0, 0), dir(1, 0, 0);
  // Pointing away (up) from every scattering point of a horizontal ray below it: exactly 0.
  fr::Light up = cone;
  up.position_m = dvec3(15, 0, 8);
  up.axis = dvec3(0, 0, 1);
  EXPECT_EQ(fr::single_scattering_radiance(m, up, eye, dir, kInf), 0.0);
  // Omni vs the cone cos_outer = -1 (omni by definition) and a cone just short of it.
  fr::Light omni;
  omni.position_m = up.position_m;
  fr::Light almost = omni;
  almost.cos_outer = -1.0;
  almost.cos_inner = -0.999999;
  const double L_omni = fr::single_scattering_radiance(m, omni, eye, dir, kInf);
  EXPECT_EQ(fr::single_scattering_radiance(m, almost, eye, dir, kInf), L_omni);
  almost.cos_outer = -0.9999999;
  const double L_almost = fr::single_scattering_radiance(m, almost, eye, dir, kInf);
  EXPECT_NEAR(L_almost, L_omni, 1e-9 * L_omni);
  // Down-pointing cone crossed by the ray: against a fixed-step composite Simpson of the same integrand.
  fr::Light down = cone;
  down.position_m = dvec3(15, 0, 8);
  down.intensity = 3.0;
  const double d_vp = 40.0, beta = m.extinction_per_m;
  auto integrand = [&](double x) {
    const dvec3 p = eye + x * dir;
    const dvec3 r = p - down.position_m;
    const double d = glm::length(r);
    const double c = glm::dot(r / d, down.axis);
    const double t = std::clamp((c - down.cos_outer) / (down.cos_inner - down.cos_outer), 0.0, 1.0);
    const double profile = t * t * (3 - 2 * t);
    return beta / (4 * kPi) * down.intensity * profile * std::exp(-beta * (d + x)) / (d * d);
  };
  const int n = 200000;
  double simpson = 0;
  for (int i = 0; i <= n; ++i) simpson += integrand(d_vp * i / n) * ((i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2));
  simpson *= d_vp / (3.0 * n);
  const double got = fr::single_scattering_radiance(m, down, eye, dir, d_vp);
  EXPECT_NEAR(got, simpson, 1e-8 * simpson);
  EXPECT_LT(got, 0.5 * 3.0 * fr::single_scattering_radiance(m, omni, eye, dir, d_vp));  // the cone cuts light
  measured("cone light vs 200k-step Simpson, relative error", rel_err(got, simpson));
}

// 7. Slab.
TEST(FogReferenceSlab, OpticalThicknessAndAirlight) {
  fr::Medium slab;
  slab.extinction_per_m = 0.1;
  slab.bottom_m = 0;
  slab.top_m = 50;
  EXPECT_NEAR(fr::optical_thickness(slab, dvec3(0, 0, 10), dvec3(0, 0, 100)), 4.0, 1e-12);
  EXPECT_NEAR(fr::optical_thickness(slab, dvec3(0, 0, -20), dvec3(0, 0, 100)), 5.0, 1e-12);
  EXPECT_NEAR(fr::optical_thickness(slab, dvec3(3, 4, 10), dvec3(6, 8, 30)), 0.1 * std::sqrt(25.0 + 400.0), 1e-12);
  // Diagonal, leaving through the top at z = 50: 3/4 of a 100 m segment from z=20 to z=60... inside part 30/40.
  EXPECT_NEAR(fr::optical_thickness(slab, dvec3(0, 0, 20), dvec3(60, 0, 100)), 0.1 * 100 * 30.0 / 80.0, 1e-12);
  EXPECT_EQ(fr::optical_thickness(slab, dvec3(0, 0, 60), dvec3(100, 0, 70)), 0.0);
  EXPECT_NEAR(fr::optical_thickness(slab, dvec3(0, 0, 25), dvec3(100, 0, 25)), 10.0, 1e-12);

  // Eye and light inside: a ray leaving through the top equals the unbounded airlight cut at the exit
  // (inside a convex slab every light->point->eye path of a point before the exit stays inside).
  fr::Medium unbounded;
  unbounded.extinction_per_m = 0.1;
  fr::Light light;
  light.position_m = dvec3(20, 5, 30);
  const dvec3 eye(0, 0, 10), dir = glm::normalize(dvec3(1, 0.2, 0.6));
  const double exit = (50.0 - eye.z) / dir.z;
  const double in_slab = fr::single_scattering_radiance(slab, light, eye, dir, kInf);
  const double cut = fr::single_scattering_radiance(unbounded, light, eye, dir, exit);
  EXPECT_NEAR(in_slab, cut, 1e-8 * cut);
  EXPECT_LT(in_slab, fr::single_scattering_radiance(unbounded, light, eye, dir, kInf));

  // Light above the slab, eye below it looking up through the slab at the light: only the slab part of
  // the ray scatters, and the light reaches it through vacuum above. Independent fixed-step Simpson.
  fr::Light high;
  high.position_m = dvec3(30, 0, 120);
  const dvec3 low_eye(0, 0, -20), up_dir = glm::normalize(dvec3(0.5, 0, 1));
  auto integrand = [&](double x) {
    const dvec3 p = low_eye + x * up_dir;
    if (p.z < 0 || p.z > 50) return 0.0;
    const double d = glm::length(p - high.position_m);
    const double tau_light = 0.1 * d * (50 - p.z) / (high.position_m.z - p.z);
    const double tau_eye = 0.1 * (p.z - 0) / up_dir.z;
    return 0.1 / (4 * kPi) * std::exp(-tau_light - tau_eye) / (d * d);
  };
  const double x0 = 20 / up_dir.z, x1 = 70 / up_dir.z;
  const int n = 200000;
  double simpson = 0;
  for (int i = 0; i <= n; ++i) {
    const double x = x0 + (x1 - x0) * i / n;
    simpson += integrand(x) * ((i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2));
  }
  simpson *= (x1 - x0) / (3.0 * n);
  const double through = fr::single_scattering_radiance(slab, high, low_eye, up_dir, kInf);
  EXPECT_NEAR(through, simpson, 1e-8 * simpson);
  EXPECT_EQ(fr::single_scattering_radiance(slab, high, low_eye, up_dir, x0), 0.0);  // vacuum below
  EXPECT_NEAR(fr::single_scattering_radiance(slab, high, low_eye, up_dir, x1), through, 1e-9 * through);
  // Eye above the slab looking sideways at the light: all vacuum, exactly 0.
  EXPECT_EQ(fr::single_scattering_radiance(slab, high, dvec3(0, 0, 100), dvec3(1, 0, 0.1), kInf), 0.0);
  measured("slab: cut ray vs unbounded cut at the exit, relative difference", rel_err(in_slab, cut));
  measured("slab: light above, eye below vs Simpson, relative error", rel_err(through, simpson));
}

// 8. Monte Carlo.
struct McCase {
  fr::Medium m;
  fr::Light light;
  dvec3 eye, dir;
};

McCase mc_case(double beta, double D, double gamma, double g, double albedo = 1.0) {
  McCase c;
  const Frame f;
  c.m.extinction_per_m = beta;
  c.m.hg_g = g;
  c.m.albedo = albedo;
  c.light.position_m = f.origin + D * f.ex;
  c.eye = f.origin;
  c.dir = std::cos(gamma) * f.ex + std::sin(gamma) * f.ey;
  return c;
}

TEST(FogReferenceMonteCarlo, SingleMatchesQuadrature) {
  double worst_sigma = 0;
  for (double g : {0.0, 0.85}) {
    for (double gamma_deg : {10.0, 60.0, 150.0}) {
      const McCase c = mc_case(0.1, 10, deg(gamma_deg), g);
      const double ref = fr::single_scattering_radiance(c.m, c.light, c.eye, c.dir, kInf);
      const fr::MonteCarloResult r =
          fr::monte_carlo_radiance(c.m, c.light, c.eye, c.dir, kInf, 400000, 11 + gamma_deg, 1, 2);
      EXPECT_NEAR(r.single, ref, 4 * r.single_std_error) << "g " << g << " gamma " << gamma_deg;
      EXPECT_LT(r.single_std_error, 0.02 * ref);
      EXPECT_EQ(r.multiple, 0.0);  // max_orders = 1
      worst_sigma = std::max(worst_sigma, std::abs(r.single - ref) / r.single_std_error);
      std::printf("[ measured ] MC single g=%.2f gamma=%5.1f: rel diff %.2e, %.2f sigma (se %.2e rel)\n", g,
                  gamma_deg, rel_err(r.single, ref), std::abs(r.single - ref) / r.single_std_error,
                  r.single_std_error / ref);
    }
  }
  // The same in a slab with paths leaving it (eye and light inside, view ray leaving through the top).
  fr::Medium slab;
  slab.extinction_per_m = 0.1;
  slab.bottom_m = 0;
  slab.top_m = 15;
  fr::Light light;
  light.position_m = dvec3(10, 0, 8);
  const dvec3 eye(0, 0, 5), dir = glm::normalize(dvec3(1, 0, 0.4));
  const double ref = fr::single_scattering_radiance(slab, light, eye, dir, kInf);
  const fr::MonteCarloResult r = fr::monte_carlo_radiance(slab, light, eye, dir, kInf, 400000, 5, 2000, 2);
  EXPECT_NEAR(r.single, ref, 4 * r.single_std_error);
  EXPECT_LT(r.truncated_weight, 1e-9);  // every path leaves a conservative slab
  EXPECT_GT(r.multiple, 0.0);
  measured("MC single, slab: sigma", std::abs(r.single - ref) / r.single_std_error);
  measured("MC single, worst deviation in standard errors (unbounded)", worst_sigma);
}

// Second order against an independent 1D quadrature. For isotropic scattering in an unbounded medium the
// light scattered once and arriving at a point from all directions is the sphere total of test 3,
// Phi_1(r) = (a beta I0 / r) J(beta r), J(T) = integral_1^inf e^{-T mu} ln((mu+1)/(mu-1)) / mu dmu, so the
// second order seen along the view ray is integral_0^inf e^{-beta x} (a beta / 4 pi) Phi_1(r(x)) dx.
TEST(FogReferenceMonteCarlo, SecondOrderMatchesQuadrature) {
  const double beta = 0.1, D = 10, gamma = deg(30);
  for (double albedo : {1.0, 0.7}) {
    auto J = [](double T) {
      auto f = [T](double s) {
        if (s == 0) return 0.0;
        const double mu = 1 + s * s;
        return 2 * s * std::exp(-T * mu) * std::log((mu + 1) / (s * s)) / mu;
      };
      return adaptive_simpson(f, 0.0, std::sqrt(45.0 / T), 1e-9);
    };
    auto integrand = [&](double x) {
      const double r = std::sqrt(D * D + x * x - 2 * x * D * std::cos(gamma));
      const double phi1 = albedo * beta * J(beta * r) / r;
      return std::exp(-beta * x) * albedo * beta / (4 * kPi) * phi1;
    };
    const double ref = adaptive_simpson(integrand, 0.0, 40.0 / beta, 1e-8);
    const McCase c = mc_case(beta, D, gamma, 0.0, albedo);
    const fr::MonteCarloResult r = fr::monte_carlo_radiance(c.m, c.light, c.eye, c.dir, kInf, 1000000, 99, 2, 2);
    EXPECT_NEAR(r.multiple, ref, 4 * r.multiple_std_error) << "albedo " << albedo;
    EXPECT_LT(r.multiple_std_error, 0.03 * ref);
    std::printf("[ measured ] MC order 2 (albedo %.1f) vs quadrature %.6e: rel diff %.2e, %.2f sigma (se %.2e rel)\n",
                albedo, ref, rel_err(r.multiple, ref), std::abs(r.multiple - ref) / r.multiple_std_error,
                r.multiple_std_error / ref);
  }
}

// Second order with a forward-peaked phase (checks the HG direction sampling): the light scattered once
// and arriving at x from direction w' depends only on the angle gamma' between w' and the light
// (library quadrature, unbounded omni light); weight it by p(w'.v) over the sphere (polar gamma' about the
// light, azimuth phi) and integrate along the view ray.
TEST(FogReferenceMonteCarlo, SecondOrderHenyeyGreenstein) {
  const double beta = 0.1, D = 10, gamma = deg(30), g = 0.85;
  const McCase c = mc_case(beta, D, gamma, g);
  auto inscattered = [&](double x) {  // integral over w' of p(w'.v) L_1(x, w')
    const dvec3 p = c.eye + x * c.dir;
    const dvec3 l = glm::normalize(c.light.position_m - p);
    const double cos_psi = glm::dot(l, c.dir), sin_psi = std::sqrt(std::max(0.0, 1 - cos_psi * cos_psi));
    dvec3 e1 = c.dir - cos_psi * l;  // in the plane of l and v, perpendicular to l
    e1 = glm::length(e1) > 0 ? glm::normalize(e1) : dvec3(0);
    auto over_u = [&](double u) {  // gamma' = u^2
      const double gp = u * u;
      const double ring = adaptive_simpson(
          [&](double phi) { return hg(std::cos(gp) * cos_psi + std::sin(gp) * sin_psi * std::cos(phi), g); }, 0.0,
          kPi, 1e-6);
      const dvec3 w = std::cos(gp) * l + std::sin(gp) * e1;
      return 2 * u * std::sin(gp) * 2 * ring * fr::single_scattering_radiance(c.m, c.light, p, w, kInf, 1e-6);
    };
    return adaptive_simpson(over_u, 0.0, std::sqrt(kPi), 1e-4);
  };
  const double ref =
      adaptive_simpson([&](double x) { return std::exp(-beta * x) * beta * inscattered(x); }, 0.0, 30.0 / beta, 1e-4);
  const fr::MonteCarloResult r = fr::monte_carlo_radiance(c.m, c.light, c.eye, c.dir, kInf, 3000000, 77, 2, 2);
  EXPECT_NEAR(r.multiple, ref, 4 * r.multiple_std_error);
  EXPECT_LT(r.multiple_std_error, 0.03 * ref);
  std::printf("[ measured ] MC order 2 (g = 0.85) vs quadrature %.6e: rel diff %.2e, %.2f sigma (se %.2e rel)\n", ref,
              rel_err(r.multiple, ref), std::abs(r.multiple - ref) / r.multiple_std_error, r.multiple_std_error / ref);
}

TEST(FogReferenceMonteCarlo, AlbedoZeroAndScaling) {
  const McCase c0 = mc_case(0.2, 10, deg(30), 0.85, 0.0);
  const fr::MonteCarloResult r0 = fr::monte_carlo_radiance(c0.m, c0.light, c0.eye, c0.dir, kInf, 20000, 3, 2000, 2);
  EXPECT_EQ(r0.multiple, 0.0);
  EXPECT_EQ(r0.single, 0.0);
  EXPECT_EQ(r0.multiple_std_error, 0.0);
  EXPECT_EQ(r0.truncated_weight, 0.0);
  // With one order the random streams are the same for any albedo: single scales exactly.
  const McCase c1 = mc_case(0.2, 10, deg(30), 0.85, 1.0), ch = mc_case(0.2, 10, deg(30), 0.85, 0.5);
  const fr::MonteCarloResult r1 = fr::monte_carlo_radiance(c1.m, c1.light, c1.eye, c1.dir, kInf, 20000, 3, 1, 2);
  const fr::MonteCarloResult rh = fr::monte_carlo_radiance(ch.m, ch.light, ch.eye, ch.dir, kInf, 20000, 3, 1, 2);
  EXPECT_GT(r1.single, 0.0);
  EXPECT_DOUBLE_EQ(rh.single, 0.5 * r1.single);
  // Absorption ends paths: nothing left at the order cap.
  const McCase ca = mc_case(0.2, 10, deg(30), 0.85, 0.9);
  const fr::MonteCarloResult ra = fr::monte_carlo_radiance(ca.m, ca.light, ca.eye, ca.dir, kInf, 20000, 3, 2000, 2);
  EXPECT_LT(ra.truncated_weight, 1e-12);
  EXPECT_GT(ra.multiple, 0.0);
}

TEST(FogReferenceMonteCarlo, MultipleFractionGrowsWithThickness) {
  // Unbounded conservative medium, D_vp = inf. The multiple fraction is 1 - single/total; its standard
  // error is bounded by that of single/total with the two treated as independent (they correlate
  // positively, which only narrows the ratio).
  double prev_fraction = -1, prev_se = 0;
  for (double T : {0.5, 2.0, 8.0}) {
    const McCase c = mc_case(T / 10, 10, deg(30), 0.85);
    const uint64_t paths = 12000;
    const auto t0 = std::chrono::steady_clock::now();
    const fr::MonteCarloResult r = fr::monte_carlo_radiance(c.m, c.light, c.eye, c.dir, kInf, paths, 21, 2000, 2);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double ratio = r.single / r.total, fraction = r.multiple / r.total;
    const double se = ratio * std::hypot(r.single_std_error / r.single, r.total_std_error / r.total);
    const double ref = fr::single_scattering_radiance(c.m, c.light, c.eye, c.dir, kInf);
    EXPECT_NEAR(r.single, ref, 4 * r.single_std_error) << "T " << T;
    EXPECT_NEAR(fraction, 1 - ratio, 1e-12);
    EXPECT_GT(fraction, prev_fraction + 3 * (se + prev_se)) << "T " << T;
    std::printf(
        "[ measured ] MC T_sv=%.1f g=0.85 gamma=30: multiple/total %.4f (se %.4f), total %.4e (se %.1f%%), single vs "
        "quadrature %.2f sigma, %.1f vertices/path, truncated weight %.3f, %.0f paths/s (2 threads)\n",
        T, fraction, se, r.total, 100 * r.total_std_error / r.total, std::abs(r.single - ref) / r.single_std_error,
        r.mean_vertices, r.truncated_weight, static_cast<double>(paths) / seconds);
    prev_fraction = fraction;
    prev_se = se;
  }
}

TEST(FogReferenceMonteCarlo, Deterministic) {
  const McCase c = mc_case(0.2, 10, deg(30), 0.85);
  auto run = [&](uint64_t seed, int threads) {
    return fr::monte_carlo_radiance(c.m, c.light, c.eye, c.dir, 25.0, 3000, seed, 300, threads);
  };
  const fr::MonteCarloResult a = run(7, 2), b = run(7, 2), one = run(7, 1), other = run(8, 2);
  EXPECT_EQ(a.total, b.total);
  EXPECT_EQ(a.multiple, b.multiple);
  EXPECT_EQ(a.total_std_error, b.total_std_error);
  EXPECT_EQ(a.total, one.total);  // chunks are seeded by index: the thread count does not matter
  EXPECT_EQ(a.multiple_std_error, one.multiple_std_error);
  EXPECT_NE(a.total, other.total);
  EXPECT_EQ(a.paths, 3000u);
}

}  // namespace
