// The brute-force reference integrator: convergence, the single-scattering
// limit against an independent quadrature, energy conservation, daylight
// magnitudes, robustness. The printed figures are quoted in docs/REFERENCE.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "reference.h"

using namespace atmo;
using reference::enu_direction;
using reference::Settings;
using spectral::SpectralAtmosphere;

namespace {

constexpr double kR = 6371000.0;

SpectralAtmosphere three_wavelengths(double visibility_m, double albedo = 0.1) {
  return spectral::make_spectral_atmosphere(visibility_m, 1200.0, albedo, kR, {440.0, 550.0, 680.0});
}

double max_relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0.0;
  for (size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(a[k] - b[k]) / std::max(std::abs(b[k]), 1e-30));
  return worst;
}

// --- An independent single-scattering integral -------------------------------
// The formula of integrate_single_scattering + ground_radiance in
// shaders/atmosphere/functions.glsl, in double, with the sun's transmittance
// marched directly (no table): quadratic spacing finest at the eye.
struct Independent {
  const SpectralAtmosphere& a;
  double sigma_t(size_t k, double h) const {
    return a.rayleigh_scattering[k] * a.rayleigh_density(h) + a.mie_extinction[k] * a.mie_density(h) +
           a.ozone_absorption[k] * a.ozone_density(h);
  }
  static double far_hit(glm::dvec3 p, glm::dvec3 d, double radius, double* near) {
    double b = glm::dot(p, d), c = glm::dot(p, p) - radius * radius, disc = b * b - c;
    if (disc < 0) {
      *near = -1;
      return -1;
    }
    *near = -b - std::sqrt(disc);
    return -b + std::sqrt(disc);
  }
  double sun_transmittance(size_t k, glm::dvec3 p, glm::dvec3 sun, int steps) const {
    double near;
    if (far_hit(p, sun, a.bottom_radius_m, &near) > 0 && near > 0) return 0.0;
    double len = far_hit(p, sun, a.top_radius_m, &near), tau = 0, prev = 0;
    for (int i = 0; i < steps; ++i) {
      double s0 = double(i) / steps, s1 = double(i + 1) / steps, sm = 0.5 * (s0 + s1);
      double t = len * sm * sm, next = len * s1 * s1;
      tau += sigma_t(k, glm::length(p + sun * t) - a.bottom_radius_m) * (next - prev);
      prev = next;
    }
    return std::exp(-tau);
  }
  double radiance(size_t k, double eye_alt, glm::dvec3 dir, glm::dvec3 sun, int steps, int sun_steps) const {
    const double pi = spectral::kPi;
    glm::dvec3 eye(0, 0, a.bottom_radius_m + eye_alt);
    double near_g, near_t;
    double far_g = far_hit(eye, dir, a.bottom_radius_m, &near_g);
    double span = far_hit(eye, dir, a.top_radius_m, &near_t);
    bool ground = far_g > 0 && near_g > 0;
    if (ground) span = near_g;
    double c = glm::dot(dir, sun), g = a.mie_g, g2 = g * g;
    double pr = 3.0 / (16.0 * pi) * (1 + c * c);
    double den = 1 + g2 - 2 * g * c;
    double pm = 3.0 / (8.0 * pi) * (1 - g2) / (2 + g2) * (1 + c * c) / (den * std::sqrt(den));
    double od = 0, prev = 0, sum = 0;
    for (int i = 0; i < steps; ++i) {
      double s0 = double(i) / steps, s1 = double(i + 1) / steps, sm = 0.5 * (s0 + s1);
      double t = span * sm * sm, next = span * s1 * s1, dt = next - prev;
      prev = next;
      glm::dvec3 p = eye + dir * t;
      double h = glm::length(p) - a.bottom_radius_m;
      double st = sigma_t(k, h);
      double scatter = a.rayleigh_scattering[k] * a.rayleigh_density(h) * pr + a.mie_scattering[k] * a.mie_density(h) * pm;
      sum += std::exp(-(od + 0.5 * st * dt)) * sun_transmittance(k, p, sun, sun_steps) * scatter * dt;
      od += st * dt;
    }
    sum *= a.solar_irradiance[k];
    if (ground) {
      glm::dvec3 n = glm::normalize(eye + dir * span);
      double mu_s = std::max(glm::dot(n, sun), 0.0);
      sum += std::exp(-od) * a.ground_albedo / pi * mu_s * sun_transmittance(k, n * a.bottom_radius_m, sun, sun_steps) *
             a.solar_irradiance[k];
    }
    return sum;
  }
};

