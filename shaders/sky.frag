// Sky pass: the sky, the sun's disc and, from altitude, the Earth below —
// only where the host drew nothing (its depth is at the far plane).
#include "atmosphere/pass_common.glsl"

out vec4 out_color;

void main() {
  if (u_has_depth != 0) {
    vec4 p = view_point_from_depth(u_view_from_clip, ndc_xy(), host_depth(), u_depth_convention, u_log_far_m,
                                   u_log_coefficient);
    if (p.w >= 0.0f) discard;  // host geometry is here
  }
  vec3 dir = normalize(u_enu_from_view * view_ray());
  float altitude = max(u_eye_altitude_m, 1.0f);
  ScatteringResult s = integrate_single_scattering(u_atmosphere, u_transmittance, u_transmittance_size, altitude,
                                                   dir, u_sun_direction_enu, 1e12f, u_steps);
  vec3 radiance = s.inscattered;
  vec3 center = vec3(0.0f, 0.0f, -(u_atmosphere.bottom_radius_m + altitude));
  float t_ground = ray_sphere_near(-center, dir, u_atmosphere.bottom_radius_m);
  if (t_ground > 0.0f) {
    radiance += s.transmittance * ground_radiance(u_atmosphere, u_transmittance, u_transmittance_size, altitude,
                                                  dir, u_sun_direction_enu, t_ground);
  } else {
    radiance += s.transmittance * sun_disc_radiance(u_atmosphere, dir, u_sun_direction_enu);
  }
  out_color = vec4(encode_output(radiance), 1.0f);
}
