// The sky's radiance (cd/m^2) in a pixel's direction, as the program's
// ATMO_METHOD draws it: sky.frag writes it, the night pass's point sources
// add to it (night_points.frag). Needs pass_common.glsl's uniforms.

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

vec3 sky_pixel_radiance(vec3 dir) {
#if ATMO_METHOD == METHOD_MARCH
  return sky_radiance(u_atmosphere, u_transmittance, u_transmittance_size, u_multiple_scattering,
                      u_multiple_scattering_size, u_eye_altitude_m, dir, u_sun_direction_enu, u_steps);
#elif ATMO_METHOD == METHOD_ANALYTIC
  // u_analytic_weight is uniform: the renderer only builds the sky-view table when it is below 1.
  return u_analytic_weight >= 1.0f ? analytic_sky(dir) : mix(lut_sky(dir), analytic_sky(dir), u_analytic_weight);
#else
  return lut_sky(dir);
#endif
}
