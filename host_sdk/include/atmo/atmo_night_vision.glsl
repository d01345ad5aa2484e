// atmo_night_vision.glsl — optional night tone mapping for the host's own
// post-process (off unless the host calls it): the loss of colour and the
// blue shift of night vision (Jensen et al. 2001 §7; Larson, Rushmeier &
// Piatko 1997; Thompson, Shirley & Ferwerda 2002). The plugin's core has the
// same function in double precision (plugin/core/night_sky/night_vision.h);
// tests/core/night_vision_glsl_test.cpp compiles this file as C++ and checks
// the two agree. docs/NIGHT_SKY.md, "Night vision".
//
// Use, on a LINEAR_HDR target before the host's tone curve:
//   color.rgb = atmo_night_vision(color.rgb / exposure_scale, adaptation_cd_m2) * exposure_scale;
// rgb: linear sRGB (Rec.709 primaries, D65) radiance in cd/m^2; adaptation:
// the eye's adaptation luminance (cd/m^2) for the frame, e.g. the luminance
// the host's exposure maps to mid-grey — one value per frame, not per pixel.
// Photopic (adaptation >= 3 cd/m^2): identity. Scotopic (<= 1e-3 cd/m^2):
// the rods' luminance drawn in one grey-blue (chromaticity x = y = 0.25),
// a D65 white keeping its luminance. Between: a smoothstep in log10.
//
// Needs GLSL 1.30+ (or C++ with GLM when ATMO_NV_FN is defined as `inline`).
#ifndef ATMO_NV_FN
#define ATMO_NV_FN
#endif

// XYZ from linear sRGB (D65), column-major.
const mat3 ATMO_NV_XYZ_FROM_RGB = mat3(0.412390799f, 0.212639006f, 0.019330819f,
                                       0.357584339f, 0.715168679f, 0.119194780f,
                                       0.180480788f, 0.072192315f, 0.950532152f);
// The scotopic grey-blue (x = y = 0.25) in linear sRGB, luminance 1.
const vec3 ATMO_NV_SCOTOPIC_TINT = vec3(0.706365244f, 0.989833980f, 1.965596149f);
// V / Y of the D65 white: the scotopic part is divided by it so a white keeps its luminance.
const float ATMO_NV_D65_SCOTOPIC_RATIO = 2.573277902f;
const float ATMO_NV_SCOTOPIC_LIMIT_CD_M2 = 1e-3f;
const float ATMO_NV_PHOTOPIC_LIMIT_CD_M2 = 3.0f;

// Scotopic luminance from XYZ (Larson et al. 1997): V = Y [1.33 (1 + (Y + Z) / X) - 1.68].
ATMO_NV_FN float atmo_scotopic_luminance(vec3 xyz) {
  if (!(xyz.y > 0.0f)) return 0.0f;
  float x = max(xyz.x, 1e-9f * xyz.y);
  float z = max(xyz.z, 0.0f);
  return max(xyz.y * (1.33f * (1.0f + (xyz.y + z) / x) - 1.68f), 0.0f);
}

// Weight of cone vision at the adaptation luminance: 0 at or below 1e-3 cd/m^2, 1 at or above 3.
ATMO_NV_FN float atmo_photopic_weight(float adaptation_cd_m2) {
  if (!(adaptation_cd_m2 > ATMO_NV_SCOTOPIC_LIMIT_CD_M2)) return 0.0f;
  if (adaptation_cd_m2 >= ATMO_NV_PHOTOPIC_LIMIT_CD_M2) return 1.0f;
  float lo = log2(ATMO_NV_SCOTOPIC_LIMIT_CD_M2), hi = log2(ATMO_NV_PHOTOPIC_LIMIT_CD_M2);
  float s = clamp((log2(adaptation_cd_m2) - lo) / (hi - lo), 0.0f, 1.0f);
  return s * s * (3.0f - 2.0f * s);
}

ATMO_NV_FN vec3 atmo_night_vision(vec3 rgb_cd_m2, float adaptation_cd_m2) {
  float w = atmo_photopic_weight(adaptation_cd_m2);
  if (w >= 1.0f) return rgb_cd_m2;
  // Negative and NaN components count as 0 (written so, not with max: max with NaN is undefined in GLSL).
  vec3 rgb = vec3(rgb_cd_m2.x > 0.0f ? rgb_cd_m2.x : 0.0f, rgb_cd_m2.y > 0.0f ? rgb_cd_m2.y : 0.0f,
                  rgb_cd_m2.z > 0.0f ? rgb_cd_m2.z : 0.0f);
  float v = atmo_scotopic_luminance(ATMO_NV_XYZ_FROM_RGB * rgb) / ATMO_NV_D65_SCOTOPIC_RATIO;
  return w * rgb + (1.0f - w) * v * ATMO_NV_SCOTOPIC_TINT;
}
