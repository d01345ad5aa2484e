// The core of one light's glow in the fog (core/lights/glow_tiles.h): its
// single scattering along the view ray up to the host's geometry
// (atmo_fog_glow, the stable form) less the same with sin gamma floored at
// the core angle's (the smooth part, which fog_glow_smooth.frag draws for
// all lights at once), added. 0 beyond the core angle: the rectangle stops there.
#include "atmosphere/pass_common.glsl"
#define ATMO_FOG_NO_UNIFORMS
#include "../host_sdk/include/atmo/atmo_fog_lights.glsl"

uniform sampler2D u_fog_airlight;   // the airlight table (R32F)
uniform float u_fog_airlight_size;
uniform float u_fog_top;            // fog top above the eye, m (ATMO_FOG_FAR: none)
uniform float u_min_sin;            // 0.2836 of a pixel's angle: the 1/gamma core averaged over a pixel
uniform float u_core_sin;           // sin of the core angle

flat in vec4 v_light;
flat in vec4 v_intensity;
flat in vec4 v_axis;
flat in float v_lobes;
out vec4 out_color;

void main() {
  vec2 ndc = ndc_xy();
  // Past the core angle both terms below are the same glow: nothing to add (the rectangle's corners).
  vec3 towards = normalize(v_light.xyz);
  vec3 dir0 = normalize(u_enu_from_view * view_ray_from_ndc(u_view_from_clip, ndc, u_depth_convention));
  float cos_gamma = dot(dir0, towards);
  if (cos_gamma > 0.0 && 1.0 - cos_gamma * cos_gamma >= u_core_sin * u_core_sin) discard;
  // Without a host depth texture every pixel is open sky (w < 0).
  vec4 p = u_has_depth != 0 ? view_point_from_depth(u_view_from_clip, ndc, host_depth(), u_depth_convention,
                                                     u_log_far_m, u_log_coefficient)
                            : vec4(0.0, 0.0, 0.0, -1.0);
  vec3 ray = p.w < 0.0 ? view_ray_from_ndc(u_view_from_clip, ndc, u_depth_convention) : p.xyz;
  vec3 dir = normalize(u_enu_from_view * ray);
  float d_vp = p.w < 0.0 ? ATMO_FOG_FAR : length(p.xyz);
  // In-scattering stops where the ray leaves the fog (eye inside it).
  if (u_fog_top < ATMO_FOG_FAR && u_fog_top > 0.0 && dir.z > 0.0) d_vp = min(d_vp, u_fog_top / dir.z);
  float la = atmo_fog_glow(u_fog_airlight, u_fog_airlight_size, v_light.w, v_light.xyz, dir, v_axis.xyz,
                           v_intensity.w, v_axis.w, v_lobes, d_vp, u_min_sin) -
             atmo_fog_glow(u_fog_airlight, u_fog_airlight_size, v_light.w, v_light.xyz, dir, v_axis.xyz,
                           v_intensity.w, v_axis.w, v_lobes, d_vp, u_core_sin);
  la = max(la, 0.0);
  out_color = vec4(encode_output(v_intensity.rgb * la), 0.0);
}
