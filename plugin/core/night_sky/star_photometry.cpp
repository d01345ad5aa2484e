#include "core/night_sky/star_photometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/atmosphere/shader_twin.h"
#include "core/spectral/colorimetry.h"
#include "core/spectral/spectral_atmosphere.h"

namespace atmo::core::night {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// Planck's law, spectral radiance up to a constant factor (the colour is normalised).
double planck_shape(double wavelength_nm, double kelvin) {
  constexpr double h = 6.62607015e-34, c = 299792458.0, k = 1.380649e-23;  // SI 2019, exact
  const double l = wavelength_nm * 1e-9;
  const double x = h * c / (l * k * kelvin);
  return 1.0 / (std::pow(wavelength_nm / 500.0, 5.0) * std::expm1(x));
}

const spectral::SpectrumToColor& visible_5nm() {
  static const spectral::SpectrumToColor conv(spectral::wavelength_grid(360.0, 830.0, 5.0));
  return conv;
}

// One channel of a grey output through the project's display encoding (the CPU twin of the shader).
double encode_grey(double exposed) {
  return static_cast<double>(twin::encode_display_srgb(glm::vec3(static_cast<float>(exposed))).x);
}
}  // namespace

double illuminance_from_magnitude(double v) { return kVZeroPointLux * std::pow(10.0, -0.4 * v); }

double magnitude_from_illuminance(double lux) {
  if (!(lux > 0.0)) return kInf;
  return -2.5 * std::log10(lux / kVZeroPointLux);
}

double jensen_irradiance_w_m2(double v, bool extra_atmospheric) {
  return std::pow(10.0, 0.4 * (-v - 19.0 + (extra_atmospheric ? 0.4 : 0.0)));
}

double luminance_from_mag_per_arcsec2(double s) { return illuminance_from_magnitude(s) / kSquareArcsecondSr; }

double mag_per_arcsec2_from_luminance(double cd_m2) { return magnitude_from_illuminance(cd_m2 * kSquareArcsecondSr); }

double luminance_from_s10(double s10) { return s10 * illuminance_from_magnitude(10.0) / kSquareDegreeSr; }

double s10_from_luminance(double cd_m2) { return cd_m2 * kSquareDegreeSr / illuminance_from_magnitude(10.0); }

double rgb_luminance(const glm::dvec3& rgb) {
  static const glm::dvec3 weights = [] {
    const glm::dmat3 xyz_from_rgb = glm::inverse(spectral::linear_srgb_from_xyz());
    return glm::dvec3(xyz_from_rgb[0][1], xyz_from_rgb[1][1], xyz_from_rgb[2][1]);  // the Y row
  }();
  return glm::dot(weights, rgb);
}

double temperature_from_bv_ballesteros(double b_minus_v) {
  const double bv = std::clamp(b_minus_v, kMinBV, kMaxBV);
  return 4600.0 * (1.0 / (0.92 * bv + 1.7) + 1.0 / (0.92 * bv + 0.62));
}

double temperature_from_bv_jensen(double b_minus_v) {
  const double bv = std::clamp(b_minus_v, kMinBV, kMaxBV);
  return 7000.0 / (bv + 0.56);
}

glm::dvec3 blackbody_rgb(double kelvin) {
  const auto& conv = visible_5nm();
  const double t = std::clamp(kelvin, 1000.0, 1.0e6);
  std::vector<double> values;
  values.reserve(conv.wavelengths_nm().size());
  for (double nm : conv.wavelengths_nm()) values.push_back(planck_shape(nm, t));
  glm::dvec3 rgb = glm::max(conv.linear_srgb(values), glm::dvec3(0.0));
  const double y = rgb_luminance(rgb);
  return y > 0.0 ? rgb / y : glm::dvec3(1.0);
}

glm::dvec3 star_rgb_from_bv(double b_minus_v) { return blackbody_rgb(temperature_from_bv_ballesteros(b_minus_v)); }

