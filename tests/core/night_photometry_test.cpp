// The photometry of the night sky (plugin/core/night_sky): magnitudes, star
// colours and footprint, the limiting-magnitude cull, the Moon (Jensen et al.
// 2001 eqs 1–5 against quadrature and the measured phase law), the diffuse
// background (against Leinert's zodiacal table, ERFA's galactic frame and the
// issue's moonless-night illuminance) and the optional night vision.
// Figures are printed with the prefix "[ night ]" and quoted in docs/NIGHT_SKY.md.
#include <erfa.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "core/atmosphere/atmosphere_model.h"
#include "core/night_sky/background.h"
#include "core/night_sky/moon_photometry.h"
#include "core/night_sky/night_vision.h"
#include "core/night_sky/star_photometry.h"
#include "core/spectral/colorimetry.h"
#include "core/spectral/spectral_atmosphere.h"

using namespace atmo;
namespace night = atmo::core::night;

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

bool finite3(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// CIE 1960 UCS (u, v) of a linear sRGB colour.
glm::dvec2 uv1960(const glm::dvec3& rgb) {
  const glm::dvec3 xyz = glm::inverse(spectral::linear_srgb_from_xyz()) * rgb;
  const double d = xyz.x + 15.0 * xyz.y + 3.0 * xyz.z;
  return {4.0 * xyz.x / d, 6.0 * xyz.y / d};
}

// The project's transmittance (CPU twin of the GPU table) from sea level straight up, per channel.
glm::dvec3 zenith_transmittance() {
  static const glm::dvec3 t = [] {
    core::AtmosphereSettings settings;  // 40 km visibility
    auto atm = core::make_atmosphere_parameters(settings, 6371000.0, 1.0);
    auto table = core::compute_transmittance_table(atm, core::kTransmittanceWidth, core::kTransmittanceHeight);
    glm::vec3 v = twin::transmittance_to_sun(atm, table, glm::vec2(table.width, table.height), atm.bottom_radius_m,
                                             1.0f);
    return glm::dvec3(v);
  }();
  return t;
}

// A direction in ICRS from right ascension and declination (degrees).
glm::dvec3 radec(double ra_deg, double dec_deg) {
  const double a = ra_deg * kDeg, d = dec_deg * kDeg;
  return {std::cos(d) * std::cos(a), std::cos(d) * std::sin(a), std::sin(d)};
}

// The Sun on the ecliptic at longitude lambda, ICRS.
glm::dvec3 sun_on_ecliptic(double lambda) {
  const double e = night::kObliquityJ2000Rad;
  return {std::cos(lambda), std::sin(lambda) * std::cos(e), std::sin(lambda) * std::sin(e)};
}

// Leinert et al. 1998 Table 17 (zodiacal light at 500 nm, 1e-8 W m^-2 sr^-1 um^-1),
// rows: helioecliptic longitude difference, columns: ecliptic latitude; 0 = not tabulated.
const double kLeinertBeta[] = {0, 5, 10, 15, 20, 25, 30, 45, 60, 75};
const double kLeinertDlam[] = {0, 5, 10, 15, 20, 25, 30, 35, 40, 45, 60, 75, 90, 105, 120, 135, 150, 165, 180};
const double kLeinertTable[19][10] = {
    {0, 0, 0, 3140, 1610, 985, 640, 275, 150, 100},     {0, 0, 0, 2940, 1540, 945, 625, 271, 150, 100},
    {0, 0, 4740, 2470, 1370, 865, 590, 264, 148, 100},  {11500, 6780, 3440, 1860, 1110, 755, 525, 251, 146, 100},
    {6400, 4480, 2410, 1410, 910, 635, 454, 237, 141, 99}, {3840, 2830, 1730, 1100, 749, 545, 410, 223, 136, 97},
    {2480, 1870, 1220, 845, 615, 467, 365, 207, 131, 95}, {1650, 1270, 910, 680, 510, 397, 320, 193, 125, 93},
    {1180, 940, 700, 530, 416, 338, 282, 179, 120, 92},   {910, 730, 555, 442, 356, 292, 250, 166, 116, 90},
    {505, 442, 352, 292, 243, 209, 183, 134, 104, 86},    {338, 317, 269, 227, 196, 172, 151, 116, 93, 82},
    {259, 251, 225, 193, 166, 147, 132, 104, 86, 79},     {212, 210, 197, 170, 150, 133, 119, 96, 82, 77},
    {188, 186, 177, 154, 138, 125, 113, 90, 77, 74},      {179, 178, 166, 147, 134, 122, 110, 90, 77, 73},
    {179, 178, 165, 148, 137, 127, 116, 96, 79, 72},      {196, 192, 179, 165, 151, 141, 131, 104, 82, 72},
    {230, 212, 195, 178, 163, 148, 134, 105, 83, 72}};
}  // namespace

// --- Magnitudes and units ------------------------------------------------------------------

TEST(NightStars, ZeroPointAgreesWithTheProjectSunAndTheMoon) {
  const double sun_v = night::illuminance_from_magnitude(-26.74);
  const double sun_model = night::sun_illuminance_at_1au_lux();
  const double moon_v = night::illuminance_from_magnitude(-12.7);
  std::printf("[ night ] V = -26.74 -> %.0f lx; the project's solar spectrum through CIE Y: %.0f lx (%+.2f %%)\n",
              sun_v, sun_model, 100.0 * (sun_v / sun_model - 1.0));
  std::printf("[ night ] V = -12.7 (full Moon) -> %.3f lx; V = 0 -> %.3g lx; V = 6 -> %.3g lx\n", moon_v,
              night::illuminance_from_magnitude(0.0), night::illuminance_from_magnitude(6.0));
  const double jensen_sun = night::jensen_irradiance_w_m2(-26.74);
  std::printf("[ night ] Jensen eq 6: V = -26.74 -> %.0f W/m^2 (TSI 1361); implied efficacy E_lux/E_W = %.1f lm/W "
              "(the 5772 K solar spectrum: %.1f lm/W); eq 7 adds 0.4 mag: x%.3f\n",
              jensen_sun, night::illuminance_from_magnitude(0.0) / night::jensen_irradiance_w_m2(0.0),
              sun_model / spectral::kTotalSolarIrradiance,
              night::jensen_irradiance_w_m2(0.0, true) / night::jensen_irradiance_w_m2(0.0));
  EXPECT_NEAR(sun_v / sun_model, 1.0, 0.02);
  EXPECT_GT(moon_v, 0.28);
  EXPECT_LT(moon_v, 0.33);
  for (double v : {-26.74, -1.46, 0.0, 6.5}) {
    EXPECT_NEAR(night::magnitude_from_illuminance(night::illuminance_from_magnitude(v)), v, 1e-12);
  }
  EXPECT_TRUE(std::isinf(night::magnitude_from_illuminance(0.0)));
}

