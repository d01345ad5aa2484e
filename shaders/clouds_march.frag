// Clouds by direct ray marching, at 1/u_divisor of the viewport per axis:
// each pixel's view ray crosses the instances of this batch (sorted near to
// far on the CPU) front to back through cloud_march.glsl, stops at the host's
// geometry, and takes the aerial perspective at each cloud's mean depth.
// Output: premultiplied radiance (encoded) and coverage, for clouds_composite.
#include "atmosphere/pass_common.glsl"
#define ATMO_AERIAL_NO_UNIFORMS
#include "../host_sdk/include/atmo/atmo_aerial_perspective.glsl"
#include "clouds/cloud_functions.glsl"

// All prototypes in one 3D atlas (RGBA16F: density, tau_light, tau_up, tau_down),
// each block surrounded by zero voxels, so trilinear fades to 0 at its border.
uniform sampler3D u_cloud_atlas;
uniform vec3 u_cloud_atlas_size;
#define CLOUD_VOLUME vec3
vec4 cloud_fetch(IN(vec3) atlas_offset, IN(vec3) p) {
  return texture(u_cloud_atlas, (atlas_offset + clamp(p, vec3(0.0f), vec3(1e9f))) / u_cloud_atlas_size);
}
#include "clouds/cloud_march.glsl"

const int kFloatsPerInstance = 7;  // vec4s, as gl/cloud_renderer.cpp writes them
const int kMaxInstances = 64;
uniform vec4 u_instances[kFloatsPerInstance * kMaxInstances];
uniform int u_instance_count;
uniform CloudPhase u_phase;
uniform CloudOctaves u_octaves;
uniform vec3 u_light_illuminance;
uniform vec3 u_sky_radiance;
uniform vec3 u_ground_radiance;
uniform float u_step_voxels;
uniform int u_max_steps;
uniform int u_divisor;
uniform vec4 u_full_viewport;  // the host's viewport (the depth texture's pixels)

layout(location = 0) out vec4 out_color;

void main() {
  vec2 ndc = ndc_xy();
  vec3 dir = normalize(u_enu_from_view * view_ray_from_ndc(u_view_from_clip, ndc, u_depth_convention));
  float t_max = 1e30f;
  if (u_has_depth != 0) {
    ivec2 full = ivec2(u_full_viewport.xy + (gl_FragCoord.xy - u_viewport.xy) * float(u_divisor));
    full = min(full, ivec2(u_full_viewport.xy + u_full_viewport.zw) - 1);
    vec4 p = view_point_from_depth(u_view_from_clip, ndc, texelFetch(u_depth, full, 0).r, u_depth_convention,
                                   u_log_far_m, u_log_coefficient);
    if (p.w > 0.0f) t_max = length(p.xyz);
  }
  vec2 uv = (gl_FragCoord.xy - u_viewport.xy) / u_viewport.zw;
  vec3 radiance = vec3(0.0f);
  float transmittance = 1.0f;
  for (int i = 0; i < u_instance_count; ++i) {
    int b = i * kFloatsPerInstance;
    vec4 centre = u_instances[b + 6];
    // Bounding sphere first: most rays miss most clouds.
    float tc = dot(centre.xyz, dir);
    vec3 closest = centre.xyz - dir * tc;
    if (dot(closest, closest) > centre.w * centre.w || tc + centre.w < 0.0f) continue;
    vec4 origin = u_instances[b + 0];
    vec3 ax = u_instances[b + 1].xyz, ay = u_instances[b + 2].xyz, az = u_instances[b + 3].xyz;
    CloudMarch m;
    m.grid_size = u_instances[b + 4].xyz;
    m.voxel_size_m = origin.w;
    m.extinction_per_m = u_instances[b + 1].w;
    m.albedo = u_instances[b + 2].w;
    m.step_voxels = u_step_voxels;
    m.max_steps = u_max_steps;
    m.light_illuminance = u_light_illuminance;
    m.light_dir_grid = u_instances[b + 5].xyz;
    m.sky_radiance = u_sky_radiance;
    m.ground_radiance = u_ground_radiance;
    vec3 rel = -origin.xyz;
    vec3 origin_index = vec3(dot(rel, ax), dot(rel, ay), dot(rel, az)) / origin.w;
    vec3 dir_grid = vec3(dot(dir, ax), dot(dir, ay), dot(dir, az));
    CloudSample s = cloud_march(vec3(u_instances[b + 3].w, u_instances[b + 4].w, u_instances[b + 5].w), m, u_phase,
                                u_octaves, origin_index, dir_grid, t_max);
    if (s.transmittance >= 1.0f) continue;
    vec3 air_inscatter, air_transmittance;
    atmo_aerial_perspective_sample(u_aerial_inscatter, u_aerial_transmittance, uv, s.depth_m, u_aerial_range_m,
                                   u_aerial_slices, air_inscatter, air_transmittance);
    radiance += transmittance * (s.radiance * air_transmittance + (1.0f - s.transmittance) * air_inscatter);
    transmittance *= s.transmittance;
    if (transmittance < 1e-3f) break;
  }
  float coverage = 1.0f - transmittance;
  if (coverage <= 0.0f) {
    out_color = vec4(0.0f);
    return;
  }
  // Encode the un-premultiplied colour (the display curve is not linear), then premultiply.
  out_color = vec4(encode_output(radiance / coverage) * coverage, coverage);
}
