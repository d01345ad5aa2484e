// Fog over everything drawn so far: colour * transmittance + the fog's own
// light (the ambient light it scatters, and the diffusion term of the host's
// lights: docs/FOG.md). Dual-source blending does the multiply, as in the
// aerial-perspective pass: blend(ONE, SRC1_COLOR).
#include "atmosphere/pass_common.glsl"
#define ATMO_FOG_NO_UNIFORMS
#include "../host_sdk/include/atmo/atmo_fog_lights.glsl"

uniform vec4 u_fog;                 // extinction 1/m, albedo, top above the eye m (ATMO_FOG_FAR: none), unused
uniform vec3 u_fog_ambient;         // cd/m^2 the fog scatters from the sky, Sun and Moon (isotropic)
uniform vec3 u_fog_fluence;         // the lights' diffusion fluence at the eye, per channel
uniform mat3 u_fog_flux;            // column c: channel c's flux vector towards the lights, ENU

layout(location = 0, index = 0) out vec4 out_light;
layout(location = 0, index = 1) out vec4 out_transmittance;

void main() {
  vec2 ndc = ndc_xy();
  // Without a host depth texture every pixel is open sky (w < 0).
  vec4 p = u_has_depth != 0 ? view_point_from_depth(u_view_from_clip, ndc, host_depth(), u_depth_convention,
                                                     u_log_far_m, u_log_coefficient)
                            : vec4(0.0, 0.0, 0.0, -1.0);
  vec3 ray = p.w < 0.0 ? view_ray_from_ndc(u_view_from_clip, ndc, u_depth_convention) : p.xyz;
  vec3 dir = normalize(u_enu_from_view * ray);
  float d = p.w < 0.0 ? ATMO_FOG_FAR : length(p.xyz);
  float transmittance = atmo_fog_transmittance(u_fog.x, atmo_fog_ray_length(d, dir.z, u_fog.z));
  vec3 light = atmo_fog_medium_light(transmittance, u_fog_ambient, u_fog_fluence, u_fog_flux, dir);
  out_light = vec4(encode_output(light), 0.0);
  out_transmittance = vec4(vec3(transmittance), 1.0);
}
