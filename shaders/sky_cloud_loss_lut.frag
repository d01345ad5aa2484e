// Builds the sky's loss to the clouds' shadow (functions.glsl
// sky_cloud_loss_direction): per view direction from the eye, the light the
// clouds' shadow takes from the sunlit air along the part of the ray under
// the clouds (up to where it leaves the clouds' layer or map),
// integrate_scattering_shadowed's shadowed_away, cd/m^2. The sky pass's
// ATMO_SKY_CLOUD_SHADOW variant subtracts it: one fetch a pixel, where
// marching every pixel made the sky pass 17x dearer on llvmpipe.
#include "atmosphere/pass_common.glsl"

uniform vec2 u_sky_cloud_loss_size;  // the table's texels (gl::Renderer::kSkyCloudLossWidth, Height)

// Samples along the part of each ray under the clouds (up to ~100 km).
const int kSkyCloudShadowSteps = 24;

out vec4 out_color;

void main() {
  vec2 x = (gl_FragCoord.xy - 0.5f) / max(u_sky_cloud_loss_size - 1.0f, vec2(1.0f));
  vec3 dir = sky_cloud_loss_direction(x);
  float reach = cloud_shadow_reach(u_cloud_shadowing, dir);
  vec3 loss = vec3(0.0f);
  if (reach > 0.0f) {
    loss = integrate_scattering_shadowed(u_atmosphere, u_transmittance, u_transmittance_size, u_multiple_scattering,
                                         u_multiple_scattering_size, u_eye_altitude_m, dir, u_sun_direction_enu,
                                         reach, kSkyCloudShadowSteps, u_cloud_shadowing, u_cloud_shadow)
               .shadowed_away;
  }
  out_color = vec4(loss, 1.0f);
}