struct View {
  const char* name;
  double eye_alt, heading, elevation;
};
const View kViews[] = {
    {"zenith, 300 m", 300, 0, 90},   {"towards sun 5 deg", 300, 180, 5}, {"away 30 deg", 300, 0, 30},
    {"horizon 90 deg", 300, 90, 0},  {"ground -10 deg", 300, 0, -10},    {"30 km down -20", 30000, 0, -20},
};

}  // namespace

TEST(Reference, SingleScatteringMatchesAnIndependentIntegral) {
  SpectralAtmosphere a = three_wavelengths(20000.0);
  const glm::dvec3 sun = enu_direction(180, 20);
  Settings s;
  s.max_scattering_order = 1;
  s.view_steps = 256;
  s.transmittance_steps = 256;
  Independent ind{a};
  double worst = 0.0;
  for (const View& v : kViews) {
    glm::dvec3 dir = enu_direction(v.heading, v.elevation);
    auto r = reference::sky_radiance(a, v.eye_alt, dir, sun, s);
    std::vector<double> expected(3);
    for (size_t k = 0; k < 3; ++k) expected[k] = ind.radiance(k, v.eye_alt, dir, sun, 5000, 1000);
    double d = max_relative_difference(r.spectral, expected);
    worst = std::max(worst, d);
    std::printf("[ single ] %-18s L(440,550,680) = %.5e %.5e %.5e W/m2/sr/nm, independent %.5e %.5e %.5e, "
                "max rel diff %.1e\n",
                v.name, r.spectral[0], r.spectral[1], r.spectral[2], expected[0], expected[1], expected[2], d);
    EXPECT_LT(d, 5e-3) << v.name;
  }
  std::printf("[ single ] worst relative difference: %.1e (tolerance 5e-3)\n", worst);
}

TEST(Reference, QuadratureConvergesAtSecondOrder) {
  SpectralAtmosphere a = three_wavelengths(20000.0);
  const glm::dvec3 sun = enu_direction(180, 3);  // low sun: long, curved sun paths
  Settings s;
  s.max_scattering_order = 1;
  for (const View& v : {kViews[0], kViews[1], kViews[5]}) {
    glm::dvec3 dir = enu_direction(v.heading, v.elevation);
    s.view_steps = s.transmittance_steps = 2048;
    auto exact = reference::sky_radiance(a, v.eye_alt, dir, sun, s).spectral;
    double previous = 0.0;
    std::printf("[ steps ] %-18s", v.name);
    for (int n : {8, 16, 32, 64, 128, 256}) {
      s.view_steps = s.transmittance_steps = n;
      double err = max_relative_difference(reference::sky_radiance(a, v.eye_alt, dir, sun, s).spectral, exact);
      std::printf("  n=%d: %.1e", n, err);
      if (n >= 32 && previous > 1e-6) {
        EXPECT_LT(err, previous / 2.5) << v.name << " n=" << n;  // ~4x per doubling
      }
      previous = err;
      if (n == 128) {
        EXPECT_LT(err, 2e-3) << v.name;
      }
    }
    std::printf("  (max rel. error vs n=2048)\n");
  }
}

// Multiple scattering is a Monte Carlo estimate: its spread over seeds must
// fall as 1/sqrt(paths), and more paths must not move the mean beyond the noise.
TEST(Reference, MonteCarloNoiseFallsAsOneOverSqrtN) {
  SpectralAtmosphere a = spectral::make_spectral_atmosphere(20000.0, 1200.0, 0.3, kR, {440.0, 550.0, 680.0});
  const glm::dvec3 sun = enu_direction(180, 30);
  const glm::dvec3 dir = enu_direction(0, 20);
  Settings s;
  s.view_steps = s.transmittance_steps = 32;
  s.max_scattering_order = 1;
  const double single = reference::sky_radiance(a, 300, dir, sun, s).luminance_cd_m2;
  s.max_scattering_order = 1000;
  const int seeds = 48;
  struct Stats {
    double mean, sd;
  };
  std::vector<Stats> stats;
  for (int k : {1, 4, 16}) {
    s.paths_per_step = k;
    double sum = 0.0, sum2 = 0.0;
    for (int seed = 1; seed <= seeds; ++seed) {
      s.seed = seed;
      double ms = reference::sky_radiance(a, 300, dir, sun, s).luminance_cd_m2 - single;
      sum += ms;
      sum2 += ms * ms;
    }
    const double mean = sum / seeds, sd = std::sqrt(std::max(sum2 / seeds - mean * mean, 0.0) * seeds / (seeds - 1));
    stats.push_back({mean, sd});
    std::printf("[ mc ] %2d paths/step x 32 steps: multiple scattering %.1f cd/m^2 (single %.1f), sd of one "
                "estimate %.1f = %.1f %% of the total\n",
                k, mean, single, sd, 100.0 * sd / (mean + single));
  }
  const double ratio = stats[2].sd / stats[0].sd;
  std::printf("[ mc ] sd(16 paths) / sd(1 path) = %.2f (1/sqrt(16) = 0.25)\n", ratio);
  EXPECT_GT(ratio, 0.15);
  EXPECT_LT(ratio, 0.40);
  // 4x the paths: the means (of 48 seeds each) agree within 3 standard errors.
  const double diff = stats[2].mean - stats[1].mean;
  const double se = std::sqrt((stats[2].sd * stats[2].sd + stats[1].sd * stats[1].sd) / seeds);
  std::printf("[ mc ] mean(16 paths) - mean(4 paths) = %+.1f cd/m^2 = %+.2f %% of the total, standard error %.1f\n",
              diff, 100.0 * diff / (stats[2].mean + single), se);
  EXPECT_LT(std::abs(diff), 3.0 * se);
  EXPECT_LT(stats[2].sd / (stats[2].mean + single), 0.10);
}

