// The glows' smooth part (fog_glow_smooth.frag, on the reduced image) added
// to every viewport pixel: bilinear over the four nearest reduced pixels,
// each giving its glow at this pixel's own surface distance, between the
// glows it holds to its block's nearest and farthest surface (in log of the
// distance), so a glow stops at the host's geometry in front of it as the
// full-resolution image would, to within the block's depth range.
#include "atmosphere/pass_common.glsl"
#define ATMO_FOG_NO_UNIFORMS
#include "../host_sdk/include/atmo/atmo_fog_lights.glsl"

uniform sampler2D u_near;   // RGBA32F: glow, log2 distance
uniform sampler2D u_far;
uniform int u_divisor;

out vec4 out_color;

void main() {
  float d = ATMO_FOG_FAR;
  if (u_has_depth != 0) {
    vec4 p = view_point_from_depth(u_view_from_clip, ndc_xy(), host_depth(), u_depth_convention, u_log_far_m,
                                   u_log_coefficient);
    if (p.w >= 0.0) d = length(p.xyz);
  }
  float l = log2(max(d, 1.0e-3));
  vec2 q = (gl_FragCoord.xy - u_viewport.xy) / float(u_divisor) - 0.5;
  vec2 q0 = floor(q), f = q - q0;
  ivec2 size = textureSize(u_near, 0);
  vec3 sum = vec3(0.0);
  for (int k = 0; k < 4; ++k) {
    ivec2 o = ivec2(k & 1, k >> 1);
    ivec2 texel = clamp(ivec2(q0) + o, ivec2(0), size - 1);
    vec4 n = texelFetch(u_near, texel, 0);
    vec4 r = texelFetch(u_far, texel, 0);
    float t = r.a - n.a > 1.0e-3 ? clamp((l - n.a) / (r.a - n.a), 0.0, 1.0) : 0.0;
    float w = (o.x == 1 ? f.x : 1.0 - f.x) * (o.y == 1 ? f.y : 1.0 - f.y);
    sum += w * mix(n.rgb, r.rgb, t);
  }
  out_color = vec4(encode_output(sum), 0.0);
}
