// Sky pass: the sky, the sun's disc and, from altitude, the Earth below —
// only where the host drew nothing (its depth is at the far plane).
#include "atmosphere/pass_common.glsl"

out vec4 out_color;

vec3 lut_sky(vec3 dir) {
  vec3 diffuse = texture(u_sky_view, sky_view_uv(u_atmosphere, u_eye_altitude_m, dir, u_sun_direction_enu,
                                                 u_sky_view_size)).rgb;
  return sky_radiance_with_sun(u_atmosphere, u_transmittance, u_transmittance_size, diffuse, u_eye_altitude_m, dir,
                               u_sun_direction_enu);
}

vec3 analytic_sky(vec3 dir) {
  return sky_radiance_with_sun(u_atmosphere, u_transmittance, u_transmittance_size,
                               preetham_sky_rgb(u_preetham, dir, u_sun_direction_enu), u_eye_altitude_m, dir,
                               u_sun_direction_enu);
}

void main() {
  if (u_has_depth != 0) {
    vec4 p = view_point_from_depth(u_view_from_clip, ndc_xy(), host_depth(), u_depth_convention, u_log_far_m,
                                   u_log_coefficient);
    if (p.w >= 0.0f) discard;  // host geometry is here
  }
  vec3 dir = normalize(u_enu_from_view * view_ray_from_ndc(u_view_from_clip, ndc_xy(), u_depth_convention));
#if ATMO_METHOD == METHOD_MARCH
  vec3 radiance = sky_radiance(u_atmosphere, u_transmittance, u_transmittance_size, u_multiple_scattering,
                               u_multiple_scattering_size, u_eye_altitude_m, dir, u_sun_direction_enu, u_steps);
#elif ATMO_METHOD == METHOD_ANALYTIC
  // u_analytic_weight is uniform: the renderer only builds the sky-view table when it is below 1.
  vec3 radiance = u_analytic_weight >= 1.0f ? analytic_sky(dir)
                                            : mix(lut_sky(dir), analytic_sky(dir), u_analytic_weight);
#else
  vec3 radiance = lut_sky(dir);
#endif
  out_color = vec4(encode_output(radiance), 1.0f);
}
