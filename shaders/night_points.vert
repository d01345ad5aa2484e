// Night-sky pass, point sources (stars and planets): one vertex per source,
// drawn as a GL_POINTS square of (2 R + 1) pixels around the source's exact
// sub-pixel position (R = kStarFootprintRadiusPx), so every pixel whose
// centre is within R pixels of it gets a fragment. Here, once per source: the
// projection, the atmosphere's transmittance along the line of sight (the
// source is culled when the Earth hides it) and the solid angle of a pixel at
// the source. plugin/gl/night_renderer.h, docs/NIGHT_SKY.md.
//
// No pass_common.glsl here (it reads gl_FragCoord): the same prelude for
// functions.glsl, with the textures sampled at level 0.
#define ATMO_FN
#define IN(T) in T
#define OUT(T) out T
#define LUT2D sampler2D
vec3 sample_lut(sampler2D lut, vec2 uv) { return textureLod(lut, uv, 0.0f).rgb; }

#include "atmosphere/functions.glsl"
#include "night_sky/pixel_solid_angle.glsl"

layout(location = 0) in vec3 a_direction_enu;     // unit, ENU at the eye
layout(location = 1) in vec3 a_illuminance_lux;   // outside the atmosphere, linear sRGB

uniform AtmosphereParameters u_atmosphere;
uniform sampler2D u_transmittance;
uniform vec2 u_transmittance_size;
uniform float u_eye_altitude_m;
uniform mat3 u_view_from_enu;       // transpose of u_enu_from_view
uniform mat4 u_clip_from_view;      // the host's projection
uniform mat4 u_view_from_clip;      // its inverse
uniform int u_depth_convention;
uniform vec4 u_viewport;            // the host's viewport: x, y, width, height (pixels)
uniform vec4 u_draw_viewport;       // the viewport this pass draws with: u_viewport grown by a margin
uniform float u_point_size;         // 2 R + 1

flat out vec2 v_center_px;          // the source's centre, window coordinates (as gl_FragCoord)
flat out vec3 v_radiance;           // E T / Omega_pixel, cd/m^2 (the whole source in one pixel)

// Transmittance from the eye to space along dir: the transmittance table at
// the eye (transmittance_to_sun: 0 behind the Earth, faded over the sun's
// angular radius at the horizon, as the sun's light is). From above the top
// of the atmosphere, a ray that crosses it is looked up from the point where
// it enters.
vec3 point_transmittance(vec3 dir) {
  float r = u_atmosphere.bottom_radius_m + max(u_eye_altitude_m, 0.0f);
  float mu = clamp(dir.z, -1.0f, 1.0f);
  if (r > u_atmosphere.top_radius_m) {
    float impact = r * sqrt(max(1.0f - mu * mu, 0.0f));
    if (mu >= 0.0f || impact >= u_atmosphere.top_radius_m) return vec3(1.0f);
    r = u_atmosphere.top_radius_m;
    mu = -sqrt(max(1.0f - (impact / r) * (impact / r), 0.0f));
  }
  return transmittance_to_sun(u_atmosphere, u_transmittance, u_transmittance_size, r, mu);
}

void cull() {
  gl_Position = vec4(4.0f, 4.0f, 0.5f, 1.0f);  // outside the x and y clip planes: discarded
  gl_PointSize = 1.0f;
  v_center_px = vec2(0.0f);
  v_radiance = vec3(0.0f);
}

void main() {
  vec3 dir = normalize(a_direction_enu);
  vec3 transmittance = point_transmittance(dir);
  if (max(transmittance.r, max(transmittance.g, transmittance.b)) <= 0.0f) { cull(); return; }
  // A source at infinity: the projection of the direction (w = 0), so the
  // projection's translation (and a finite far plane) does not apply.
  vec4 clip = u_clip_from_view * vec4(u_view_from_enu * dir, 0.0f);
  if (!(clip.w > 0.0f)) { cull(); return; }  // behind the camera
  vec2 ndc = clip.xy / clip.w;
  vec2 center = u_viewport.xy + (ndc * 0.5f + 0.5f) * u_viewport.zw;
  float omega = pixel_solid_angle(u_view_from_clip, u_depth_convention, u_viewport.zw, ndc);
  if (!(omega > 0.0f)) { cull(); return; }
  v_center_px = center;
  v_radiance = a_illuminance_lux * transmittance / omega;
  // Placed in the grown viewport so that its window position is `center`
  // exactly; z = 0.5 lies inside the clip volume for both depth conventions.
  vec2 draw_ndc = (center - u_draw_viewport.xy) / u_draw_viewport.zw * 2.0f - 1.0f;
  gl_Position = vec4(draw_ndc, 0.5f, 1.0f);
  gl_PointSize = u_point_size;
}
