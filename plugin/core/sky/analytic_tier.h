// analytic_tier.h — the ANALYTIC sky tier's inputs: Preetham's coefficients
// for the air and the sun, its zenith luminance calibrated to the LUT model,
// and the weight with which it replaces the LUT tier (its validity confidence:
// 1 well inside the fit's region, falling smoothly to 0 where it fails, so the
// hand-over is a cross-fade). Shared by the plugin and the accuracy tool.
#pragma once

#include "core/atmosphere/atmosphere_model.h"
#include "core/sky/preetham.h"

namespace atmo::core {

struct AnalyticTier {
  twin::PreethamCoefficients coefficients{};
  float weight = 0.0f;  // 0: the LUT tier draws alone
};

// Absolute calibration: Preetham's zenith luminance fit is off by a factor of
// ~2 against the physical model (docs/PREETHAM.md); its angular distribution
// and chromaticity are kept and its zenith luminance is taken from the model
// (one CPU march of 64 steps through the shared functions, microseconds).
AnalyticTier analytic_tier(const AtmosphereSettings& air, const twin::AtmosphereParameters& atm,
                           const twin::Lut2D& transmittance, const twin::Lut2D& multiple_scattering,
                           const glm::vec3& sun_direction_enu, float eye_altitude_m);

}  // namespace atmo::core
