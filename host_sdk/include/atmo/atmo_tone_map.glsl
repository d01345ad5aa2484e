// atmo_tone_map.glsl — the display encoding of Atmo's previews, ONE source:
// the plugin's ATMO_OUTPUT_DISPLAY_SRGB output (shaders/atmosphere/
// functions.glsl, encode_display_srgb), the tools' PNG previews
// (tools/support: tone_map_to_display, compiled as C++ over GLM) and the
// sample host's tone-map pass include it. A host may include it too.
//
// exposed: linear Rec.709 radiance times the exposure (cd/m^2 x exposure
// scale). The curve is K. Narkowicz's 2015 fit of the ACES filmic tone curve,
// then the sRGB transfer function (IEC 61966-2-1). Written in the subset the
// C++ twins compile (float literals with f, no swizzles); functions start with
// ATMO_TONE_FN (`inline` in C++, nothing in GLSL).
#ifndef ATMO_TONE_MAP_GLSL
#define ATMO_TONE_MAP_GLSL

#ifndef ATMO_TONE_FN
#define ATMO_TONE_FN
#endif

// The filmic curve per channel, in [0, 1]: 0 at and below 0; inputs beyond
// 1e4 (+inf too) count as 1e4, where the curve is already clamped to 1 (it
// tends to 2.51 / 2.43).
ATMO_TONE_FN vec3 atmo_aces_filmic(vec3 exposed) {
  vec3 x = clamp(exposed, vec3(0.0f), vec3(1.0e4f));
  return clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), vec3(0.0f), vec3(1.0f));
}

// The sRGB transfer function of linear values in [0, 1] (1 encodes to exactly 1).
ATMO_TONE_FN vec3 atmo_srgb_encode(vec3 linear) {
  vec3 c = max(linear, vec3(0.0f));
  vec3 p = pow(c, vec3(1.0f / 2.4f));
  return mix(c * 12.92f, p + 0.055f * (p - 1.0f), step(vec3(0.0031308f), c));  // 1.055 p - 0.055
}

ATMO_TONE_FN vec3 atmo_display_srgb(vec3 exposed) { return atmo_srgb_encode(atmo_aces_filmic(exposed)); }

#endif  // ATMO_TONE_MAP_GLSL
