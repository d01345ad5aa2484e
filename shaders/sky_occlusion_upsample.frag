// ATMO_PASS_SKY_OCCLUSION at a fraction of the pixels, second step: each pixel takes the reduced image's
// factors (sky_occlusion.frag with ATMO_OCC_REDUCED: factor rgb, the distance of the surface it was evaluated
// on) of the four texels around it, bilinearly, weighted by how near each one's distance is to the pixel's
// own (so a factor does not bleed across a silhouette); where none is near, the nearest in distance.
#include "atmosphere/pass_common.glsl"

uniform sampler2D u_reduced;  // RGBA32F: factor rgb (linear), distance m (-1: no surface)
uniform int u_reduction;      // pixels a texel spans across

out vec4 out_factor;

void main() {
  vec4 p = view_point_from_depth(u_view_from_clip, ndc_xy(), host_depth(), u_depth_convention, u_log_far_m,
                                 u_log_coefficient);
  if (p.w < 0.0) discard;
  float d = length(p.xyz);
  vec2 at = (gl_FragCoord.xy - u_viewport.xy) / float(u_reduction) - 0.5;  // in texel centres
  ivec2 base = ivec2(floor(at));
  vec2 f = at - vec2(base);
  ivec2 last = textureSize(u_reduced, 0) - 1;
  vec3 sum = vec3(0.0);
  float weights = 0.0;
  vec3 nearest = vec3(1.0);
  float best = 1.0e30;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      vec4 t = texelFetch(u_reduced, clamp(base + ivec2(i, j), ivec2(0), last), 0);
      if (t.w < 0.0) continue;
      float off = abs(t.w - d) / max(d, 1.0e-3);  // relative distance between the surfaces
      // Within 2 % of the distance: the same surface; beyond 10 %: another.
      float w = (i == 0 ? 1.0 - f.x : f.x) * (j == 0 ? 1.0 - f.y : f.y) * (1.0 - smoothstep(0.02, 0.1, off));
      sum += w * t.rgb;
      weights += w;
      if (off < best) {
        best = off;
        nearest = t.rgb;
      }
    }
  }
  vec3 factor = weights > 1.0e-4 ? sum / weights : nearest;
  if (u_output_encoding == 1) factor = pow(factor, vec3(1.0 / 2.2));
  out_factor = vec4(factor, 1.0);
}
