// Sky pass: the sky, the sun's disc and, from altitude, the Earth below —
// only where the host drew nothing (its depth is at the far plane).
#include "atmosphere/pass_common.glsl"
#include "atmosphere/sky_pixel.glsl"

out vec4 out_color;

void main() {
  if (u_has_depth != 0) {
    vec4 p = view_point_from_depth(u_view_from_clip, ndc_xy(), host_depth(), u_depth_convention, u_log_far_m,
                                   u_log_coefficient);
    if (p.w >= 0.0f) discard;  // host geometry is here
  }
  vec3 dir = normalize(u_enu_from_view * view_ray_from_ndc(u_view_from_clip, ndc_xy(), u_depth_convention));
  out_color = vec4(encode_output(sky_pixel_radiance(dir)), 1.0f);
}
