// The float twins of shaders/night_sky/moon_disc.glsl and
// shaders/night_sky/background.glsl (plugin/core/night_sky/night_sky_twin.h)
// against the core's double-precision Moon disc (moon_photometry.h) and
// background (background.h).
//
// Proved: the disc's radiance equals moon_disc_normal + moon_disc_radiance_rgb
// over many directions, phases and orientations: to 1e-4 relative where it is
// well conditioned (away from the limb and the terminator, where a float
// direction's own rounding moves it by up to 1e-3), and everywhere the twin's
// value is the core's for a direction within 0.02" (backward error); the bright limb
// faces the Sun (synthetic orientations and the ephemeris's own bright-limb
// direction); the disc integrates to moon_illuminance() within 1 % with a hard
// edge and with coverage ramps of 1/150 to 1/4 of the radius; the ramp is
// monotonic, one pixel wide, 0.5 on the limb; nothing is NaN or negative for
// degenerate inputs. The background's four components and RGB equal
// night_background(...) to 1e-3 for random frames, Suns, eye altitudes and
// settings; the per-frame bound is above every direction that escapes the
// planet. Figures are printed with the prefix "[ night twin ]" and quoted in
// docs/NIGHT_SKY.md.
#include "core/night_sky/night_sky_twin.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/astro/ephemeris.h"
#include "core/night_sky/star_photometry.h"

namespace {

namespace night = atmo::core::night;
namespace astro = atmo::core::astro;
namespace twin = atmo::twin;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// Worst and median of a set of errors.
struct Errors {
  std::vector<double> v;
  void add(double e) { v.push_back(e); }
  double worst() const { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }
  double median() const {
    if (v.empty()) return 0.0;
    std::vector<double> c = v;
    std::nth_element(c.begin(), c.begin() + c.size() / 2, c.end());
    return c[c.size() / 2];
  }
};

double max_abs(const glm::dvec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

bool finite_non_negative(const glm::vec3& v) {
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(v[i]) || v[i] < 0.0f) return false;
  return true;
}

glm::dvec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  for (;;) {
    const glm::dvec3 v(n(rng), n(rng), n(rng));
    const double l = glm::length(v);
    if (l > 1e-6) return v / l;
  }
}

// Any unit vector perpendicular to u.
glm::dvec3 perpendicular(const glm::dvec3& u) {
  const glm::dvec3 a = std::abs(u.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::cross(u, a));
}

// A random rotation (columns: east, north, up of the ENU frame in ICRS).
glm::dmat3 random_rotation(std::mt19937& rng) {
  const glm::dvec3 up = random_unit(rng);
  const glm::dvec3 east = glm::normalize(glm::cross(random_unit(rng), up));
  const glm::dvec3 north = glm::cross(up, east);
  return glm::dmat3(east, north, up);
}

// --- The Moon ------------------------------------------------------------------------

// The core's radiance (double) in direction `dir` for a Moon of centre `c`,
// angular radius `alpha`, Moon -> Sun `to_sun`; 0 off the disc (hard edge).
glm::dvec3 core_moon(const night::MoonDiscLighting& l, const glm::dvec3& c, double alpha, const glm::dvec3& to_sun,
                     const glm::dvec3& dir) {
  return night::moon_disc_radiance_toward(l, c, alpha, to_sun, dir);
}

// A direction at disc coordinates (rho, angle) of a Moon at c, angular radius alpha.
glm::dvec3 disc_direction(const glm::dvec3& c, double alpha, double rho, double angle) {
  const glm::dvec3 right = perpendicular(c), up = glm::cross(c, right);
  const double theta = std::asin(std::min(rho * std::sin(alpha), 1.0));
  return std::cos(theta) * c + std::sin(theta) * (std::cos(angle) * right + std::sin(angle) * up);
}

// Moon -> Sun for a phase angle `phase` (Sun-Moon-observer) and an
// orientation angle `psi` around the line of sight.
glm::dvec3 to_sun_for(const glm::dvec3& c, double phase, double psi) {
  const glm::dvec3 right = perpendicular(c), up = glm::cross(c, right);
  return std::cos(phase) * (-c) + std::sin(phase) * (std::cos(psi) * right + std::sin(psi) * up);
}

double angular_radius(double distance_m) { return std::asin(night::kMoonRadiusM / distance_m); }