TEST(NightStars, SurfaceBrightnessConversions) {
  const double s10 = night::luminance_from_s10(1.0);
  const double l216 = night::luminance_from_mag_per_arcsec2(21.6), l220 = night::luminance_from_mag_per_arcsec2(22.0);
  std::printf("[ night ] 1 S10 = %.4g cd/m^2 = %.3f mag/arcsec^2; 21.6 mag/arcsec^2 = %.3g cd/m^2; 22.0 = %.3g cd/m^2; "
              "L = %.5g * 10^(-0.4 S)\n",
              s10, night::mag_per_arcsec2_from_luminance(s10), l216, l220, night::luminance_from_mag_per_arcsec2(0.0));
  EXPECT_NEAR(night::mag_per_arcsec2_from_luminance(s10), 27.78, 0.005);  // 10 + 2.5 log10(3600^2)
  EXPECT_NEAR(l216, 2.48e-4, 0.02e-4);
  EXPECT_NEAR(l220, 1.71e-4, 0.02e-4);
  EXPECT_NEAR(night::s10_from_luminance(night::luminance_from_s10(145.0)), 145.0, 1e-9);
  EXPECT_NEAR(night::mag_per_arcsec2_from_luminance(night::luminance_from_mag_per_arcsec2(21.9)), 21.9, 1e-12);
}

// --- Colour ------------------------------------------------------------------------------

TEST(NightStars, TemperatureFromBVBallesterosBeatsJensen) {
  struct Star {
    const char* name;
    double bv, teff;  // B−V (Hipparcos / BSC) and a published effective temperature
  };
  // T_eff: Sun (IAU 2015), Procyon A 6530 K, Capella (mean of Aa/Ab) ~5000 K,
  // Pollux 4666 K, Arcturus 4286 K, Aldebaran 3910 K, Betelgeuse ~3600 K, Vega 9600 K.
  const Star stars[] = {{"Sun", 0.65, 5772}, {"Procyon", 0.42, 6530}, {"Capella", 0.80, 5000},
                        {"Pollux", 1.00, 4666}, {"Arcturus", 1.23, 4286}, {"Aldebaran", 1.54, 3910},
                        {"Betelgeuse", 1.85, 3600}, {"Vega", 0.00, 9600}};
  double err_b = 0.0, err_j = 0.0;
  for (const Star& s : stars) {
    const double tb = night::temperature_from_bv_ballesteros(s.bv), tj = night::temperature_from_bv_jensen(s.bv);
    std::printf("[ night ] %-10s B-V %+.2f: T_eff %5.0f K; Ballesteros %5.0f K (%+5.1f %%), Jensen eq 8 %5.0f K (%+5.1f %%)\n",
                s.name, s.bv, s.teff, tb, 100.0 * (tb / s.teff - 1.0), tj, 100.0 * (tj / s.teff - 1.0));
    err_b += std::abs(std::log(tb / s.teff));
    err_j += std::abs(std::log(tj / s.teff));
    EXPECT_NEAR(tb / s.teff, 1.0, 0.08) << s.name;
  }
  std::printf("[ night ] mean |ln(T/T_eff)|: Ballesteros %.3f, Jensen %.3f\n", err_b / 8, err_j / 8);
  EXPECT_LT(err_b, 0.5 * err_j);
  // The clamp.
  EXPECT_EQ(night::temperature_from_bv_ballesteros(5.0), night::temperature_from_bv_ballesteros(night::kMaxBV));
  EXPECT_EQ(night::temperature_from_bv_ballesteros(-1.0), night::temperature_from_bv_ballesteros(night::kMinBV));
  EXPECT_TRUE(std::isfinite(night::temperature_from_bv_jensen(-0.9)));
}

TEST(NightStars, BlackBodyColoursFollowThePlanckianLocus) {
  // Jensen et al. 2001's temperature -> chromaticity table (CIE 1960 u, v), an independent reference.
  struct Row {
    double t, u, v;
  };
  const Row rows[] = {{25000, 0.18293, 0.27407}, {10000, 0.19031, 0.29325}, {6667, 0.19960, 0.30918},
                      {5000, 0.21140, 0.32309},  {4000, 0.22507, 0.33436},  {3077, 0.24787, 0.34653},
                      {2000, 0.30496, 0.35906}};
  double worst = 0.0;
  for (const Row& r : rows) {
    const glm::dvec3 rgb = night::blackbody_rgb(r.t);
    const glm::dvec2 uv = uv1960(rgb);
    worst = std::max({worst, std::abs(uv.x - r.u), std::abs(uv.y - r.v)});
    EXPECT_NEAR(night::rgb_luminance(rgb), 1.0, 1e-9);
  }
  std::printf("[ night ] black body -> CIE 1931 -> linear sRGB vs Jensen's Planckian (u, v) table: worst %.5f\n", worst);
  EXPECT_LT(worst, 0.002);  // 2000 K is outside sRGB: its clamped colour stays close to the locus

  const glm::dvec3 white = night::blackbody_rgb(6504.0);
  EXPECT_NEAR(white.r, 1.0, 0.1);
  EXPECT_NEAR(white.b, 1.0, 0.1);

  struct Star {
    const char* name;
    double v, bv;
  };
  const Star stars[] = {{"Sirius", -1.46, 0.00}, {"Vega", 0.03, 0.00}, {"Rigel", 0.13, -0.03},
                        {"Betelgeuse", 0.42, 1.85}, {"Antares", 0.91, 1.83}};
  for (const Star& s : stars) {
    const glm::dvec3 c = night::star_rgb_from_bv(s.bv);
    const double e = night::illuminance_from_magnitude(s.v);
    std::printf("[ night ] %-10s V %+.2f B-V %+.2f: E = %.3g lx outside the air, rgb (%.3f, %.3f, %.3f), "
                "RGB illuminance (%.3g, %.3g, %.3g) lx\n",
                s.name, s.v, s.bv, e, c.r, c.g, c.b, e * c.r, e * c.g, e * c.b);
    EXPECT_TRUE(finite3(c));
    EXPECT_NEAR(night::rgb_luminance(c), 1.0, 1e-9);
    EXPECT_LE(std::max({c.r, c.g, c.b}), night::star_max_channel_factor() + 1e-12);
  }
  const glm::dvec3 vega = night::star_rgb_from_bv(0.0), betelgeuse = night::star_rgb_from_bv(1.85);
  EXPECT_GT(vega.b, vega.r);
  EXPECT_GT(betelgeuse.r, betelgeuse.g);
  EXPECT_GT(betelgeuse.g, betelgeuse.b);
  std::printf("[ night ] largest channel of any star colour (the cull's factor): %.3f\n", night::star_max_channel_factor());
  for (double bv = -1.0; bv <= 6.0; bv += 0.01) EXPECT_TRUE(finite3(night::star_rgb_from_bv(bv))) << bv;
}

// --- Footprint -------------------------------------------------------------------------------