TEST(Reference, NoSunNoLight) {
  SpectralAtmosphere a = three_wavelengths(10000.0);
  std::fill(a.solar_irradiance.begin(), a.solar_irradiance.end(), 0.0);
  Settings s;
  for (const View& v : kViews) {
    auto r = reference::sky_radiance(a, v.eye_alt, enu_direction(v.heading, v.elevation), enu_direction(0, 40), s);
    for (double l : r.spectral) EXPECT_EQ(l, 0.0) << v.name;
  }
  // Sun 30° below the horizon: the shadow of the Earth reaches 986 km, above the whole atmosphere.
  a = three_wavelengths(10000.0);
  for (const View& v : kViews) {
    auto r = reference::sky_radiance(a, v.eye_alt, enu_direction(v.heading, v.elevation), enu_direction(0, -30), s);
    for (double l : r.spectral) EXPECT_EQ(l, 0.0) << v.name;
  }
}

// Without absorption and with a white ground, all the sunlight that enters
// leaves again. In a plane-parallel atmosphere the upward flux at the top,
// pi x the mean radiance over cosine-weighted downward directions, then equals
// the solar irradiance at every point. On a sphere it does not locally (the
// light reflected by the ground spreads over the larger top sphere and part of
// the lower hemisphere sees only the limb), so the check runs on a planet 1000x
// Earth's radius, where the horizon dips 0.3° at 100 km; Earth's value is printed.
TEST(Reference, ConservativeAtmosphereReturnsAllSunlight) {
  for (double visibility : {300000.0, 10000.0}) {
    for (double radius : {kR * 1000.0, kR}) {
      SpectralAtmosphere a = spectral::make_spectral_atmosphere(visibility, 1200.0, 1.0, radius, {440.0, 550.0, 680.0});
      a.mie_scattering = a.mie_extinction;
      std::fill(a.ozone_absorption.begin(), a.ozone_absorption.end(), 0.0);
      const glm::dvec3 sun(0, 0, 1);
      Settings s;
      s.view_steps = s.transmittance_steps = 32;
      s.ground_paths = 4;
      const int m = radius > kR ? 32 : 12;  // m x m stratified cosine-weighted directions
      std::vector<double> flux(3, 0.0);
      for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
          double u1 = (i + 0.5) / m, u2 = (j + 0.5) / m;
          double r = std::sqrt(u1), phi = 2 * spectral::kPi * u2;
          glm::dvec3 dir(r * std::cos(phi), r * std::sin(phi), -std::sqrt(1 - u1));
          auto rad = reference::sky_radiance(a, 99999.0, dir, sun, s, i * m + j);
          for (int k = 0; k < 3; ++k) flux[k] += spectral::kPi * rad.spectral[k] / (m * m);
        }
      std::printf("[ energy ] MOR %3.0f km, planet radius %5.0f km: upward flux at the top / solar irradiance at "
                  "440, 550, 680 nm = %.4f %.4f %.4f\n",
                  visibility / 1000.0, radius / 1000.0, flux[0] / a.solar_irradiance[0],
                  flux[1] / a.solar_irradiance[1], flux[2] / a.solar_irradiance[2]);
      if (radius > kR) {
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(flux[k] / a.solar_irradiance[k], 1.0, 0.03);
      }
    }
  }
}