// The smallest angle delta (of a ladder, arcsec) such that `value` lies within
// the range of the core's luminance over the circle of radius delta around
// `dir` (and at dir), widened by 1e-5 of the value for the float arithmetic
// itself: the twin's backward error, the error of the direction it effectively
// evaluated.
double backward_error_arcsec(double value, const night::MoonDiscLighting& l, const glm::dvec3& c, double alpha,
                             const glm::dvec3& to_sun, const glm::dvec3& dir, double peak) {
  const glm::dvec3 e1 = perpendicular(dir), e2 = glm::cross(dir, e1);
  const double at = night::rgb_luminance(core_moon(l, c, alpha, to_sun, dir));
  double lo = at, hi = at;
  const double tol = 1e-5 * value + 1e-7 * peak;  // plus the rounding of the value itself
  if (std::abs(value - at) <= tol) return 0.0;
  for (double arcsec : {0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0}) {
    const double delta = arcsec * kDeg / 3600.0;
    for (int k = 0; k < 16; ++k) {
      const double a = k * kPi / 8.0;
      const glm::dvec3 d = dir + delta * (std::cos(a) * e1 + std::sin(a) * e2);
      const double v = night::rgb_luminance(core_moon(l, c, alpha, to_sun, d));
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    if (value >= lo - tol && value <= hi + tol) return arcsec;
  }
  return 1e9;
}

TEST(NightSkyTwin, MoonDiscMatchesTheCore) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double phases_deg[] = {0.0, 0.5, 5.0, 30.0, 60.0, 89.0, 90.0, 91.0, 120.0, 150.0, 170.0, 179.0, 180.0};
  // Forward (relative) error where the radiance is well conditioned: within 0.99
  // of the radius (mu >= 0.14) and where the sunlit term mu0 / (mu0 + mu) >= 0.1.
  // A float direction is only known to ~6e-8 rad = 1.3e-5 of the disc's radius;
  // near the limb (mu = sqrt(1 - rho^2)) and the terminator (mu0 -> 0) that
  // moves the value by more than 1e-3, for the twin as for any float code.
  Errors formula, end_to_end;
  Errors backward;  // arcsec, everywhere on the disc
  int compared = 0;
  for (double phase_deg : phases_deg) {
    for (int o = 0; o < 12; ++o) {
      const double distance = 356500e3 + u01(rng) * 50000e3;
      const double alpha = angular_radius(distance);
      const glm::dvec3 c = random_unit(rng);
      const glm::dvec3 to_sun = to_sun_for(c, phase_deg * kDeg, u01(rng) * 2.0 * kPi);
      const night::MoonDiscLighting l = night::moon_disc_lighting(phase_deg * kDeg, distance, 1.0 + 0.02 * u01(rng));
      const twin::MoonDisc m = night::make_moon_disc(c, alpha, to_sun, l);
      const double earthshine = night::rgb_luminance(glm::dvec3(m.earthshine_radiance));
      const double sun_peak = night::rgb_luminance(glm::dvec3(m.sun_radiance));
      for (int i = 0; i < 400; ++i) {
        const double rho = i < 40 ? 0.99999 * i / 39.0 : std::sqrt(u01(rng)) * 0.99999;
        const glm::dvec3 dir = disc_direction(c, alpha, rho, u01(rng) * 2.0 * kPi);
        const glm::vec3 dir_f(dir);
        const glm::dvec3 twin_value(twin::moon_disc_radiance(m, dir_f, 0.0f));
        ASSERT_TRUE(finite_non_negative(glm::vec3(twin_value)));
        // The same float inputs in double: the twin's own arithmetic.
        const glm::dvec3 cf(m.direction), sf(m.to_sun), df(dir_f);
        const glm::dvec3 core_f = core_moon(l, cf, alpha, sf, df);
        // The exact inputs: plus the rounding of the direction to float.
        const glm::dvec3 core_d = core_moon(l, c, alpha, to_sun, dir);
        ++compared;
        backward.add(backward_error_arcsec(night::rgb_luminance(twin_value), l, cf, alpha, sf, df,
                                           sun_peak + earthshine));
        const double sunlit = sun_peak > 0.0 ? (night::rgb_luminance(core_d) - earthshine) / sun_peak : 0.0;
        if (rho <= 0.99 && sunlit >= 0.1) {
          formula.add(max_abs(twin_value - core_f) / max_abs(core_f));
          end_to_end.add(max_abs(twin_value - core_d) / max_abs(core_d));
        }
      }
    }
  }
  std::printf("[ night twin ] Moon disc, float twin vs double core, %d directions on the disc (13 phases 0-180 deg x "
              "12 orientations): relative error where well conditioned (rho <= 0.99, sunlit term >= 0.1; %zu): same "
              "float inputs worst %.2e median %.2e, exact inputs (direction rounded to float) worst %.2e median %.2e; "
              "everywhere, backward error (the twin's value is the core's within this angle of the direction) worst "
              "%.3f\" median %.3f\"\n",
              compared, formula.v.size(), formula.worst(), formula.median(), end_to_end.worst(), end_to_end.median(),
              backward.worst(), backward.median());
  EXPECT_LT(formula.worst(), 1e-4);
  EXPECT_LT(end_to_end.worst(), 2e-3);  // mostly the direction's rounding to float, which the twin cannot undo
  EXPECT_LT(formula.median(), 1e-6);
  EXPECT_LE(backward.worst(), 0.02);
}

