// night_vision.h — an optional scotopic tone-mapping helper (off by default):
// the loss of colour and the blue shift of night vision (Jensen et al. 2001
// §7 uses the XYZV method of Jensen et al. 2000; the same ideas as Larson,
// Rushmeier & Piatko 1997 and Thompson, Shirley & Ferwerda 2002).
//
// Input and output: linear sRGB (D65) radiance in cd/m^2, before exposure.
// The blend depends on the eye's ADAPTATION luminance (the scene's, chosen
// by the caller's exposure logic), not on each pixel: one weight per frame.
//   photopic (adaptation >= kPhotopicLimitCdM2): identity;
//   scotopic (adaptation <= kScotopicLimitCdM2): the rods' luminance V drawn
//     in a single grey-blue, the chromaticity kBlueShiftXy;
//   between: a smoothstep in log10 luminance mixes the two.
// Formulas and sources: docs/NIGHT_SKY.md.
#pragma once

#include <glm/glm.hpp>

namespace atmo::core::night {

// The mesopic range: CIE 191:2010 puts it at ~0.005–5 cd/m^2; these are the
// limits the project uses (the 1e-3 and 3 cd/m^2).
constexpr double kScotopicLimitCdM2 = 1e-3;
constexpr double kPhotopicLimitCdM2 = 3.0;
// Blue-shift chromaticity (CIE 1931 x, y), Thompson et al. 2002.
constexpr double kBlueShiftX = 0.25;
constexpr double kBlueShiftY = 0.25;

struct NightVisionSettings {
  bool enabled = false;  // off by default: night_vision_rgb is then the identity
};

// Scotopic luminance from CIE XYZ (Larson et al. 1997): V = Y [1.33 (1 + (Y + Z) / X) - 1.68],
// in scotopic units; 0 for non-positive Y. D65 white gives V = 2.57 Y (its S/P ratio).
double scotopic_luminance(const glm::dvec3& xyz);
// Weight of photopic (cone) vision at an adaptation luminance: 0 at or below
// kScotopicLimitCdM2, 1 at or above kPhotopicLimitCdM2, smoothstep in log10 between.
double photopic_weight(double adaptation_cd_m2);
// The grey-blue of scotopic vision, linear sRGB, luminance 1.
glm::dvec3 scotopic_tint_rgb();
// w · rgb + (1 - w) · (V / V_D65-per-Y) · tint, with w = photopic_weight(adaptation):
// the scotopic part is scaled so a D65 white keeps its luminance.
glm::dvec3 night_vision_rgb(const glm::dvec3& linear_srgb, double adaptation_cd_m2,
                            const NightVisionSettings& settings);

}  // namespace atmo::core::night
