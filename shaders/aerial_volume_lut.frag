// Builds one slice of the aerial-perspective volume: for the froxel centre
// ray through this texel of the (u_viewport-sized screen mapped to a
// u_aerial_size grid), in-scattering and transmittance from the eye to the
// slice's distance. Two render targets: in-scattered cd/m^2, transmittance.
#include "atmosphere/pass_common.glsl"
#define ATMO_AERIAL_NO_UNIFORMS
#include "../host_sdk/include/atmo/atmo_aerial_perspective.glsl"  // the slice mapping

uniform int u_slice;
uniform vec2 u_aerial_grid;  // froxels across the screen (x, y)

layout(location = 0) out vec4 out_inscattered;
layout(location = 1) out vec4 out_transmittance;

void main() {
  vec2 ndc = gl_FragCoord.xy / u_aerial_grid * 2.0f - 1.0f;
  vec3 dir = normalize(u_enu_from_view * view_ray_from_ndc(u_view_from_clip, ndc, u_depth_convention));
  float distance_m = atmo_aerial_slice_distance(u_slice, u_aerial_slices, u_aerial_range_m);
  ScatteringResult s = integrate_scattering_shadowed(u_atmosphere, u_transmittance, u_transmittance_size,
                                            u_multiple_scattering, u_multiple_scattering_size, u_eye_altitude_m, dir,
                                            u_sun_direction_enu, distance_m, u_steps, u_cloud_shadowing,
                                            u_cloud_shadow);
  out_inscattered = vec4(s.inscattered, 1.0f);
  out_transmittance = vec4(s.transmittance, 1.0f);
}