TEST(NightStars, FootprintIsSubPixelStable) {
  double erf_worst = 0.0;
  for (double x = -5.0; x <= 5.0; x += 0.001) erf_worst = std::max(erf_worst, std::abs(night::erf_approx(x) - std::erf(x)));
  EXPECT_LT(erf_worst, 2e-7);

  // The star at (ox, oy) in pixel units; pixel (i, j) has its centre at (i + 0.5, j + 0.5). The pass
  // draws every pixel whose centre is within kStarFootprintRadiusPx of the star along each axis.
  const int r = night::kStarFootprintRadiusPx;
  auto drawn_sum = [&](double ox, double oy, auto weight) {
    double sum = 0.0;
    for (int j = -r - 1; j <= r + 1; ++j) {
      for (int i = -r - 1; i <= r + 1; ++i) {
        const double dx = i + 0.5 - ox, dy = j + 0.5 - oy;
        if (std::abs(dx) <= r && std::abs(dy) <= r) sum += weight(dx, dy);
      }
    }
    return sum;
  };
  double lo = 1e9, hi = 0.0, naive_lo = 1e9, naive_hi = 0.0;
  for (double oy = 0.0; oy < 1.0; oy += 0.05) {
    for (double ox = 0.0; ox < 1.0; ox += 0.05) {
      const double s = drawn_sum(ox, oy, [](double dx, double dy) { return night::star_footprint_weight(dx, dy); });
      lo = std::min(lo, s);
      hi = std::max(hi, s);
      // The naive alternative for contrast: a narrow Gaussian point-sampled at pixel centres.
      const double n = drawn_sum(ox, oy, [](double dx, double dy) {
        const double sigma = 0.35;
        return std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma)) / (2 * kPi * sigma * sigma);
      });
      naive_lo = std::min(naive_lo, n);
      naive_hi = std::max(naive_hi, n);
    }
  }
  std::printf("[ night ] footprint sigma %.2f px, drawn within +-%d px: sum over pixels %.5f .. %.5f for sub-pixel "
              "offsets (spread %.3f %%); peak pixel %.4f; a point-sampled 0.35 px Gaussian would spread %.1f %%\n",
              night::kStarFootprintSigmaPx, r, lo, hi, 100.0 * (hi - lo) / hi, night::star_footprint_peak(),
              100.0 * (naive_hi - naive_lo) / naive_hi);
  EXPECT_LT((hi - lo) / hi, 0.01);
  EXPECT_GT(lo, 0.997);  // truncation loss
  EXPECT_LT(hi, 1.0 + 1e-6);
  EXPECT_GT((naive_hi - naive_lo) / naive_hi, 0.05);  // the check above does discriminate
  EXPECT_NEAR(night::star_footprint_peak(), 0.2756, 0.0005);
  // No position gives a pixel more than the peak.
  for (double d = -1.0; d <= 1.0; d += 0.01) EXPECT_LE(night::star_footprint_weight(d, 0.3 * d), night::star_footprint_peak() + 1e-12);
}

TEST(NightStars, PixelSolidAngleSumsToTheFrustum) {
  const double fov_y = 60.0 * kDeg, w = 1280, h = 720;
  const double t = std::tan(0.5 * fov_y), aspect = w / h;
  double sum = 0.0;
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const double x = ((i + 0.5) / w * 2.0 - 1.0) * t * aspect, y = ((j + 0.5) / h * 2.0 - 1.0) * t;
      sum += night::pixel_solid_angle_sr(t, h, 1.0 / std::sqrt(1.0 + x * x + y * y));
    }
  }
  // Solid angle of a rectangular pyramid with half-angles a, b: 4 asin(sin a sin b).
  const double frustum = 4.0 * std::asin(std::sin(std::atan(t * aspect)) * std::sin(std::atan(t)));
  std::printf("[ night ] 1280x720, 60 deg vertical: centre pixel %.4g sr; sum of pixels %.6f sr, frustum %.6f sr\n",
              night::pixel_solid_angle_sr(t, h), sum, frustum);
  EXPECT_NEAR(sum / frustum, 1.0, 1e-4);
}

// --- The cull ------------------------------------------------------------------------------------

TEST(NightStars, LimitingMagnitudeIsTheDisplayThreshold) {
  const double t = std::tan(30.0 * kDeg), omega = night::pixel_solid_angle_sr(t, 720);
  const double peak = night::star_footprint_peak(), channel = night::star_max_channel_factor();
  auto encode = [](double y) { return double(twin::encode_display_srgb(glm::vec3(float(y))).x); };

  struct Case {
    const char* name;
    double background, exposure;
  };
  // Exposures put the background at 0.05 (night, dark sky), 0.18 (twilight and day).
  const Case cases[] = {{"moonless night", 2.0e-4, 0.05 / 2.0e-4},
                        {"civil twilight", 3.0, 0.18 / 3.0},
                        {"day, blue sky", 5000.0, 0.18 / 5000.0}};
  double previous = 1e9;
  for (const Case& c : cases) {
    const double v = night::display_limiting_magnitude(c.background, c.exposure, omega);
    // A star exactly at the limit moves the display by one step; 0.1 mag fainter it does not.
    auto display_change = [&](double mag) {
      const double dl = night::illuminance_from_magnitude(mag) * channel * peak / omega;
      const double y0 = c.exposure * c.background;
      return encode(y0 + c.exposure * dl) - encode(y0);
    };
    std::printf("[ night ] %-15s background %.3g cd/m^2, exposure %.3g: limiting V %.2f (display change at the limit "
                "%.3f/255, 0.1 mag fainter %.3f/255)\n",
                c.name, c.background, c.exposure, v, 255.0 * display_change(v), 255.0 * display_change(v + 0.1));
    EXPECT_NEAR(255.0 * display_change(v), 1.0, 0.02);
    EXPECT_LT(255.0 * display_change(v + 0.1), 1.0);
    EXPECT_LT(v, previous);
    previous = v;
  }
  EXPECT_GT(night::display_limiting_magnitude(2.0e-4, 0.05 / 2.0e-4, omega), 6.0);
  EXPECT_LT(night::display_limiting_magnitude(5000.0, 0.18 / 5000.0, omega), -4.6);  // not even Venus: no night pass
  // Saturated output: nothing to draw.
  EXPECT_TRUE(std::isinf(night::display_limiting_magnitude(1e4, 1.0, omega)));
  EXPECT_LT(night::display_limiting_magnitude(1e4, 1.0, omega), 0.0);
  // A linear (HDR) threshold is the closed form.
  night::DisplayThreshold hdr{night::DisplayThreshold::Kind::kLinear, 1e-3};
  const double v_hdr = night::display_limiting_magnitude(1.0, 2.0, omega, hdr);
  const double expected = night::magnitude_from_illuminance(1e-3 / 2.0 * omega / (channel * peak));
  EXPECT_NEAR(v_hdr, expected, 1e-9);
  // Transmittance dims: a star behind T = 0.5 must be 0.75 mag brighter.
  EXPECT_NEAR(night::display_limiting_magnitude(1.0, 2.0, omega, hdr, 0.5), expected - 2.5 * std::log10(2.0), 1e-9);
}

