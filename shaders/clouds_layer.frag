// Clouds by the layer march (clouds/cloud_layer_march.glsl), at 1/u_divisor
// of the viewport per axis: each pixel's view ray crosses every cloud at
// once through the clipmap, within a step budget, stops at the host's
// geometry and takes the aerial perspective in front of each cloud. Output:
// exposed linear radiance, premultiplied, and coverage (clouds_composite
// encodes), and the clouds' opacity-weighted depth (the temporal pass's
// reprojection). With u_trace_stride 2 a fragment traces image pixel
// 2 * fragment + u_trace_offset (one of each 2x2 block: clouds_resolve.frag).
#include "atmosphere/pass_common.glsl"
#define ATMO_AERIAL_NO_UNIFORMS
#include "../host_sdk/include/atmo/atmo_aerial_perspective.glsl"
#include "clouds/cloud_functions.glsl"

// The clipmap's levels stacked along z (gl/cloud_layer_renderer.cpp):
// RGBA16F (sigma, tau_light, tau_up, tau_down) and RG16F (tau_back,
// sigma droplet_um): core/clouds/cloud_clipmap.h.
uniform sampler3D u_layer_a;
uniform sampler3D u_layer_b;
uniform usampler3D u_layer_clear;  // R8UI: the levels' clear bricks, stacked along z likewise
uniform vec3 u_layer_size;  // texels of the stacked texture
#define CLOUD_LAYER int
vec3 cloud_layer_uvw(int level, vec3 q);
vec4 cloud_layer_fetch_a(IN(int) unused, int level, IN(vec3) q) { return texture(u_layer_a, cloud_layer_uvw(level, q)); }
vec2 cloud_layer_fetch_b(IN(int) unused, int level, IN(vec3) q) { return texture(u_layer_b, cloud_layer_uvw(level, q)).rg; }
float cloud_layer_fetch_clear(IN(int) unused, int level, IN(ivec3) brick);
vec2 g_uv;  // this pixel's place in the aerial-perspective volume
void cloud_layer_air(float depth_m, OUT(vec3) inscatter, OUT(vec3) transmittance) {
  atmo_aerial_perspective_sample(u_aerial_inscatter, u_aerial_transmittance, g_uv, depth_m, u_aerial_range_m,
                                 u_aerial_slices, inscatter, transmittance);
}
#include "clouds/cloud_layer_march.glsl"
#include "clouds/cloud_host_depth.glsl"

uniform CloudLayerMarch u_layer;
uniform CloudOctaves u_octaves;
uniform mat3 u_clouds_from_enu;  // the view's ENU axes to the clouds' ENU axes
uniform int u_trace_stride;      // 1: every image pixel; 2: one of each 2x2 block
uniform ivec2 u_trace_offset;    // which one

vec3 cloud_layer_uvw(int level, vec3 q) {
  return (q + vec3(0.0f, 0.0f, u_layer.level_dims[level].w)) / u_layer_size;
}
float cloud_layer_fetch_clear(IN(int) unused, int level, IN(ivec3) brick) {
  ivec3 k = clamp(brick, ivec3(0), ivec3(u_layer.level_bricks[level].xyz) - 1);
  return float(texelFetch(u_layer_clear, k + ivec3(0, 0, int(u_layer.level_bricks[level].w)), 0).r);
}

layout(location = 0) out vec4 out_color;
layout(location = 1) out float out_depth;

void main() {
  // The image pixel this fragment traces (u_viewport is the image: 0, 0, w, h).
  vec2 pixel = floor(gl_FragCoord.xy - u_viewport.xy) * float(u_trace_stride) + vec2(u_trace_offset) + 0.5f;
  g_uv = pixel / u_viewport.zw;
  vec2 ndc = g_uv * 2.0f - 1.0f;
  vec3 dir = normalize(u_enu_from_view * view_ray_from_ndc(u_view_from_clip, ndc, u_depth_convention));
  float t_max = cloud_host_distance_at_m(pixel, ndc);
  CloudLayerSample s = cloud_layer_march(0, u_layer, u_octaves, normalize(u_clouds_from_enu * dir), t_max);
  out_color = vec4(s.radiance * u_exposure, 1.0f - s.transmittance);
  out_depth = s.depth_m;
}