TEST(Reference, DaylightMagnitudesAndColours) {
  SpectralAtmosphere a = spectral::make_spectral_atmosphere(40000.0, 1200.0, 0.1, kR);
  Settings s;
  s.paths_per_step = 4;
  const glm::dvec3 noon_sun = enu_direction(180, 60);
  auto zenith = reference::sky_radiance(a, 300, enu_direction(0, 90), noon_sun, s);
  auto horizon = reference::sky_radiance(a, 300, enu_direction(90, 1), noon_sun, s);
  std::printf("[ day ] sun 60 deg: zenith %.0f cd/m^2 (sRGB %.0f %.0f %.0f), horizon at 90 deg azimuth %.0f cd/m^2\n",
              zenith.luminance_cd_m2, zenith.linear_srgb.r, zenith.linear_srgb.g, zenith.linear_srgb.b,
              horizon.luminance_cd_m2);
  EXPECT_GT(zenith.luminance_cd_m2, 2000.0);
  EXPECT_LT(zenith.luminance_cd_m2, 10000.0);
  EXPECT_GT(zenith.linear_srgb.b, zenith.linear_srgb.r);  // blue sky
  EXPECT_GT(horizon.luminance_cd_m2, zenith.luminance_cd_m2);

  const glm::dvec3 sunset_sun = enu_direction(270, 0.5);
  auto sunset = reference::sky_radiance(a, 300, enu_direction(270, 2), sunset_sun, s);
  std::printf("[ day ] sunset (sun 0.5 deg): towards the sun at 2 deg %.0f cd/m^2, sRGB %.0f %.0f %.0f\n",
              sunset.luminance_cd_m2, sunset.linear_srgb.r, sunset.linear_srgb.g, sunset.linear_srgb.b);
  EXPECT_GT(sunset.linear_srgb.r, sunset.linear_srgb.b);
}

TEST(Reference, FiniteAndNonNegativeInExtremeConditions) {
  Settings s;
  s.view_steps = s.transmittance_steps = 32;
  s.ground_paths = 4;
  int checked = 0;
  for (double visibility : {1000.0, 300000.0}) {
    SpectralAtmosphere a = spectral::make_spectral_atmosphere(visibility, 1200.0, 0.3, kR, spectral::wavelength_grid(360, 830, 20));
    for (double sun_el : {-20.0, -5.0, 0.0, 45.0})
      for (double alt : {0.0, 300.0, 120000.0})
        for (double el : {90.0, 10.0, 0.0, -3.0, -18.0, -90.0}) {
          auto r = reference::sky_radiance(a, alt, enu_direction(30, el), enu_direction(200, sun_el), s, checked);
          for (double l : r.spectral) {
            ASSERT_TRUE(std::isfinite(l)) << visibility << " " << sun_el << " " << alt << " " << el;
            ASSERT_GE(l, 0.0);
          }
          for (double t : r.transmittance) ASSERT_TRUE(t >= 0.0 && t <= 1.0);
          ASSERT_TRUE(std::isfinite(r.luminance_cd_m2));
          ++checked;
        }
  }
  std::printf("[ robust ] %d cases finite and non-negative\n", checked);
}

TEST(Reference, ImagesDoNotDependOnThreadCount) {
  SpectralAtmosphere a = spectral::make_spectral_atmosphere(20000.0, 1200.0, 0.1, kR, spectral::wavelength_grid(360, 830, 20));
  reference::Camera cam;
  cam.enu_from_view = reference::enu_from_view(270.0, 10.0);
  cam.width = 12;
  cam.height = 8;
  Settings s;
  s.view_steps = s.transmittance_steps = 32;
  const glm::dvec3 sun = enu_direction(250, 15);
  auto t0 = std::chrono::steady_clock::now();
  auto two = reference::render_image(a, 300, cam, sun, s, 2);
  double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  auto one = reference::render_image(a, 300, cam, sun, s, 1);
  std::printf("[ image ] %dx%d, 32 steps, 1 path/step, 20 nm: %.1f ms on 2 threads (%.2f ms/pixel)\n", cam.width,
              cam.height, ms, ms / (cam.width * cam.height));
  ASSERT_EQ(one.luminance_cd_m2, two.luminance_cd_m2);
  // Row 0 is the top: the bottom row looks ~17 deg below the horizon at a dark (albedo 0.1) ground.
  EXPECT_LT(two.luminance_cd_m2[(cam.height - 1) * cam.width + 6], 0.5 * two.luminance_cd_m2[6]);
  // The camera's forward axis is -z of the view: the centre pixel looks along heading 270, pitch 10.
  glm::dvec3 forward = cam.enu_from_view * glm::dvec3(0, 0, -1);
  EXPECT_NEAR(glm::dot(forward, enu_direction(270.0, 10.0)), 1.0, 1e-12);
}
