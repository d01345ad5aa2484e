// cloud_instance.glsl — the clouds of one batch as gl/cloud_renderer.cpp packs
// them, and the march of one along a ray from the eye: shared by the direct
// march (clouds_march.frag) and the impostor bake (clouds_impostor_bake.frag),
// so both draw a cloud the same way. Needs pass_common.glsl (ATMO_FN, IN())
// and clouds/cloud_functions.glsl before it. Positions are metres from the
// eye in the eye's ENU axes.

// All prototypes in one 3D atlas (RGBA16F: density, tau_light, tau_up, tau_down),
// each block surrounded by zero voxels, so trilinear fades to 0 at its border.
uniform sampler3D u_cloud_atlas;
uniform vec3 u_cloud_atlas_size;
#define CLOUD_VOLUME vec3
vec4 cloud_fetch(IN(vec3) atlas_offset, IN(vec3) p) {
  return texture(u_cloud_atlas, (atlas_offset + clamp(p, vec3(0.0f), vec3(1e9f))) / u_cloud_atlas_size);
}
#include "clouds/cloud_march.glsl"

// Per instance, kVec4PerInstance vec4s (gl/cloud_renderer.cpp pack_instance):
//   0 grid origin, voxel size m | 1 grid x axis, extinction 1/m | 2 y axis, albedo
//   3 z axis, atlas offset x    | 4 grid size (voxels), offset y | 5 light direction (grid), offset z
//   6 bounding-sphere centre, radius m | 7 phase (g_hg, g_draine, alpha_draine, w_draine)
//   8 (direct-march weight, continuing sides as bits: west 1, east 2, south 4, north 8, unused, unused)
const int kVec4PerInstance = 9;
const int kMaxInstances = 64;
uniform vec4 u_instances[kVec4PerInstance * kMaxInstances];
uniform int u_instance_count;
uniform CloudOctaves u_octaves;
uniform vec3 u_light_illuminance;
uniform vec3 u_sky_radiance;
uniform vec3 u_ground_radiance;
uniform float u_step_voxels;
uniform int u_max_steps;

// Whether the ray from the eye along unit `dir` meets instance i's bounding sphere.
bool cloud_instance_hit(int i, vec3 dir) {
  vec4 centre = u_instances[i * kVec4PerInstance + 6];
  float tc = dot(centre.xyz, dir);
  vec3 closest = centre.xyz - dir * tc;
  return dot(closest, closest) <= centre.w * centre.w && tc + centre.w >= 0.0f;
}

float cloud_instance_weight(int i) { return u_instances[i * kVec4PerInstance + 8].x; }

// Instance i along the ray from the eye, stopping at t_max_m.
CloudSample cloud_instance_march(int i, vec3 dir, float t_max_m) {
  int b = i * kVec4PerInstance;
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
  int sides = int(u_instances[b + 8].y);  // bit 0 west, 1 east, 2 south, 3 north
  m.continuing_sides = vec4(float(sides & 1), float((sides >> 1) & 1), float((sides >> 2) & 1), float((sides >> 3) & 1));
  vec4 p = u_instances[b + 7];
  CloudPhase phase;
  phase.g_hg = p.x;
  phase.g_draine = p.y;
  phase.alpha_draine = p.z;
  phase.w_draine = p.w;
  vec3 rel = -origin.xyz;
  vec3 origin_index = vec3(dot(rel, ax), dot(rel, ay), dot(rel, az)) / origin.w;
  vec3 dir_grid = vec3(dot(dir, ax), dot(dir, ay), dot(dir, az));
  return cloud_march(vec3(u_instances[b + 3].w, u_instances[b + 4].w, u_instances[b + 5].w), m, phase, u_octaves,
                     origin_index, dir_grid, t_max_m);
}