// The angle about the Moon's centre (from perpendicular(c) toward
// cross(c, perpendicular(c))) of the brightest point of the ring at disc
// radius `rho`, sampled every 0.05°.
double brightest_ring_angle(const twin::MoonDisc& m, const glm::dvec3& c, double alpha, double rho) {
  double best = -1.0, best_angle = 0.0;
  for (int k = 0; k < 7200; ++k) {
    const double a = k * 2.0 * kPi / 7200.0;
    const double v = night::rgb_luminance(
        glm::dvec3(twin::moon_disc_radiance(m, glm::vec3(disc_direction(c, alpha, rho, a)), 0.0f)));
    if (v > best) {
      best = v;
      best_angle = a;
    }
  }
  return best_angle;
}

// The same angle of the centroid of the sunlit light (radiance less the
// earthshine) over a polar grid of disc coordinates (100 rings x 720 angles).
double lit_centroid_angle(const twin::MoonDisc& m, const glm::dvec3& c, double alpha) {
  const double earthshine = night::rgb_luminance(glm::dvec3(m.earthshine_radiance));
  glm::dvec2 sum(0.0);
  for (int j = 0; j < 100; ++j) {
    const double rho = (j + 0.5) / 100.0;
    for (int i = 0; i < 720; ++i) {
      const double a = (i + 0.5) * 2.0 * kPi / 720.0;
      const glm::vec3 dir(disc_direction(c, alpha, rho, a));
      const double v = night::rgb_luminance(glm::dvec3(twin::moon_disc_radiance(m, dir, 0.0f))) - earthshine;
      sum += v * rho * rho * glm::dvec2(std::cos(a), std::sin(a));  // area rho d(rho) d(a) times the position
    }
  }
  return std::atan2(sum.y, sum.x);
}

// The angle about the Moon's centre c of the direction `across` (perpendicular to c).
double disc_angle_of(const glm::dvec3& c, const glm::dvec3& across) {
  const glm::dvec3 right = perpendicular(c), up = glm::cross(c, right);
  return std::atan2(glm::dot(across, up), glm::dot(across, right));
}

double angle_difference(double a, double b) {
  double d = std::fmod(std::abs(a - b), 2.0 * kPi);
  return std::min(d, 2.0 * kPi - d);
}

