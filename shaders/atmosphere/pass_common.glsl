// Uniforms and helpers shared by the sky and aerial-perspective passes.
// Prelude for functions.glsl in GLSL: how parameters and textures are spelled.
#define ATMO_FN
#define IN(T) in T
#define OUT(T) out T
#define LUT2D sampler2D
vec3 sample_lut(sampler2D lut, vec2 uv) { return texture(lut, uv).rgb; }

#include "atmosphere/functions.glsl"
#include "atmosphere/preetham.glsl"

// ATMO_METHOD: which tier this program variant draws (plugin/gl/renderer.h
// SkyMethod); the renderer builds one program per method, so no GPU — nor
// llvmpipe, which runs both sides of a branch under a mask — pays for the
// branches of the other tiers.
#define METHOD_LUT 0       // sky-view table + aerial-perspective volume
#define METHOD_ANALYTIC 1  // Preetham sky cross-faded with the LUT tier by u_analytic_weight
#define METHOD_MARCH 2     // per-pixel ray march (reference-grade, slow)
#ifndef ATMO_METHOD
#define ATMO_METHOD METHOD_LUT
#endif

uniform AtmosphereParameters u_atmosphere;
uniform sampler2D u_transmittance;
uniform vec2 u_transmittance_size;
uniform sampler2D u_multiple_scattering;
uniform vec2 u_multiple_scattering_size;
uniform sampler2D u_depth;        // host depth texture (window-space values)
uniform int u_has_depth;
uniform ivec2 u_depth_origin;  // the window pixel of its texel (0, 0): 0, or the viewport's corner (AtmoViewState.depth_origin)
uniform int u_depth_convention;   // AtmoDepthConvention
uniform float u_log_far_m;
uniform float u_log_coefficient;
uniform mat4 u_view_from_clip;    // inverse of the host projection
uniform mat3 u_enu_from_view;     // camera orientation in ENU at the eye
uniform vec4 u_viewport;          // x, y, width, height in pixels
uniform float u_eye_altitude_m;
uniform vec3 u_sun_direction_enu;
uniform float u_exposure;
uniform int u_output_encoding;    // AtmoOutputEncoding
uniform int u_steps;
uniform sampler2D u_sky_view;          // sky-view table, RGBA32F, cd/m^2
uniform vec2 u_sky_view_size;
uniform sampler3D u_aerial_inscatter;  // aerial-perspective volume, cd/m^2
uniform sampler3D u_aerial_transmittance;
uniform float u_aerial_range_m;
uniform int u_aerial_slices;
uniform PreethamCoefficients u_preetham;  // zenith luminance already calibrated to the LUT tier
uniform float u_analytic_weight;          // Preetham's confidence, 0..1
uniform CloudShadowing u_cloud_shadowing;  // the clouds' shadow on the air (aerial volume, march tier)
uniform sampler2D u_cloud_shadow;          // its map (R16F direct transmittance)

vec2 ndc_xy() { return (gl_FragCoord.xy - u_viewport.xy) / u_viewport.zw * 2.0f - 1.0f; }

// The host's depth at this pixel: the texel at the window pixel less the texture's origin (AtmoViewState.depth_origin).
float host_depth() { return texelFetch(u_depth, ivec2(gl_FragCoord.xy) - u_depth_origin, 0).r; }


vec3 encode_output(vec3 radiance_cd_m2) {
  vec3 exposed = radiance_cd_m2 * u_exposure;
  return u_output_encoding == 1 ? encode_display_srgb(exposed) : exposed;
}
