// The glows' smooth part on the reduced image (core/lights/glow_tiles.h): per
// pixel of it, a block of u_divisor x u_divisor viewport pixels, the glows of
// its screen tile (at most 8: the largest exactly, the rest merged) with sin
// gamma floored at the core angle's, along the block's central ray up to the
// nearest and the farthest host surface in the block (or the fog top).
// Outputs: the glow (cd/m^2, linear, times the albedo) and log2 of that
// distance, for each; the composite blends them per pixel by its own depth.
#include "atmosphere/pass_common.glsl"
#define ATMO_FOG_NO_UNIFORMS
#include "../host_sdk/include/atmo/atmo_fog_lights.glsl"

uniform sampler2D u_fog_airlight;   // the airlight table (R32F)
uniform float u_fog_airlight_size;
uniform float u_fog_top;            // fog top above the eye, m (ATMO_FOG_FAR: none)
uniform float u_core_sin;           // sin of the core angle: the floor of sin gamma here
uniform usampler2D u_tiles;         // RG32UI per tile: the first entry of its list, its length
uniform usampler2D u_lists;         // R32UI, entries of the glows texture, 4096 a row
uniform sampler2D u_glows;          // RGBA32F, 4 texels a glow, 256 a row
uniform vec2 u_tile_count;          // tiles across, up
uniform int u_divisor;

layout(location = 0) out vec4 out_near;
layout(location = 1) out vec4 out_far;

// The distance to the host's surface at viewport pixel px (ATMO_FOG_FAR where it drew nothing).
float surface_distance(vec2 px) {
  if (u_has_depth == 0) return ATMO_FOG_FAR;
  vec2 ndc = (px + 0.5 - u_viewport.xy) / u_viewport.zw * 2.0 - 1.0;
  float depth = texelFetch(u_depth, ivec2(px) - u_depth_origin, 0).r;
  vec4 p = view_point_from_depth(u_view_from_clip, ndc, depth, u_depth_convention, u_log_far_m, u_log_coefficient);
  return p.w < 0.0 ? ATMO_FOG_FAR : length(p.xyz);
}

// The sum of the tile's glows along `dir` up to d_vp (the include's atmo_fog_tile_glows).
vec3 glows(uint first, uint count, vec3 dir, float d_vp) {
  return atmo_fog_tile_glows(u_fog_airlight, u_fog_airlight_size, u_lists, u_glows, first, count, dir, d_vp,
                             u_core_sin);
}

void main() {
  // The block of viewport pixels under this pixel, clipped to the viewport.
  vec2 block = floor(gl_FragCoord.xy) * float(u_divisor) + u_viewport.xy;
  vec2 last = min(block + float(u_divisor - 1), u_viewport.xy + u_viewport.zw - 1.0);
  float d_near = ATMO_FOG_FAR, d_far = 0.0;
  for (int y = 0; y < u_divisor; ++y)
    for (int x = 0; x < u_divisor; ++x) {
      float d = surface_distance(min(block + vec2(x, y), last));
      d_near = min(d_near, d);
      d_far = max(d_far, d);
    }
  vec2 centre = 0.5 * (block + last + 1.0);
  vec2 ndc = (centre - u_viewport.xy) / u_viewport.zw * 2.0 - 1.0;
  vec3 dir = normalize(u_enu_from_view * view_ray_from_ndc(u_view_from_clip, ndc, u_depth_convention));
  // In-scattering stops where the ray leaves the fog (eye inside it).
  float top = u_fog_top < ATMO_FOG_FAR && u_fog_top > 0.0 && dir.z > 0.0 ? u_fog_top / dir.z : ATMO_FOG_FAR;
  ivec2 tile = ivec2(min(floor((centre - u_viewport.xy) / u_viewport.zw * u_tile_count), u_tile_count - 1.0));
  uvec2 list = texelFetch(u_tiles, tile, 0).xy;
  vec3 near_glow = glows(list.x, list.y, dir, min(d_near, top));
  // One evaluation where the block holds one surface (or only sky).
  bool one = d_far <= d_near * 1.01 || min(d_near, top) >= top;
  vec3 far_glow = one ? near_glow : glows(list.x, list.y, dir, min(d_far, top));
  out_near = vec4(near_glow, log2(max(d_near, 1.0e-3)));
  out_far = vec4(far_glow, log2(max(d_far, 1.0e-3)));
}