TEST(NightStars, NakedEyeLimitFollowsSchaefer) {
  // Schaefer's night branch in closed form (the sky-quality-meter relation):
  // NELM = 7.93 - 5 log10(10^(4.316 - S/5) + 1), S in V mag/arcsec^2.
  double worst = 0.0;
  for (double s = 19.0; s <= 23.0; s += 0.1) {
    const double ours = night::naked_eye_limiting_magnitude(night::luminance_from_mag_per_arcsec2(s));
    const double ref = 7.93 - 5.0 * std::log10(std::pow(10.0, 4.316 - s / 5.0) + 1.0);
    worst = std::max(worst, std::abs(ours - ref));
  }
  const double dark = night::naked_eye_limiting_magnitude(night::luminance_from_mag_per_arcsec2(21.9));
  const double day = night::naked_eye_limiting_magnitude(5000.0);
  std::printf("[ night ] naked-eye limit: dark sky 21.9 mag/arcsec^2 -> V %.2f; 19 -> %.2f; blue day sky 5000 cd/m^2 "
              "-> %.2f; worst difference from the closed form (19..23 mag/arcsec^2) %.4f mag\n",
              dark, night::naked_eye_limiting_magnitude(night::luminance_from_mag_per_arcsec2(19.0)), day, worst);
  EXPECT_LT(worst, 0.01);
  EXPECT_GT(dark, 6.3);
  EXPECT_LT(dark, 6.9);
  EXPECT_GT(day, -5.0);  // Venus (-4.6) is at the edge of daytime naked-eye visibility
  EXPECT_LT(day, -3.0);
  // Monotonic and continuous across the rod/cone switch.
  double prev = night::naked_eye_limiting_magnitude(1e-6);
  for (double l = 1e-6; l < 1e5; l *= 1.01) {
    const double m = night::naked_eye_limiting_magnitude(l);
    EXPECT_LE(m, prev + 1e-12);
    EXPECT_LT(prev - m, 0.02) << l;
    prev = m;
  }
  EXPECT_NEAR(night::naked_eye_limiting_magnitude(2e-4, 2.0), night::naked_eye_limiting_magnitude(2e-4) - 2.5 * std::log10(2.0),
              1e-9);
}

// --- The Moon -------------------------------------------------------------------------------------

TEST(NightMoon, PhaseFunctionsHaveTheirLimitsAndNoNaN) {
  EXPECT_EQ(night::lommel_seeliger_phase(0.0), 1.0);
  EXPECT_EQ(night::lommel_seeliger_phase(kPi), 0.0);
  EXPECT_NEAR(night::lommel_seeliger_phase(1e-5), 1.0, 1e-8);
  EXPECT_NEAR(night::lommel_seeliger_phase(kPi - 1e-5), 0.0, 1e-4);
  // Quarter: 1 - sin 45° tan 45° ln(cot 22.5°) = 1 - 0.70711 · 0.88137.
  EXPECT_NEAR(night::lommel_seeliger_phase(0.5 * kPi), 1.0 - std::sqrt(0.5) * std::log(1.0 + std::sqrt(2.0)), 1e-12);
  EXPECT_EQ(night::hapke_retrodirective(0.0), 2.0);
  EXPECT_EQ(night::hapke_retrodirective(0.5 * kPi), 1.0);
  EXPECT_NEAR(night::hapke_retrodirective(0.5 * kPi - 1e-7), 1.0, 1e-4);  // continuous at pi/2
  EXPECT_NEAR(night::hapke_scattering(0.0), 1.025, 1e-12);
  EXPECT_NEAR(night::earthshine_fraction(kPi), 0.5 * 0.19 / 1905.0, 1e-15);
  EXPECT_EQ(night::earthshine_fraction(0.0), 0.0);
  double prev_ls = 2.0, prev_b = 3.0;
  for (int i = 0; i <= 100000; ++i) {
    const double p = kPi * i / 100000.0;
    const double ls = night::lommel_seeliger_phase(p), b = night::hapke_retrodirective(p);
    const double s = night::hapke_scattering(p), e = night::earthshine_fraction(p);
    ASSERT_TRUE(std::isfinite(ls) && std::isfinite(b) && std::isfinite(s) && std::isfinite(e)) << p;
    EXPECT_LE(ls, prev_ls + 1e-12);
    EXPECT_LE(b, prev_b + 1e-12);
    EXPECT_GE(s, 0.0);
    prev_ls = ls;
    prev_b = b;
  }
}

TEST(NightMoon, FullMoonIlluminance) {
  const glm::dvec3 t = zenith_transmittance(), c = night::moon_color_rgb();
  const double t_lum = night::rgb_luminance(c * t);  // luminance transmittance of moonlight
  std::printf("[ night ] zenith transmittance (project model, 40 km visibility) RGB (%.3f, %.3f, %.3f), for moonlight %.3f\n",
              t.r, t.g, t.b, t_lum);
  std::printf("[ night ] moonlight colour (solar spectrum x lunar ramp) rgb (%.3f, %.3f, %.3f); calibrated albedo at full "
              "Moon %.4f (Jensen 0.072)\n",
              c.r, c.g, c.b, night::moon_calibrated_albedo(0.0));
  for (double deg : {0.0, 2.0, 5.0}) {
    const double p = deg * kDeg;
    const double ks = night::illuminance_from_magnitude(night::moon_magnitude_krisciunas_schaefer(p));
    const double jensen = night::moon_illuminance_jensen_lux(p);
    const double hapke = night::moon_illuminance_hapke(p, night::kMoonMeanDistanceM, 1.0, 0.072, 0.072).total();
    const double used = night::moon_illuminance(p).total();
    std::printf("[ night ] full Moon phase %.0f deg, mean distance: outside the air K&S %.3f lx, Jensen eq 5 %.3f lx, "
                "Hapke C=0.072 %.3f lx; used %.3f lx -> at the ground, Moon at the zenith %.3f lx\n",
                deg, ks, jensen, hapke, used, used * t_lum);
    EXPECT_GT(used * t_lum, 0.1);
    EXPECT_LT(used * t_lum, 0.3);
    EXPECT_NEAR(used, ks, 1e-3 * ks);  // earthshine is ~0 at full Moon
  }
  EXPECT_GT(t_lum, 0.75);
  EXPECT_LT(t_lum, 0.92);
  // Perigee and apogee (356 500 / 406 700 km) change it by the inverse square.
  const double perigee = night::moon_illuminance(0.0, 356500e3).total(), apogee = night::moon_illuminance(0.0, 406700e3).total();
  EXPECT_NEAR(perigee / apogee, std::pow(406700.0 / 356500.0, 2.0), 1e-6);
  // Red-weighted like the ramp: more red than blue relative to the Sun.
  const glm::dvec3 sun = night::zodiacal_color_rgb();
  EXPECT_GT(c.r / c.b, sun.r / sun.b);
  EXPECT_NEAR(night::rgb_luminance(c), 1.0, 1e-9);
}

