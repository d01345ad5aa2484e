// The host's lights as points (ATMO_PASS_LIGHT_POINTS): one vertex per light
// that shows (core/lights/light_points.h chose them and computed the
// illuminance E each brings to the eye, after the air and the fog), drawn as
// a GL_POINTS square around its exact sub-pixel position. Here, once per
// light: the projection; whether the host's geometry hides it (the host's
// depth at the light's pixel and its 8 neighbours all nearer than the light,
// so a light standing on the ground, whose lower neighbours show nearer
// ground, stays visible); the pixel's solid angle; and the footprint's width,
// which grows with the light's brightness against the view's white (a
// display cannot show more than white, so a brighter light spreads its E
// over more pixels, up to 3x: IG light points' intensity-driven size).
// plugin/gl/light_point_renderer.h, docs/FOG.md "Light points".
#define ATMO_FN
#define IN(T) in T
#define OUT(T) out T
#define LUT2D sampler2D
vec3 sample_lut(sampler2D lut, vec2 uv) { return textureLod(lut, uv, 0.0f).rgb; }

#include "atmosphere/functions.glsl"
#include "night_sky/pixel_solid_angle.glsl"

layout(location = 0) in vec3 a_position_enu;     // relative to the eye, m
layout(location = 1) in vec3 a_illuminance_lux;  // at the eye, linear Rec.709

uniform mat3 u_view_from_enu;
uniform mat4 u_clip_from_view;      // the host's projection
uniform mat4 u_view_from_clip;      // its inverse
uniform int u_depth_convention;
uniform float u_log_far_m;
uniform float u_log_coefficient;
uniform sampler2D u_depth;
uniform int u_has_depth;
uniform ivec2 u_depth_origin;       // the window pixel of the depth texture's texel (0, 0)
uniform vec4 u_viewport;            // the host's viewport: x, y, width, height (pixels)
uniform vec4 u_draw_viewport;       // the viewport this pass draws with: u_viewport grown by a margin
uniform float u_exposure;           // output units per cd/m^2: 1 is the view's white
uniform float u_sigma_px;           // the footprint's width for a light at or below white
uniform float u_sigma_max_px;       // ... and at most

flat out vec2 v_center_px;          // the light's centre, window coordinates (as gl_FragCoord)
flat out vec3 v_radiance;           // E / Omega_pixel, cd/m^2 (the whole light in one pixel)
flat out float v_sigma_px;

void cull() {
  gl_Position = vec4(4.0f, 4.0f, 0.5f, 1.0f);  // outside the x and y clip planes: discarded
  gl_PointSize = 1.0f;
  v_center_px = vec2(0.0f);
  v_radiance = vec3(0.0f);
  v_sigma_px = 1.0f;
}

// The host's view distance at window pixel `px` (1e30 where it drew nothing).
float host_distance(ivec2 px) {
  ivec2 texel = clamp(px, ivec2(u_viewport.xy), ivec2(u_viewport.xy + u_viewport.zw) - 1) - u_depth_origin;
  float depth = texelFetch(u_depth, texel, 0).r;
  vec2 ndc = (vec2(px) + 0.5f - u_viewport.xy) / u_viewport.zw * 2.0f - 1.0f;
  vec4 p = view_point_from_depth(u_view_from_clip, ndc, depth, u_depth_convention, u_log_far_m, u_log_coefficient);
  return p.w < 0.0f ? 1.0e30f : length(p.xyz);
}

void main() {
  vec3 v = u_view_from_enu * a_position_enu;
  vec4 clip = u_clip_from_view * vec4(v, 1.0f);
  if (!(clip.w > 0.0f)) { cull(); return; }
  vec2 ndc = clip.xy / clip.w;
  vec2 center = u_viewport.xy + (ndc * 0.5f + 0.5f) * u_viewport.zw;
  if (u_has_depth != 0) {
    // Hidden when the farthest host surface around the light's pixel is nearer than the light (less a
    // tolerance for a light mounted on a surface: 0.2 % of the distance and half a metre).
    float d = length(v);
    float farthest = 0.0f;
    ivec2 c = ivec2(floor(center));
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) farthest = max(farthest, host_distance(c + ivec2(dx, dy)));
    if (farthest < d * 0.998f - 0.5f) { cull(); return; }
  }
  float omega = pixel_solid_angle(u_view_from_clip, u_depth_convention, u_viewport.zw, ndc);
  if (!(omega > 0.0f)) { cull(); return; }
  v_center_px = center;
  v_radiance = a_illuminance_lux / omega;
  // The footprint's peak (0.318 of the light in its centre pixel at sigma 0.7 px, as 1/(2 pi sigma^2) roughly)
  // against white: past white the footprint widens as the square root, keeping E.
  float peak = max(v_radiance.r, max(v_radiance.g, v_radiance.b)) * u_exposure / (6.2832f * u_sigma_px * u_sigma_px);
  v_sigma_px = clamp(u_sigma_px * sqrt(max(peak, 1.0f)), u_sigma_px, u_sigma_max_px);
  vec2 draw_ndc = (center - u_draw_viewport.xy) / u_draw_viewport.zw * 2.0f - 1.0f;
  gl_Position = vec4(draw_ndc, 0.5f, 1.0f);
  gl_PointSize = 2.0f * ceil(3.0f * v_sigma_px) + 1.0f;
}
