#include "core/sky/analytic_tier.h"

#include <algorithm>
#include <cmath>

namespace atmo::core {

AnalyticTier analytic_tier(const AtmosphereSettings& air, const twin::AtmosphereParameters& atm,
                           const twin::Lut2D& transmittance, const twin::Lut2D& multiple_scattering,
                           const glm::vec3& sun_direction_enu, float eye_altitude_m) {
  AnalyticTier tier;
  const double turbidity = preetham_turbidity_from_visibility(air.visibility_m, air.aerosol_scale_height_m);
  const double sun_elevation = std::asin(std::clamp(static_cast<double>(sun_direction_enu.z), -1.0, 1.0));
  const PreethamValidity validity = preetham_validity(turbidity, sun_elevation, eye_altitude_m);
  if (!validity.valid || validity.confidence <= 0.0) return tier;
  tier.coefficients = preetham_coefficients(turbidity, M_PI / 2.0 - sun_elevation);
  const glm::vec2 t_size(transmittance.width, transmittance.height);
  const glm::vec2 ms_size(multiple_scattering.width, multiple_scattering.height);
  const glm::vec3 zenith = twin::sky_radiance_parts(atm, transmittance, t_size, multiple_scattering, ms_size,
                                                    eye_altitude_m, glm::vec3(0.0f, 0.0f, 1.0f), sun_direction_enu,
                                                    64)
                               .diffuse;
  const float model_luminance = 0.2126f * zenith.x + 0.7152f * zenith.y + 0.0722f * zenith.z;
  if (!(tier.coefficients.zenith_Yxy.x > 0.0f) || !(model_luminance > 0.0f)) return tier;
  tier.coefficients.zenith_Yxy.x = model_luminance;
  tier.weight = static_cast<float>(validity.confidence);
  return tier;
}

}  // namespace atmo::core