TEST(NightMoon, PhaseCurveUsesTheMeasuredLaw) {
  double worst_shape = 0.0;
  for (double deg = 0.0; deg <= 180.0; deg += 15.0) {
    const double p = deg * kDeg;
    const double ks = night::illuminance_from_magnitude(night::moon_magnitude_krisciunas_schaefer(p));
    const night::MoonIlluminance used = night::moon_illuminance(p);
    const double hapke072 = night::moon_illuminance_hapke(p, night::kMoonMeanDistanceM, 1.0, 0.072, 0.072).sun_lux;
    std::printf("[ night ] phase %3.0f deg: K&S %.3e lx, Jensen eq 5 %.3e, Hapke(C=0.072) %.3e, C(phi) %.4f, used: "
                "sun %.3e + earthshine %.3e lx\n",
                deg, ks, night::moon_illuminance_jensen_lux(p), hapke072, night::moon_calibrated_albedo(p),
                used.sun_lux, used.earthshine_lux);
    if (p <= night::kMoonPhaseLawLimitRad + 1e-12) {
      EXPECT_NEAR(used.sun_lux / ks, 1.0, 1e-9);
      // The Hapke shape with one albedo follows the measured law within 20 %.
      const double shape = (hapke072 / ks) / (night::moon_illuminance_hapke(0.0, night::kMoonMeanDistanceM, 1.0, 0.072, 0.072).sun_lux /
                                              night::illuminance_from_magnitude(night::moon_magnitude_krisciunas_schaefer(0.0)));
      worst_shape = std::max(worst_shape, std::abs(std::log(shape)));
    }
  }
  std::printf("[ night ] Hapke phase curve vs K&S (0..150 deg), one albedo: worst %.1f %%\n", 100.0 * std::expm1(worst_shape));
  EXPECT_LT(worst_shape, std::log(1.22));  // measured 20.4 % (at 105 deg)
  // Beyond the law's range the light falls continuously to the earthshine at new Moon.
  const double limit = night::kMoonPhaseLawLimitRad;
  EXPECT_NEAR(night::moon_illuminance(limit + 1e-9).sun_lux / night::moon_illuminance(limit).sun_lux, 1.0, 1e-6);
  double prev = 1e9;
  for (double p = 0.0; p <= kPi; p += 0.001) {
    const double e = night::moon_illuminance(p).sun_lux;
    EXPECT_LE(e, prev * (1.0 + 1e-12));
    prev = e;
  }
  EXPECT_EQ(night::moon_illuminance(kPi).sun_lux, 0.0);
  const double new_moon = night::moon_illuminance(kPi).earthshine_lux;
  std::printf("[ night ] new Moon: earthshine on the disc %.3g lx (V %.2f); Jensen eq 1 at the Moon %.2f lx\n", new_moon,
              night::magnitude_from_illuminance(new_moon),
              night::earthshine_fraction(kPi) * night::sun_illuminance_at_1au_lux());
  EXPECT_GT(new_moon, 0.0);
}

TEST(NightMoon, DiscIntegralMatchesTheClosedForm) {
  // Polar midpoint quadrature of the disc radiance over the unit disc (the Moon
  // at the mean distance, seen along +z): E = (r/d)^2 ∫∫ L rho drho dtheta.
  const glm::dvec3 view(0.0, 0.0, 1.0), right(1.0, 0.0, 0.0), up(0.0, 1.0, 0.0);
  const double k = std::pow(night::kMoonRadiusM / night::kMoonMeanDistanceM, 2.0);
  const int nr = 1500, nt = 3000;
  for (auto calibration : {night::MoonCalibration::kMagnitudeLaw, night::MoonCalibration::kJensen}) {
    for (double deg : {0.0, 5.0, 20.0, 45.0, 90.0, 120.0, 150.0, 165.0}) {
      const double p = deg * kDeg;
      const glm::dvec3 sun(std::sin(p), 0.0, std::cos(p));
      const night::MoonDiscLighting lighting = night::moon_disc_lighting(p, night::kMoonMeanDistanceM, 1.0, calibration);
      double sum = 0.0;
      for (int i = 0; i < nr; ++i) {
        const double rho = (i + 0.5) / nr;
        for (int j = 0; j < nt; ++j) {
          const double th = 2.0 * kPi * (j + 0.5) / nt;
          const glm::dvec3 n = night::moon_disc_normal({rho * std::cos(th), rho * std::sin(th)}, view, right, up);
          sum += night::moon_disc_luminance(lighting, n, sun, view) * rho;
        }
      }
      const double quadrature = k * sum * (1.0 / nr) * (2.0 * kPi / nt);
      const bool measured = calibration == night::MoonCalibration::kMagnitudeLaw;
      const double closed = measured ? night::moon_illuminance(p).total()
                                     : night::moon_illuminance_hapke(p, night::kMoonMeanDistanceM, 1.0, 0.072, 0.072).total();
      std::printf("[ night ] disc quadrature (%s) phase %3.0f deg: %.5e lx, closed form %.5e lx (%+.4f %%)\n",
                  measured ? "calibrated" : "C=0.072   ", deg, quadrature, closed, 100.0 * (quadrature / closed - 1.0));
      EXPECT_NEAR(quadrature / closed, 1.0, deg <= 150.0 ? 0.002 : 0.01) << deg;
    }
  }
}

TEST(NightMoon, DiscRadianceIsFiniteEverywhere) {
  const glm::dvec3 view(0.0, 0.0, 1.0), right(1.0, 0.0, 0.0), up(0.0, 1.0, 0.0);
  long count = 0;
  for (int i = 0; i <= 720; ++i) {
    const double p = kPi * i / 720.0;
    const glm::dvec3 sun(std::sin(p), 0.0, std::cos(p));
    const night::MoonDiscLighting lighting = night::moon_disc_lighting(p);
    auto check = [&](const glm::dvec3& n) {
      const glm::dvec3 l = night::moon_disc_radiance_rgb(lighting, n, sun, view);
      ASSERT_TRUE(finite3(l)) << p;
      ASSERT_GE(std::min({l.r, l.g, l.b}), 0.0);
      ++count;
    };
    for (int j = 0; j < 360; ++j) {
      const double th = 2.0 * kPi * j / 360.0;
      check(glm::dvec3(std::cos(th), std::sin(th), 0.0));  // the limb
      // The terminator: n perpendicular to the Sun, on the visible side.
      const glm::dvec3 a = glm::normalize(glm::cross(sun, up)), b = up;
      const glm::dvec3 t = std::cos(th) * a + std::sin(th) * b;
      check(t);
      check(night::moon_disc_normal({1.5 * std::cos(th), 1.5 * std::sin(th)}, view, right, up));  // outside: pulled in
    }
    for (int y = -20; y <= 20; ++y)
      for (int x = -20; x <= 20; ++x) check(night::moon_disc_normal({x / 20.0, y / 20.0}, view, right, up));
    check(view);
    check(sun);
    check(-view);  // the far side: 0
    EXPECT_EQ(night::moon_disc_luminance(lighting, -view, sun, view), 0.0);
  }
  std::printf("[ night ] Moon disc: %ld radiance samples over phases 0..180 deg (limb, terminator, interior), all finite\n",
              count);
  // Extreme distances and sun distances.
  for (double d : {1.0, 1e3, 356500e3, 1e12})
    for (double r : {0.0, 0.98, 1.02, 50.0}) {
      EXPECT_TRUE(std::isfinite(night::moon_illuminance(0.3, d, r).total()));
      EXPECT_TRUE(std::isfinite(night::moon_magnitude_krisciunas_schaefer(0.3, d, r)));
    }
}