TEST(NightSkyTwin, BrightLimbFacesTheSun) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  double worst_peak = 0.0, worst_centroid = 0.0;
  int cases = 0;
  for (double phase_deg : {10.0, 45.0, 90.0, 135.0, 170.0}) {
    for (int o = 0; o < 8; ++o) {
      const glm::dvec3 c = random_unit(rng);
      const double alpha = angular_radius(384400e3);
      const glm::dvec3 to_sun = to_sun_for(c, phase_deg * kDeg, u01(rng) * 2.0 * kPi);
      const twin::MoonDisc m =
          night::make_moon_disc(c, alpha, to_sun, night::moon_disc_lighting(phase_deg * kDeg, 384400e3, 1.0));
      const double expected = disc_angle_of(c, to_sun - glm::dot(to_sun, c) * c);
      // A ring inside the lit part (the crescent of 170° is lit beyond 0.985).
      const double rho = phase_deg <= 135.0 ? 0.9 : 0.995;
      worst_peak = std::max(worst_peak, angle_difference(brightest_ring_angle(m, c, alpha, rho), expected));
      worst_centroid = std::max(worst_centroid, angle_difference(lit_centroid_angle(m, c, alpha), expected));
      ++cases;
    }
  }
  // The ephemeris: the Moon's bright limb (astro::BodyEphemeris::bright_limb_enu,
  // the Sun's direction from the eye projected across the disc) at real dates.
  struct Date {
    const char* utc;
    double lat, lon;
  };
  const Date dates[] = {{"2024-03-14T19:00:00Z", 47.26, 11.35},   // waxing crescent, evening
                        {"2024-03-17T21:00:00Z", 47.26, 11.35},   // first quarter
                        {"2024-04-01T04:00:00Z", -33.87, 151.21},  // waning gibbous, Sydney
                        {"2023-11-09T05:00:00Z", 40.0, -105.0}};  // waning crescent, dawn
  double worst_ephemeris = 0.0, worst_phase = 0.0;
  for (const Date& d : dates) {
    std::string error;
    const auto cal = astro::parse_iso8601(d.utc, &error);
    ASSERT_TRUE(cal) << error;
    const auto t = astro::time_scales_from_utc(*cal, {}, &error);
    ASSERT_TRUE(t) << error;
    const auto o = astro::observer_from_geodetic(d.lat, d.lon, 500.0, &error);
    ASSERT_TRUE(o) << error;
    astro::EphemerisOptions options;
    options.refraction = false;
    const auto f = astro::AstrometryFrame::create(*t, *o, options, &error);
    ASSERT_TRUE(f) << error;
    const astro::BodyEphemeris moon = f->body(astro::Body::kMoon), sun = f->body(astro::Body::kSun);
    const glm::dvec3 c = moon.direction.enu_unrefracted;
    const glm::dvec3 to_sun =
        night::moon_to_sun_direction(sun.direction.enu_unrefracted, sun.distance_m, c, moon.distance_m);
    worst_phase = std::max(worst_phase, std::abs(std::acos(glm::dot(to_sun, -c)) - moon.phase_angle_rad));
    const twin::MoonDisc m = night::make_moon_disc(c, moon.angular_radius_rad, to_sun,
                                                   night::moon_disc_lighting(moon.phase_angle_rad, moon.distance_m));
    worst_ephemeris = std::max(worst_ephemeris, angle_difference(lit_centroid_angle(m, c, moon.angular_radius_rad),
                                                                 disc_angle_of(c, moon.bright_limb_enu)));
  }
  std::printf("[ night twin ] bright limb vs Moon->Sun projected on the sky, %d cases (phase 10-170 deg, random "
              "orientations): centroid of the sunlit light worst %.4f deg, brightest point of a lit ring (0.05 deg "
              "steps; the maximum is flat) worst %.2f deg; centroid vs the ephemeris's bright_limb_enu at 4 dates: "
              "worst %.3f deg (phase from moon_to_sun_direction vs the ephemeris: %.4f deg)\n",
              cases, worst_centroid / kDeg, worst_peak / kDeg, worst_ephemeris / kDeg, worst_phase / kDeg);
  EXPECT_LT(worst_centroid, 0.05 * kDeg);
  EXPECT_LT(worst_peak, 1.0 * kDeg);
  EXPECT_LT(worst_ephemeris, 0.5 * kDeg);
  EXPECT_LT(worst_phase, 0.05 * kDeg);
}

TEST(NightSkyTwin, DiscIntegratesToTheMoonsIlluminance) {
  // Ramp widths: none (hard edge), one grid step, and pixels of radius/10 and
  // radius/4 (a 0.26° Moon at ~0.05° and 0.13° a pixel) integrated on the fine grid.
  const double width_over_radius[] = {0.0, 1.0 / 150.0, 0.1, 0.25};
  double worst[4] = {0.0, 0.0, 0.0, 0.0};
  std::string table;
  for (double phase_deg : {0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 165.0, 170.0, 175.0, 180.0}) {
    const double distance = 370000e3, sun_au = 1.01;
    const double alpha = angular_radius(distance);
    const glm::dvec3 c = glm::normalize(glm::dvec3(0.3, 0.8, 0.52));
    const glm::dvec3 to_sun = to_sun_for(c, phase_deg * kDeg, 1.1);
    const twin::MoonDisc m =
        night::make_moon_disc(c, alpha, to_sun, night::moon_disc_lighting(phase_deg * kDeg, distance, sun_au));
    const glm::dvec3 right = perpendicular(c), up = glm::cross(c, right);
    // Gnomonic grid of step h (radians at the centre), out to the ramp's end.
    const double h = alpha / 150.0;
    const int n = static_cast<int>(std::ceil(1.15 * std::tan(alpha) / h)) + 2;
    double sum[4] = {0.0, 0.0, 0.0, 0.0};
    for (int j = -n; j <= n; ++j) {
      for (int i = -n; i <= n; ++i) {
        const double u = i * h, v = j * h;
        const double d_omega = h * h / std::pow(1.0 + u * u + v * v, 1.5);
        const glm::vec3 dir(glm::normalize(c + u * right + v * up));
        for (int k = 0; k < 4; ++k)
          sum[k] += night::rgb_luminance(glm::dvec3(twin::moon_disc_radiance(
                        m, dir, static_cast<float>(width_over_radius[k] * alpha)))) * d_omega;
      }
    }
    const double expected = night::moon_illuminance(phase_deg * kDeg, distance, sun_au).total();
    char line[200];
    std::snprintf(line, sizeof line, " %g deg %.4g lx:", phase_deg, expected);
    table += line;
    for (int k = 0; k < 4; ++k) {
      // The crescent of 175° is 0.4 % of the radius wide, under one grid step:
      // only the ramps of radius/10 and /4 (pixels much wider than the step) see it whole.
      if (phase_deg <= 170.0 || k >= 2) worst[k] = std::max(worst[k], std::abs(sum[k] / expected - 1.0));
      std::snprintf(line, sizeof line, " %+.3f", (sum[k] / expected - 1.0) * 100.0);
      table += line;
    }
    table += " %;";
  }
  std::printf("[ night twin ] disc integral (gnomonic grid, step = radius/150) vs moon_illuminance, in %% for the "
              "hard edge / ramp of 1 step / radius/10 / radius/4:%s worst %.3f / %.3f (phase <= 170 deg) / %.3f / "
              "%.3f %%\n",
              table.c_str(), worst[0] * 100.0, worst[1] * 100.0, worst[2] * 100.0, worst[3] * 100.0);
  for (int k = 0; k < 4; ++k) EXPECT_LT(worst[k], 0.01) << width_over_radius[k];
}

