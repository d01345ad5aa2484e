// Clouds by direct ray marching, at 1/u_divisor of the viewport per axis:
// each pixel's view ray crosses the instances of this batch (sorted near to
// far on the CPU) front to back, stops at the host's geometry, and takes the
// aerial perspective at each cloud's mean depth. A cloud cross-fading to its
// impostor counts with its weight. Output: exposed linear radiance,
// premultiplied, and coverage (clouds_composite encodes).
#include "atmosphere/pass_common.glsl"
#define ATMO_AERIAL_NO_UNIFORMS
#include "../host_sdk/include/atmo/atmo_aerial_perspective.glsl"
#include "clouds/cloud_functions.glsl"
#include "clouds/cloud_instance.glsl"

#include "clouds/cloud_host_depth.glsl"

layout(location = 0) out vec4 out_color;

void main() {
  vec2 ndc = ndc_xy();
  vec3 dir = normalize(u_enu_from_view * view_ray_from_ndc(u_view_from_clip, ndc, u_depth_convention));
  float t_max = cloud_host_distance_m(ndc);
  vec2 uv = (gl_FragCoord.xy - u_viewport.xy) / u_viewport.zw;
  vec3 radiance = vec3(0.0f);
  float transmittance = 1.0f;
  for (int i = 0; i < u_instance_count; ++i) {
    if (!cloud_instance_hit(i, dir)) continue;  // most rays miss most clouds
    CloudSample s = cloud_instance_march(i, dir, t_max);
    if (s.transmittance >= 1.0f) continue;
    float w = cloud_instance_weight(i);
    vec3 air_inscatter, air_transmittance;
    atmo_aerial_perspective_sample(u_aerial_inscatter, u_aerial_transmittance, uv, s.depth_m, u_aerial_range_m,
                                   u_aerial_slices, air_inscatter, air_transmittance);
    float opacity = w * (1.0f - s.transmittance);
    radiance += transmittance * (w * s.radiance * air_transmittance + opacity * air_inscatter);
    transmittance *= 1.0f - opacity;
    if (transmittance < CLOUD_OPAQUE_TRANSMITTANCE) {  // cloud_march.glsl: nothing behind shows
      transmittance = 0.0f;
      break;
    }
  }
  out_color = vec4(radiance * u_exposure, 1.0f - transmittance);
}
