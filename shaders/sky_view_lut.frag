// Builds the sky-view table (functions.glsl, sky_view_texel): one fragment per
// texel of a u_sky_view_size render target, radiance in cd/m^2.
#include "atmosphere/pass_common.glsl"

uniform float u_sin_sun_elevation;

out vec4 out_color;

void main() {
  vec2 x = (gl_FragCoord.xy - 0.5f) / max(u_sky_view_size - 1.0f, vec2(1.0f));
  vec3 diffuse = sky_view_texel(u_atmosphere, u_transmittance, u_transmittance_size, u_multiple_scattering,
                                u_multiple_scattering_size, u_eye_altitude_m, x, u_sin_sun_elevation, u_steps);
  out_color = vec4(diffuse, 1.0f);
}