TEST(NightSkyTwin, CoverageRampIsMonotonicAndOnePixelWide) {
  // The ramp itself.
  const float w = 1e-3f;
  float previous = -1.0f;
  for (int i = -2000; i <= 2000; ++i) {
    const float edge = i * 1e-6f;
    const float cov = twin::moon_disc_coverage(edge, w);
    EXPECT_GE(cov, previous);
    EXPECT_GE(cov, 0.0f);
    EXPECT_LE(cov, 1.0f);
    previous = cov;
  }
  EXPECT_FLOAT_EQ(twin::moon_disc_coverage(0.0f, w), 0.5f);
  EXPECT_EQ(twin::moon_disc_coverage(-0.5f * w, w), 0.0f);
  EXPECT_EQ(twin::moon_disc_coverage(0.5f * w, w), 1.0f);
  EXPECT_EQ(twin::moon_disc_coverage(0.0f, 0.0f), 1.0f);  // hard edge: the limb is on the disc
  EXPECT_EQ(twin::moon_disc_coverage(-1e-9f, 0.0f), 0.0f);
  // On the disc: at full Moon the Lommel–Seeliger disc is uniform (mu0 = mu:
  // sunlit = 1/2 everywhere), so across the limb the radiance over the disc's
  // value is the coverage (times the stretched band's area factor, 1 - O(pixel
  // / radius)): 1 half a pixel inside, falling monotonically to 0 half a pixel
  // outside, ~0.5 on the limb — for pixels of 1/40 and 1/4 of the radius.
  const glm::dvec3 c = glm::normalize(glm::dvec3(-0.2, 0.5, 0.7));
  const double alpha = angular_radius(384400e3);
  const twin::MoonDisc m = night::make_moon_disc(c, alpha, -c, night::moon_disc_lighting(0.0, 384400e3, 1.0));
  const glm::dvec3 across = std::cos(0.3) * perpendicular(c) + std::sin(0.3) * glm::cross(c, perpendicular(c));
  const double inside = twin::moon_disc_radiance(m, glm::vec3(c), 0.0f).y;
  double worst_ramp = 0.0;
  for (double pixel : {alpha / 40.0, alpha / 4.0}) {
    double prev_ratio = 2.0;
    for (int k = -100; k <= 100; ++k) {
      const double theta = alpha + k * pixel / 100.0;
      const glm::vec3 dir(std::cos(theta) * c + std::sin(theta) * across);
      const double ratio = twin::moon_disc_radiance(m, dir, static_cast<float>(pixel)).y / inside;
      EXPECT_LE(ratio, prev_ratio + 1e-4) << k;  // monotonic but for the float rounding of a flat disc
      // The coverage, times sin(theta_s) / sin(theta) >= 1 - width / (2 radius)
      // (the stretched band's area); the float direction (~6e-8 rad) moves the
      // ramp by ~6e-8 / pixel.
      const double tol = 1e-4 + 2e-7 / pixel;
      const double expected = std::clamp(0.5 - k / 100.0, 0.0, 1.0);
      worst_ramp = std::max(worst_ramp, std::abs(ratio - expected) / (pixel / alpha));
      EXPECT_LE(ratio, expected + tol) << k;
      EXPECT_GE(ratio, expected * (1.0 - 0.5 * pixel / alpha) - tol) << k;
      if (k <= -52) {
        EXPECT_NEAR(ratio, 1.0, 1e-4) << k;
      }
      if (k >= 52) {
        EXPECT_EQ(ratio, 0.0) << k;
      }
      prev_ratio = ratio;
    }
  }
  std::printf("[ night twin ] limb ramp (full Moon, uniform; pixel = radius/40 and /4): radiance / disc radiance "
              "= the linear 1-pixel coverage ramp within %.3f x pixel/radius\n", worst_ramp);
}

