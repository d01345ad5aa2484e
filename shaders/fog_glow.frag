// The glow of one light in the fog: single scattering along the view ray up
// to the host's geometry (atmo_fog_airlight, the stable form), added.
#include "atmosphere/pass_common.glsl"
#define ATMO_FOG_NO_UNIFORMS
#include "../host_sdk/include/atmo/atmo_fog_lights.glsl"

uniform sampler2D u_fog_airlight;   // the airlight table (R32F)
uniform float u_fog_airlight_size;
uniform float u_fog_top;            // fog top above the eye, m (ATMO_FOG_FAR: none)
uniform float u_min_sin;            // half a pixel's angle: the 1/gamma core averaged over a pixel

flat in vec4 v_light;
flat in vec4 v_intensity;
flat in vec4 v_axis;
out vec4 out_color;

void main() {
  vec2 ndc = ndc_xy();
  vec4 p = view_point_from_depth(u_view_from_clip, ndc, host_depth(), u_depth_convention, u_log_far_m,
                                 u_log_coefficient);
  vec3 ray = p.w < 0.0 ? view_ray_from_ndc(u_view_from_clip, ndc, u_depth_convention) : p.xyz;
  vec3 dir = normalize(u_enu_from_view * ray);
  float d_vp = p.w < 0.0 ? ATMO_FOG_FAR : length(p.xyz);
  // In-scattering stops where the ray leaves the fog (eye inside it).
  if (u_fog_top < ATMO_FOG_FAR && u_fog_top > 0.0 && dir.z > 0.0) d_vp = min(d_vp, u_fog_top / dir.z);
  vec3 to_light = v_light.xyz;
  float distance = length(to_light);
  float cos_gamma = dot(dir, to_light) / max(distance, 1.0e-3);
  // A cone light: its intensity towards the ray's closest approach, where most of the glow comes from.
  float closest = clamp(distance * cos_gamma, 0.0, min(d_vp, 1.0e7));
  float cone = atmo_fog_cone(v_axis.xyz, v_intensity.w, v_axis.w, normalize(dir * closest - to_light + vec3(0.0, 0.0, 1.0e-6)));
  float la = atmo_fog_airlight(u_fog_airlight, u_fog_airlight_size, v_light.w, distance, cos_gamma, d_vp, u_min_sin);
  out_color = vec4(encode_output(v_intensity.rgb * (cone * la)), 0.0);
}