// --- The background ------------------------------------------------------------------------

TEST(NightBackground, FramesMatchErfa) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    const double ra = std::atan2(d.y, d.x), dec = std::asin(d.z);
    double l = 0.0, b = 0.0;
    eraIcrs2g(ra, dec, &l, &b);
    const glm::dvec2 ours = night::galactic_lon_lat(d);
    const glm::dvec3 a(std::cos(b) * std::cos(l), std::cos(b) * std::sin(l), std::sin(b));
    const glm::dvec3 o(std::cos(ours.y) * std::cos(ours.x), std::cos(ours.y) * std::sin(ours.x), std::sin(ours.y));
    worst = std::max(worst, glm::length(a - o));
  }
  // The ecliptic pole: third row of ERFA's ICRS -> ecliptic-of-date matrix at J2000.0.
  double rm[3][3];
  eraEcm06(2451545.0, 0.0, rm);
  const glm::dvec3 pole(rm[2][0], rm[2][1], rm[2][2]);
  const double pole_err = glm::length(pole - night::ecliptic_pole_icrs());
  std::printf("[ night ] galactic frame vs eraIcrs2g: worst %.2e rad; ecliptic pole vs eraEcm06(J2000): %.2e rad\n",
              worst, pole_err);
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(pole_err, 2e-7);  // the frame bias (23 mas) and nothing else
}

TEST(NightBackground, AirglowFollowsVanRhijn) {
  const double radius = 6371000.0;
  const night::BackgroundSettings s;
  const double k = radius / (radius + s.airglow_layer_altitude_m);
  double worst = 0.0;
  for (double z = 0.0; z <= 85.0; z += 1.0) {
    const double ours = night::airglow_slant_factor(std::cos(z * kDeg), 0.0, radius);
    const double van_rhijn = 1.0 / std::sqrt(1.0 - k * k * std::pow(std::sin(z * kDeg), 2.0));
    worst = std::max(worst, std::abs(ours / van_rhijn - 1.0));
  }
  const double horizon = night::airglow_slant_factor(0.0, 0.0, radius);
  std::printf("[ night ] airglow slant factor vs van Rhijn (h = 90 km) for z <= 85 deg: worst %.3f %%; horizon %.2f "
              "(van Rhijn %.2f); zenith %.4f\n",
              100.0 * worst, horizon, 1.0 / std::sqrt(1.0 - k * k), night::airglow_slant_factor(1.0, 0.0, radius));
  EXPECT_LT(worst, 0.005);
  EXPECT_NEAR(horizon, 1.0 / std::sqrt(1.0 - k * k), 0.1);
  EXPECT_NEAR(night::airglow_slant_factor(1.0, 0.0, radius), 1.0, 1e-9);
  // Looking down from an aircraft: the ground hides it; from above the layer, two crossings.
  EXPECT_EQ(night::airglow_slant_factor(-1.0, 10000.0, radius), 0.0);
  EXPECT_EQ(night::airglow_slant_factor(1.0, 200000.0, radius), 0.0);
  {
    // From 400 km: a steep ray crosses the layer once before the ground; a grazing one (closest
    // approach 6415 km, between the ground and the layer) crosses it twice.
    const double r0 = radius + 400000.0, rl = radius + s.airglow_layer_altitude_m;
    auto thin_shell = [&](double mu) { return 1.0 / std::sqrt(1.0 - std::pow(r0 / rl, 2.0) * (1.0 - mu * mu)); };
    const double steep = night::airglow_slant_factor(-0.5, 400000.0, radius);
    const double grazing = night::airglow_slant_factor(-0.32, 400000.0, radius);
    std::printf("[ night ] airglow seen from 400 km: steep ray %.3f (thin shell %.3f), grazing ray %.2f (two crossings, "
                "thin shell %.2f)\n", steep, thin_shell(-0.5), grazing, 2.0 * thin_shell(-0.32));
    EXPECT_NEAR(steep / thin_shell(-0.5), 1.0, 0.01);
    EXPECT_NEAR(grazing / (2.0 * thin_shell(-0.32)), 1.0, 0.1);
  }
  // No jump when climbing through the layer, and nothing undefined anywhere.
  double worst_step = 0.0;
  for (double mu : {1.0, 0.5, 0.2, -0.2, -0.5}) {
    double prev = night::airglow_slant_factor(mu, 0.0, radius);
    for (double h = 1.0; h <= 120000.0; h += 1.0) {
      const double f = night::airglow_slant_factor(mu, h, radius);
      worst_step = std::max(worst_step, std::abs(f - prev));
      prev = f;
    }
  }
  std::printf("[ night ] airglow: largest change for a 1 m climb, 0..120 km: %.4f\n", worst_step);
  EXPECT_LT(worst_step, 0.01);
  for (double h : {-400.0, 0.0, 10000.0, 84999.0, 85000.0, 90000.0, 95000.0, 100000.0, 1e6, 5e6, 1e7}) {
    for (int i = 0; i <= 2000; ++i) {
      const double f = night::airglow_slant_factor(-1.0 + i / 1000.0, h, radius);
      ASSERT_TRUE(std::isfinite(f) && f >= 0.0) << h << " " << i;
    }
  }
}