TEST(NightSkyTwin, NoNaNForDegenerateInputs) {
  const night::MoonDiscLighting l = night::moon_disc_lighting(1.0, 384400e3, 1.0);
  const glm::dvec3 c(0.0, 0.6, 0.8);
  std::vector<twin::MoonDisc> moons = {
      night::make_moon_disc(c, 0.0045, to_sun_for(c, 1.0, 0.0), l),
      night::make_moon_disc(c, 0.0, to_sun_for(c, 1.0, 0.0), l),               // radius 0
      night::make_moon_disc(c, 0.0045, -c, l),                                  // full
      night::make_moon_disc(c, 0.0045, c, night::moon_disc_lighting(kPi)),      // new
      night::make_moon_disc(c, 0.5 * kPi, to_sun_for(c, 1.0, 0.0), l),         // a hemisphere
      night::make_moon_disc(glm::dvec3(0.0), 0.0045, glm::dvec3(0.0), l),       // zero vectors
      night::make_moon_disc(c, -1.0, to_sun_for(c, 1.0, 0.0), l),               // negative radius
      night::make_moon_disc(c, std::numeric_limits<double>::quiet_NaN(), c, l),  // NaN radius
  };
  int evaluated = 0;
  for (const twin::MoonDisc& m : moons) {
    const glm::dvec3 mc(m.direction);
    const double a = m.angular_radius_rad;
    std::vector<glm::vec3> dirs = {glm::vec3(mc), -glm::vec3(mc), glm::vec3(0.0f), glm::vec3(1, 0, 0), glm::vec3(0, 0, 1)};
    for (double rho : {0.0, 0.5, 0.999999, 1.0, 1.000001, 1.01, 2.0})
      for (double ang : {0.0, 1.0, 2.0, 4.0}) dirs.push_back(glm::vec3(disc_direction(mc, std::max(a, 1e-6), rho, ang)));
    dirs.push_back(glm::vec3(std::numeric_limits<float>::quiet_NaN()));
    for (const glm::vec3& d : dirs)
      for (float px : {0.0f, 1e-6f, 1e-4f, 0.01f, 10.0f, -1.0f}) {
        EXPECT_TRUE(finite_non_negative(twin::moon_disc_radiance(m, d, px)));
        ++evaluated;
      }
  }
  // A Moon of radius 0 sends no light (but for its exact centre direction, one direction).
  const twin::MoonDisc zero = moons[1];
  EXPECT_EQ(twin::moon_disc_radiance(zero, glm::vec3(disc_direction(c, 1e-4, 0.5, 0.0)), 1e-3f), glm::vec3(0.0f));

  // The background.
  std::mt19937 rng(3);
  night::BackgroundSettings thin;
  thin.airglow_layer_thickness_m = 0.0;
  thin.starlight_width_sin_b = 0.0;
  const glm::dvec3 pole = night::ecliptic_pole_icrs();
  const glm::dmat3 g = night::galactic_from_icrs();
  const glm::dvec3 galactic_pole(g[0][2], g[1][2], g[2][2]), galactic_centre(g[0][0], g[1][0], g[2][0]);
  for (const glm::dvec3& sun : {glm::dvec3(1, 0, 0), pole, galactic_pole, glm::dvec3(0.0)}) {
    for (double h : {-400.0, 0.0, 1000.0, 84999.0, 85000.0, 90000.0, 95000.0, 200000.0}) {
      for (const night::BackgroundSettings& s : {night::BackgroundSettings{}, thin}) {
        const glm::dmat3 m = random_rotation(rng);
        const twin::NightBackground b = night::make_night_background(m, sun, h, 6371000.0, s);
        const glm::dmat3 enu_from_icrs = glm::transpose(m);
        std::vector<glm::dvec3> dirs = {glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1), glm::dvec3(1, 0, 0),
                                        glm::dvec3(0, 1, 0), glm::dvec3(0.0), enu_from_icrs * pole,
                                        enu_from_icrs * -pole, enu_from_icrs * galactic_pole,
                                        enu_from_icrs * galactic_centre, enu_from_icrs * glm::dvec3(b.sun_icrs),
                                        -(enu_from_icrs * glm::dvec3(b.sun_icrs))};
        for (double el : {-0.1, -0.01, -1e-4, -1e-7, 0.0, 1e-7, 1e-4, 0.01})
          dirs.push_back(glm::dvec3(std::cos(el), 0.0, std::sin(el)));
        for (const glm::dvec3& d : dirs) {
          EXPECT_TRUE(finite_non_negative(twin::night_background_radiance(b, glm::vec3(d))));
          ++evaluated;
        }
      }
    }
  }
  std::printf("[ night twin ] degenerate inputs: %d evaluations, all finite and >= 0\n", evaluated);
}

