// The sky's radiance (cd/m^2) in a pixel's direction, as the program's
// ATMO_METHOD draws it, with the night sky's diffuse terms: sky.frag writes
// it, the night pass's point sources add to it (night_points.frag). Needs
// pass_common.glsl's uniforms.
// ATMO_NIGHT_TERMS: which night terms this program variant can draw, the
// bits of u_night_terms (1 the moonlit sky, 2 the Moon's disc, 4 the
// background); default all. The renderer draws each frame with the variant of
// exactly the terms on (gl::Renderer, built on first use): llvmpipe runs the
// code behind a uniform branch even when it is off (the day sky took twice
// as long with the night code in it, docs/PERFORMANCE.md).
#ifndef ATMO_NIGHT_TERMS
#define ATMO_NIGHT_TERMS 7
#endif
#if ATMO_NIGHT_TERMS != 0
// The night terms on this frame (core/night_sky/night_plan.h decides, gl::NightTerms).
uniform int u_night_terms;
uniform float u_pixel_angle_rad;
#if (ATMO_NIGHT_TERMS & 1) != 0
uniform sampler2D u_moon_sky_view;  // the sky-view table with the Moon as the light (u_sky_view_size)
uniform vec3 u_moon_direction_enu;
uniform vec3 u_moon_sky_scale;      // the table's texels to the current Moon's light
#endif
#if (ATMO_NIGHT_TERMS & 2) != 0
#include "night_sky/moon_disc.glsl"
uniform MoonDisc u_moon_disc;
#endif
#if (ATMO_NIGHT_TERMS & 4) != 0
#include "night_sky/background.glsl"
uniform NightBackground u_night_background;
#endif

// The Moon and the faint background seen through the air (0 where the ray
// meets the Earth), and the sky the Moon lights.
vec3 night_sky_radiance(vec3 dir) {
  if (u_night_terms == 0) return vec3(0.0f);
  vec3 radiance = vec3(0.0f);
#if (ATMO_NIGHT_TERMS & 1) != 0
  if ((u_night_terms & 1) != 0) {
    radiance += u_moon_sky_scale *
                texture(u_moon_sky_view, sky_view_uv(u_atmosphere, u_eye_altitude_m, dir, u_moon_direction_enu,
                                                     u_sky_view_size)).rgb;
  }
#endif
#if (ATMO_NIGHT_TERMS & 6) != 0
  if ((u_night_terms & 6) != 0) {
    float r = u_atmosphere.bottom_radius_m + max(u_eye_altitude_m, 0.0f);
    if (!(ray_sphere_near(vec3(0.0f, 0.0f, r), dir, u_atmosphere.bottom_radius_m) > 0.0f)) {
      vec3 outside = vec3(0.0f);
#if (ATMO_NIGHT_TERMS & 2) != 0
      if ((u_night_terms & 2) != 0) outside += moon_disc_radiance(u_moon_disc, dir, u_pixel_angle_rad);
#endif
#if (ATMO_NIGHT_TERMS & 4) != 0
      if ((u_night_terms & 4) != 0) outside += night_background_radiance(u_night_background, dir);
#endif
      radiance += outside * sample_lut(u_transmittance, transmittance_uv_from_r_mu(u_atmosphere, r, dir.z,
                                                                                   u_transmittance_size));
    }
  }
#endif
  return radiance;
}
#else
vec3 night_sky_radiance(vec3 dir) { return vec3(0.0f); }
#endif

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

// ATMO_SKY_CLOUD_SHADOW 1: the clouds' shadow darkens the sunlit air along
// the sky's rays (the renderer builds this variant for frames with a shadow
// map of the Sun and the eye below the clouds' tops; the sky-view table, the
// analytic sky and the march know no clouds).
#ifndef ATMO_SKY_CLOUD_SHADOW
#define ATMO_SKY_CLOUD_SHADOW 0
#endif
#if ATMO_SKY_CLOUD_SHADOW != 0
uniform sampler2D u_sky_cloud_loss;  // sky_cloud_loss_lut.frag's table, cd/m^2
uniform vec2 u_sky_cloud_loss_size;

// The light the clouds' shadow takes from the sky in `dir`.
vec3 sky_cloud_shadow_loss(vec3 dir) {
  return texture(u_sky_cloud_loss, sky_cloud_loss_uv(dir, u_sky_cloud_loss_size)).rgb;
}
#endif

vec3 unshadowed_day_sky_radiance(vec3 dir) {
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

vec3 day_sky_radiance(vec3 dir) {
#if ATMO_SKY_CLOUD_SHADOW != 0
  return max(unshadowed_day_sky_radiance(dir) - sky_cloud_shadow_loss(dir), vec3(0.0f));
#else
  return unshadowed_day_sky_radiance(dir);
#endif
}

vec3 sky_pixel_radiance(vec3 dir) { return day_sky_radiance(dir) + night_sky_radiance(dir); }