TEST(NightBackground, ZodiacalFitMatchesLeinertTable17) {
  double worst40 = 0.0, worst_all = 0.0;
  int n = 0;
  for (int i = 0; i < 19; ++i) {
    for (int j = 0; j < 10; ++j) {
      const double table = kLeinertTable[i][j];
      if (table <= 0.0) continue;
      const double dl = kLeinertDlam[i] * kDeg, beta = kLeinertBeta[j] * kDeg;
      // Through the vector form: the Sun on the ecliptic at longitude 1 rad, the direction at (lambda_sun + dl, beta).
      const double ls = 1.0, e = night::kObliquityJ2000Rad;
      const glm::dvec3 ecl(std::cos(beta) * std::cos(ls + dl), std::cos(beta) * std::sin(ls + dl), std::sin(beta));
      const glm::dvec3 dir(ecl.x, ecl.y * std::cos(e) - ecl.z * std::sin(e), ecl.y * std::sin(e) + ecl.z * std::cos(e));
      const double ours = night::s10_from_luminance(night::zodiacal_luminance(dir, sun_on_ecliptic(ls))) * 1.28;
      const double rel = std::abs(ours / table - 1.0);
      const double elong = std::acos(std::cos(dl) * std::cos(beta));
      worst_all = std::max(worst_all, rel);
      if (elong >= 40.0 * kDeg) worst40 = std::max(worst40, rel);
      ++n;
    }
  }
  const double pole = night::zodiacal_s10(0.5 * kPi, 0.5 * kPi);
  // Leinert's 1.28 against the project's own photometry: table units -> luminance with the solar spectrum shape.
  const std::vector<double> grid = spectral::wavelength_grid(360.0, 830.0, 5.0);
  std::vector<double> shape;
  for (double nm : grid) shape.push_back(spectral::solar_irradiance_blackbody(nm) / spectral::solar_irradiance_blackbody(500.0));
  const double cd_per_unit = spectral::SpectrumToColor(grid).luminance(shape) * 1e-8 * 1e-3;  // per um -> per nm
  const double s10_of_pole_ours = night::s10_from_luminance(77.0 * cd_per_unit);
  std::printf("[ night ] zodiacal fit vs Leinert Table 17 (%d cells): worst %.1f %% at elongation >= 40 deg, %.1f %% "
              "everywhere; ecliptic pole %.1f S10 (Leinert 60); 90 deg on the ecliptic %.0f S10; Gegenschein %.0f S10\n",
              n, 100.0 * worst40, 100.0 * worst_all, pole, night::zodiacal_s10(0.5 * kPi, 0.0), night::zodiacal_s10(kPi, 0.0));
  std::printf("[ night ] Leinert's pole (77 table units) through the project's solar spectrum and CIE Y: %.1f S10 "
              "(Leinert's factor 1.28: 60.2)\n", s10_of_pole_ours);
  EXPECT_LT(worst40, 0.15);
  EXPECT_LT(worst_all, 0.22);
  EXPECT_NEAR(pole, 60.0, 4.0);
  EXPECT_NEAR(s10_of_pole_ours / 60.2, 1.0, 0.15);
  // Finite and positive in every direction, the Sun included (|beta| <= elongation for real
  // directions; impossible pairs stay finite).
  for (int i = 0; i <= 360; ++i)
    for (int j = -90; j <= 90; ++j) {
      const double z = night::zodiacal_s10(i * 0.5 * kDeg, j * kDeg);
      ASSERT_TRUE(std::isfinite(z) && z >= 0.0) << i << " " << j;
      if (std::abs(j) <= i * 0.5) {
        ASSERT_GT(z, 0.0) << i << " " << j;
      }
    }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    const double z = night::zodiacal_luminance(glm::dvec3(u(rng), u(rng), u(rng)), glm::dvec3(u(rng), u(rng), u(rng)));
    ASSERT_TRUE(std::isfinite(z) && z > 0.0);
  }
  // Continuous at the ecliptic poles (the longitude is undefined there).
  const glm::dvec3 ecliptic_pole = night::ecliptic_pole_icrs();
  const double at_pole = night::zodiacal_luminance(ecliptic_pole, sun_on_ecliptic(0.0));
  for (double l = 0.0; l < 2.0 * kPi; l += 0.5)
    EXPECT_NEAR(night::zodiacal_luminance(ecliptic_pole, sun_on_ecliptic(l)) / at_pole, 1.0, 1e-9);
}

TEST(NightBackground, MilkyWayIsBrighterInThePlane) {
  const night::BackgroundSettings s;
  const double centre = night::starlight_s10(0.0, 0.0, s), anticentre = night::starlight_s10(kPi, 0.0, s);
  const double pole = night::starlight_s10(0.0, 0.5 * kPi, s);
  // Sky average by quadrature over the sphere.
  double sum = 0.0, area = 0.0;
  for (int i = 0; i < 400; ++i) {
    const double b = std::asin(-1.0 + (i + 0.5) / 200.0);
    for (int j = 0; j < 400; ++j) {
      sum += night::starlight_s10(2.0 * kPi * (j + 0.5) / 400.0, b, s);
      area += 1.0;
    }
  }
  std::printf("[ night ] integrated starlight (V > ~6): galactic centre %.0f S10, anticentre %.0f S10, pole %.0f S10, "
              "sky average %.1f S10 (star counts: ~79)\n", centre, anticentre, pole, sum / area);
  EXPECT_GT(centre, 5.0 * pole);
  EXPECT_GT(anticentre, 2.0 * pole);
  EXPECT_NEAR(sum / area, 79.0, 4.0);
  // Continuous at the galactic poles, where the longitude is undefined.
  for (double l = 0.0; l < 2.0 * kPi; l += 0.5)
    EXPECT_NEAR(night::starlight_s10(l, 0.5 * kPi - 1e-4, s) / pole, 1.0, 1e-3);
  // Galactic centre direction (ICRS) is the brightest, the north galactic pole the faintest.
  EXPECT_GT(night::starlight_luminance(radec(266.40500, -28.93617)), night::starlight_luminance(radec(192.85948, 27.12825)));
  // Everything finite for every direction, Sun and zenith.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    const glm::dvec3 d(u(rng), u(rng), u(rng)), sun(u(rng), u(rng), u(rng)), zen(u(rng), u(rng), u(rng));
    const night::BackgroundLuminance b = night::night_background(d, sun, zen, 100000.0 * (u(rng) + 1.0) - 400.0);
    ASSERT_TRUE(std::isfinite(b.total()) && finite3(b.rgb()) && b.total() > 0.0);
  }
  // Degenerate inputs.
  const night::BackgroundLuminance z = night::night_background(glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0), 0.0);
  EXPECT_TRUE(std::isfinite(z.total()));
  EXPECT_NEAR(night::rgb_luminance(night::airglow_color_rgb()), 1.0, 1e-9);
  const glm::dvec3 ag = night::airglow_color_rgb(), st = night::starlight_color_rgb();
  std::printf("[ night ] colours (luminance 1): airglow (%.3f, %.3f, %.3f), zodiacal (%.3f, %.3f, %.3f), starlight "
              "(%.3f, %.3f, %.3f)\n", ag.r, ag.g, ag.b, night::zodiacal_color_rgb().r, night::zodiacal_color_rgb().g,
              night::zodiacal_color_rgb().b, st.r, st.g, st.b);
  EXPECT_GT(ag.g, ag.b);  // the green line and the yellow-red continuum
}