// --- The background -----------------------------------------------------------------

TEST(NightSkyTwin, BackgroundMatchesTheCore) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double altitudes[] = {0.0, 300.0, 1000.0, 12000.0, 50000.0, 84000.0, 87000.0, 90000.0, 96000.0, 200000.0};
  night::BackgroundSettings custom;
  custom.airglow_zenith_s10 = 290.0;
  custom.airglow_layer_altitude_m = 95000.0;
  custom.airglow_layer_thickness_m = 12000.0;
  custom.zodiacal_scale = 1.1;
  custom.starlight_pole_s10 = 35.0;
  custom.starlight_plane_excess_s10 = 180.0;
  custom.starlight_width_sin_b = 0.2;
  custom.starlight_longitude_contrast = 0.7;
  custom.diffuse_galactic_fraction = 0.25;
  custom.cosmic_s10 = 1.4;
  const char* names[] = {"airglow", "zodiacal", "starlight", "diffuse galactic + cosmic", "RGB"};
  Errors errors[5];
  int compared = 0, airglow_near_edges = 0;
  for (int frame = 0; frame < 200; ++frame) {
    const glm::dmat3 m = random_rotation(rng);
    const double lambda = u01(rng) * 2.0 * kPi;
    // The Sun on the ecliptic (3 frames in 4), or anywhere (exercises the fit's |beta| <= eps clamp).
    const glm::dvec3 sun = frame % 4 != 3 ? glm::dvec3(std::cos(lambda), std::sin(lambda) * std::cos(night::kObliquityJ2000Rad),
                                                       std::sin(lambda) * std::sin(night::kObliquityJ2000Rad))
                                          : random_unit(rng);
    const double h = altitudes[frame % 10];
    const double radius = 6371000.0 + (u01(rng) - 0.5) * 40000.0;
    const night::BackgroundSettings s = frame % 2 ? custom : night::BackgroundSettings{};
    const twin::NightBackground b = night::make_night_background(m, sun, h, radius, s);
    for (int i = 0; i < 500; ++i) {
      glm::dvec3 dir_enu = random_unit(rng);
      if (i < 50) dir_enu = glm::normalize(glm::dvec3(dir_enu.x, dir_enu.y, 0.02 * dir_enu.z));  // near the horizon
      const glm::vec3 dir_f(dir_enu);
      // The core for the same float direction, in ICRS.
      const glm::dvec3 dir_icrs = m * glm::dvec3(dir_f);
      const night::BackgroundLuminance core =
          night::night_background(dir_icrs, sun, m * glm::dvec3(0, 0, 1), h, radius, s);
      const glm::dvec4 core4(core.airglow, core.zodiacal, core.starlight, core.diffuse_galactic + core.cosmic);
      const glm::dvec4 twin4(twin::night_background_luminances(b, dir_f));
      const glm::dvec3 twin_rgb(twin::night_background_radiance(b, dir_f));
      ASSERT_TRUE(finite_non_negative(glm::vec3(twin_rgb)));
      // The airglow is discontinuous where a ray grazes the ground or a shell
      // (the slant factor jumps; float and double may fall on either side):
      // those rays are counted, not compared.
      const double r0 = radius + h, mu = dir_f.z;
      const double tangent = r0 * std::sqrt(std::max(1.0 - mu * mu, 0.0));
      bool near_edge = false;
      for (double rho : {radius, radius + s.airglow_layer_altitude_m - 0.5 * s.airglow_layer_thickness_m,
                         radius + s.airglow_layer_altitude_m + 0.5 * s.airglow_layer_thickness_m})
        if (mu <= 0.0 && std::abs(tangent - rho) < 1.0) near_edge = true;
      if (h == 0.0 && std::abs(mu) < 1e-6) near_edge = true;
      for (int k = 0; k < 4; ++k) {
        if (k == 0 && near_edge) {
          ++airglow_near_edges;
          continue;
        }
        if (core4[k] > 0.0) errors[k].add(std::abs(twin4[k] - core4[k]) / core4[k]);
        else EXPECT_LE(twin4[k], 1e-12) << names[k];
      }
      const glm::dvec3 core_rgb = core.rgb();
      if (!near_edge) errors[4].add(max_abs(twin_rgb - core_rgb) / max_abs(core_rgb));
      ++compared;
    }
  }
  std::string line;
  for (int k = 0; k < 5; ++k) {
    char buf[120];
    std::snprintf(buf, sizeof buf, " %s worst %.2e median %.2e;", names[k], errors[k].worst(), errors[k].median());
    line += buf;
  }
  std::printf("[ night twin ] background, float twin vs double core, %d directions (200 frames: random orientation, "
              "Sun, eye altitude 0-200 km, default and custom settings), relative error:%s (%d airglow values within "
              "1 m of a grazing ray not compared)\n",
              compared, line.c_str(), airglow_near_edges);
  for (int k = 0; k < 5; ++k) {
    EXPECT_LT(errors[k].worst(), 1e-3) << names[k];
    EXPECT_LT(errors[k].median(), 1e-5) << names[k];
  }
}

