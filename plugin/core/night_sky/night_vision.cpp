#include "core/night_sky/night_vision.h"

#include <algorithm>
#include <cmath>

#include "core/night_sky/star_photometry.h"
#include "core/spectral/colorimetry.h"

namespace atmo::core::night {

namespace {
const glm::dmat3& xyz_from_rgb() {
  static const glm::dmat3 m = glm::inverse(spectral::linear_srgb_from_xyz());
  return m;
}

// V / Y of the D65 white (the white of linear sRGB: RGB = 1).
double d65_scotopic_ratio() {
  static const double r = [] {
    const glm::dvec3 xyz = xyz_from_rgb() * glm::dvec3(1.0);
    return scotopic_luminance(xyz) / xyz.y;
  }();
  return r;
}
}  // namespace

double scotopic_luminance(const glm::dvec3& xyz) {
  if (!(xyz.y > 0.0)) return 0.0;
  const double x = std::max(xyz.x, 1e-9 * xyz.y);
  const double z = std::max(xyz.z, 0.0);
  return std::max(xyz.y * (1.33 * (1.0 + (xyz.y + z) / x) - 1.68), 0.0);
}

double photopic_weight(double adaptation_cd_m2) {
  if (!(adaptation_cd_m2 > kScotopicLimitCdM2)) return 0.0;  // also NaN
  if (adaptation_cd_m2 >= kPhotopicLimitCdM2) return 1.0;
  const double lo = std::log10(kScotopicLimitCdM2), hi = std::log10(kPhotopicLimitCdM2);
  const double s = std::clamp((std::log10(adaptation_cd_m2) - lo) / (hi - lo), 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}

glm::dvec3 scotopic_tint_rgb() {
  static const glm::dvec3 rgb = [] {
    const glm::dvec3 xyz(kBlueShiftX / kBlueShiftY, 1.0, (1.0 - kBlueShiftX - kBlueShiftY) / kBlueShiftY);
    const glm::dvec3 c = glm::max(spectral::linear_srgb_from_xyz() * xyz, glm::dvec3(0.0));
    return c / rgb_luminance(c);
  }();
  return rgb;
}

glm::dvec3 night_vision_rgb(const glm::dvec3& rgb, double adaptation_cd_m2, const NightVisionSettings& settings) {
  if (!settings.enabled) return rgb;
  const double w = photopic_weight(adaptation_cd_m2);
  if (w >= 1.0) return rgb;
  const double v = scotopic_luminance(xyz_from_rgb() * glm::max(rgb, glm::dvec3(0.0))) / d65_scotopic_ratio();
  return w * rgb + (1.0 - w) * v * scotopic_tint_rgb();
}

}  // namespace atmo::core::night