double star_max_channel_factor() {
  static const double factor = [] {
    double m = 0.0;
    const int n = 96;
    for (int i = 0; i <= n; ++i) {
      const glm::dvec3 c = star_rgb_from_bv(kMinBV + (kMaxBV - kMinBV) * i / n);
      m = std::max({m, c.r, c.g, c.b});
    }
    return m;
  }();
  return factor;
}

double erf_approx(double x) {
  // Abramowitz & Stegun 7.1.26.
  const double sign = x < 0.0 ? -1.0 : 1.0;
  const double ax = std::abs(x);
  const double t = 1.0 / (1.0 + 0.3275911 * ax);
  const double poly = t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429))));
  return sign * (1.0 - poly * std::exp(-ax * ax));
}

double star_footprint_weight(double dx, double dy, double sigma_px) {
  const double k = 1.0 / (std::sqrt(2.0) * std::max(sigma_px, 1e-6));
  const double wx = 0.5 * (erf_approx((dx + 0.5) * k) - erf_approx((dx - 0.5) * k));
  const double wy = 0.5 * (erf_approx((dy + 0.5) * k) - erf_approx((dy - 0.5) * k));
  return std::max(wx, 0.0) * std::max(wy, 0.0);
}

double star_footprint_peak(double sigma_px) { return star_footprint_weight(0.0, 0.0, sigma_px); }

double pixel_solid_angle_sr(double tan_half_fov_y, double viewport_height_px, double cos_off_axis) {
  const double pitch = 2.0 * tan_half_fov_y / viewport_height_px;
  const double c = std::clamp(cos_off_axis, 0.0, 1.0);
  return pitch * pitch * c * c * c;
}

double star_pixel_luminance(double illuminance_lux, double omega) {
  return omega > 0.0 ? illuminance_lux / omega : 0.0;
}

double display_limiting_magnitude(double background_cd_m2, double exposure, double omega,
                                  const DisplayThreshold& threshold, double transmittance, double max_channel,
                                  double sigma_px) {
  if (!(exposure > 0.0) || !(omega > 0.0) || !(transmittance > 0.0) || !(threshold.step > 0.0)) return -kInf;
  const double channel = max_channel > 0.0 ? max_channel : star_max_channel_factor();
  const double y0 = exposure * std::max(background_cd_m2, 0.0);

  // Smallest increase of the exposed (linear) output that moves the display by `step`.
  double dy = 0.0;
  if (threshold.kind == DisplayThreshold::Kind::kLinear) {
    dy = threshold.step;
  } else {
    const double e0 = encode_grey(y0);
    auto moves = [&](double d) { return encode_grey(y0 + d) - e0 >= threshold.step; };
    double hi = 1.0e6 + 2.0 * y0;
    if (!moves(hi)) return -kInf;  // saturated: nothing can change this pixel
    double lo = 1e-12;
    if (moves(lo)) {
      dy = lo;
    } else {
      for (int i = 0; i < 200 && hi / lo > 1.0 + 1e-9; ++i) {
        const double mid = std::sqrt(lo * hi);
        (moves(mid) ? hi : lo) = mid;
      }
      dy = hi;
    }
  }
  const double d_luminance = dy / exposure;  // cd/m^2 added to the brightest channel
  const double lux = d_luminance * omega / (transmittance * channel * star_footprint_peak(sigma_px));
  return magnitude_from_illuminance(lux);
}

double naked_eye_limiting_magnitude(double background_cd_m2, double observer_factor) {
  constexpr double kCdM2PerNanolambert = 1e-9 * 1e4 / 3.14159265358979323846;  // 1 L = (1/pi) cd/cm^2
  const double b = std::max(background_cd_m2, 0.0) / kCdM2PerNanolambert;
  auto threshold = [b](double c1, double c2) {
    const double s = 1.0 + std::sqrt(c2 * b);
    return c1 * s * s;
  };
  const double night = threshold(std::pow(10.0, -9.8), std::pow(10.0, -1.9));
  const double day = threshold(std::pow(10.0, -8.35), std::pow(10.0, -5.9));
  const double foot_candles = std::min(night, day) * std::max(observer_factor, 1e-6);
  return -16.57 - 2.5 * std::log10(foot_candles);
}

}  // namespace atmo::core::night