TEST(NightSkyTwin, BackgroundBoundHoldsAboveTheHorizon) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  double worst_ratio = 0.0, loosest_deep = 1.0;  // max sample / bound; deep: Sun >= 18° below
  double worst_channel_ratio = 0.0;
  for (int frame = 0; frame < 120; ++frame) {
    const glm::dmat3 m = random_rotation(rng);
    const double h = std::vector<double>{0.0, 2000.0, 12000.0, 88000.0, 91000.0, 150000.0}[frame % 6];
    const double radius = 6371000.0;
    const double sun_el = -(5.0 + 85.0 * u01(rng)) * kDeg, sun_az = u01(rng) * 2.0 * kPi;
    const glm::dvec3 sun_enu(std::cos(sun_el) * std::sin(sun_az), std::cos(sun_el) * std::cos(sun_az), std::sin(sun_el));
    const glm::dvec3 sun = m * sun_enu;
    const night::BackgroundSettings s{};
    const double bound = night::night_background_max_luminance(m, sun, h, radius, s);
    const glm::dvec3 bound_rgb = night::night_background_max_rgb(m, sun, h, radius, s);
    const double dip = std::acos(radius / (radius + h));
    double max_sample = 0.0;
    glm::dvec3 max_rgb(0.0);
    for (int i = 0; i < 4000; ++i) {
      glm::dvec3 d = random_unit(rng);
      if (i < 1000) d = glm::normalize(glm::dvec3(d.x, d.y, 0.03 * std::abs(d.z) - std::sin(dip)));  // the horizon
      if (d.z < -std::sin(dip)) continue;
      const night::BackgroundLuminance l = night::night_background(m * d, sun, m * glm::dvec3(0, 0, 1), h, radius, s);
      max_sample = std::max(max_sample, l.total());
      max_rgb = glm::max(max_rgb, l.rgb());
    }
    EXPECT_LE(max_sample, bound) << "frame " << frame;
    for (int c = 0; c < 3; ++c) {
      EXPECT_LE(max_rgb[c], bound_rgb[c]) << "frame " << frame;
      worst_channel_ratio = std::max(worst_channel_ratio, max_rgb[c] / bound_rgb[c]);
    }
    worst_ratio = std::max(worst_ratio, max_sample / bound);
    if (sun_el <= -18.0 * kDeg) loosest_deep = std::min(loosest_deep, max_sample / bound);
  }
  // Typical values: a dark site, the Sun 30° below the horizon.
  const glm::dmat3 m(1.0);
  const double bound_ground =
      night::night_background_max_luminance(m, glm::dvec3(0.0, std::cos(30 * kDeg), -std::sin(30 * kDeg)), 0.0, 6371000.0);
  std::printf("[ night twin ] background bound: largest sampled luminance / bound over 120 frames (Sun 5-90 deg below, "
              "eye 0-150 km, 4000 directions above -dip each) %.3f (per channel %.3f); loosest with the Sun >= 18 deg "
              "below %.3f; sea level, Sun 30 deg below: %.3e cd/m^2 = %.0f S10\n",
              worst_ratio, worst_channel_ratio, loosest_deep, bound_ground, night::s10_from_luminance(bound_ground));
  EXPECT_LE(worst_ratio, 1.0);
  EXPECT_GT(loosest_deep, 0.2);  // useful: not a wild over-estimate
}

}  // namespace
