// Aerial perspective: host colour * transmittance + in-scattered light along
// the view ray up to the host's geometry. Dual-source blending does the
// multiply: blend(ONE, SRC1_COLOR) with out_transmittance as source 1.
// The LUT and analytic tiers read the aerial-perspective volume (two texture
// fetches); the march tier integrates per pixel.
#include "atmosphere/pass_common.glsl"
#define ATMO_AERIAL_NO_UNIFORMS
#include "../host_sdk/include/atmo/atmo_aerial_perspective.glsl"  // the same lookup hosts use

layout(location = 0, index = 0) out vec4 out_inscattered;
layout(location = 0, index = 1) out vec4 out_transmittance;

void main() {
  vec4 p = view_point_from_depth(u_view_from_clip, ndc_xy(), host_depth(), u_depth_convention, u_log_far_m,
                                 u_log_coefficient);
  if (p.w < 0.0f) discard;  // sky: nothing to haze
  float distance_m = length(p.xyz);
  vec3 inscattered;
  vec3 transmittance;
#if ATMO_METHOD == METHOD_MARCH
  {
    vec3 dir = normalize(u_enu_from_view * (p.xyz / max(distance_m, 1e-6f)));
    ScatteringResult s = integrate_scattering_shadowed(u_atmosphere, u_transmittance, u_transmittance_size,
                                              u_multiple_scattering, u_multiple_scattering_size, u_eye_altitude_m, dir,
                                              u_sun_direction_enu, distance_m, u_steps, u_cloud_shadowing,
                                              u_cloud_shadow);
    inscattered = s.inscattered;
    transmittance = s.transmittance;
  }
#else
  {
    vec2 uv = (gl_FragCoord.xy - u_viewport.xy) / u_viewport.zw;
    atmo_aerial_perspective_sample(u_aerial_inscatter, u_aerial_transmittance, uv, distance_m, u_aerial_range_m,
                                   u_aerial_slices, inscattered, transmittance);
  }
#endif
  out_inscattered = vec4(encode_output(inscattered), 0.0f);
  out_transmittance = vec4(transmittance, 1.0f);
}