TEST(NightBackground, MoonlessClearNightIsAboutOneMilliLux) {
  // Horizontal illuminance from the whole background over the upper hemisphere
  // (the stars of the catalogue excluded), with a flat transmittance of 0.8.
  struct Config {
    const char* name;
    glm::dvec3 zenith;
    bool dark;  // high galactic and ecliptic latitude: the dark-site zenith of the literature
  };
  const Config configs[] = {{"zenith at the north galactic pole", radec(192.85948, 27.12825), true},
                            {"zenith at the galactic centre", radec(266.40500, -28.93617), false},
                            {"zenith at the galactic anticentre", radec(86.40500, 28.93617), false},
                            {"zenith at RA 0, Dec +45", radec(0.0, 45.0), false}};
  const double transmittance = 0.8;
  for (const Config& c : configs) {
    const glm::dvec3 zen = glm::normalize(c.zenith);
    // The Sun on the ecliptic 30 deg below the horizon.
    double best = 1e9, lambda = 0.0;
    for (int i = 0; i < 3600; ++i) {
      const double l = 2.0 * kPi * i / 3600.0, err = std::abs(glm::dot(zen, sun_on_ecliptic(l)) + 0.5);
      if (err < best) best = err, lambda = l;
    }
    ASSERT_LT(best, 0.01);
    const glm::dvec3 sun = sun_on_ecliptic(lambda);
    const glm::dvec3 east = glm::normalize(glm::cross(glm::dvec3(0.0, 0.0, 1.0), zen)), north = glm::cross(zen, east);
    night::BackgroundLuminance e;  // horizontal illuminance per component, lux
    const int nu = 300, na = 600;
    for (int i = 0; i < nu; ++i) {
      const double mu = (i + 0.5) / nu, sin_z = std::sqrt(1.0 - mu * mu);
      for (int j = 0; j < na; ++j) {
        const double a = 2.0 * kPi * (j + 0.5) / na;
        const glm::dvec3 d = mu * zen + sin_z * (std::cos(a) * north + std::sin(a) * east);
        const night::BackgroundLuminance l = night::night_background(d, sun, zen, 0.0);
        const double w = transmittance * mu * (1.0 / nu) * (2.0 * kPi / na);
        e.airglow += l.airglow * w;
        e.zodiacal += l.zodiacal * w;
        e.starlight += l.starlight * w;
        e.diffuse_galactic += l.diffuse_galactic * w;
        e.cosmic += l.cosmic * w;
      }
    }
    const night::BackgroundLuminance at_zenith = night::night_background(zen, sun, zen, 0.0);
    const double total = e.total();
    std::printf("[ night ] %-34s horizontal %.3g lx (airglow %.0f %%, zodiacal %.0f %%, starlight %.0f %%, diffuse "
                "galactic %.0f %%, cosmic %.1f %%); zenith %.3g cd/m^2 = %.2f mag/arcsec^2 outside the air\n",
                c.name, total, 100 * e.airglow / total, 100 * e.zodiacal / total, 100 * e.starlight / total,
                100 * e.diffuse_galactic / total, 100 * e.cosmic / total, at_zenith.total(),
                night::mag_per_arcsec2_from_luminance(at_zenith.total()));
    EXPECT_GT(total, 3e-4);
    EXPECT_LT(total, 3e-3);
    if (c.dark) {
      EXPECT_GT(night::mag_per_arcsec2_from_luminance(at_zenith.total()), 21.5);
      EXPECT_LT(night::mag_per_arcsec2_from_luminance(at_zenith.total()), 22.1);
    }
  }
}

// --- Night vision -----------------------------------------------------------------------------

TEST(NightVision, PhotopicIdentityScotopicGreyBlue) {
  const night::NightVisionSettings on{true};
  const glm::dvec3 colours[] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}, {1.0, 1.0, 1.0}, {0.8, 0.5, 0.1}};
  for (const glm::dvec3& c : colours) {
    // Off by default: identity at any level.
    EXPECT_EQ(night::night_vision_rgb(c * 1e-5, 1e-5, night::NightVisionSettings{}), c * 1e-5);
    // Photopic: identity.
    EXPECT_EQ(night::night_vision_rgb(c * 10.0, 3.0, on), c * 10.0);
    EXPECT_EQ(night::night_vision_rgb(c * 10.0, 100.0, on), c * 10.0);
    // Scotopic: every colour becomes the same grey-blue.
    const glm::dvec3 out = night::night_vision_rgb(c * 1e-4, 1e-4, on);
    const glm::dvec3 tint = night::scotopic_tint_rgb();
    const double y = night::rgb_luminance(out);
    ASSERT_GT(y, 0.0);
    EXPECT_NEAR(glm::length(out / y - tint), 0.0, 1e-9);
  }
  // A D65 white keeps its luminance; red looks darker, blue brighter (Purkinje).
  const double white = night::rgb_luminance(night::night_vision_rgb(glm::dvec3(1e-4), 1e-4, on));
  EXPECT_NEAR(white, 1e-4, 1e-12);
  const glm::dvec3 red(1e-4, 0.0, 0.0), blue(0.0, 0.0, 1e-4);
  EXPECT_LT(night::rgb_luminance(night::night_vision_rgb(red, 1e-4, on)), night::rgb_luminance(red));
  EXPECT_GT(night::rgb_luminance(night::night_vision_rgb(blue, 1e-4, on)), night::rgb_luminance(blue));
  const glm::dvec3 tint = night::scotopic_tint_rgb();
  EXPECT_GT(tint.b, tint.r);
  std::printf("[ night ] night vision: scotopic tint rgb (%.3f, %.3f, %.3f); D65 V/Y = %.3f; photopic weight at 0.01, "
              "0.1, 1 cd/m^2: %.3f %.3f %.3f\n",
              tint.r, tint.g, tint.b,
              night::scotopic_luminance(glm::inverse(spectral::linear_srgb_from_xyz()) * glm::dvec3(1.0)) /
                  night::rgb_luminance(glm::dvec3(1.0)),
              night::photopic_weight(0.01), night::photopic_weight(0.1), night::photopic_weight(1.0));
  // The weight is monotonic and continuous, finite for any input.
  double prev = 0.0;
  for (double l = 1e-5; l < 10.0; l *= 1.01) {
    const double w = night::photopic_weight(l);
    EXPECT_GE(w, prev);
    EXPECT_LT(w - prev, 0.02);
    prev = w;
  }
  EXPECT_TRUE(finite3(night::night_vision_rgb(glm::dvec3(0.0), 1e-4, on)));
  EXPECT_TRUE(finite3(night::night_vision_rgb(glm::dvec3(-1.0, 0.0, 0.0), 1e-4, on)));
  EXPECT_TRUE(finite3(night::night_vision_rgb(glm::dvec3(1.0), std::nan(""), on)));
}
