// One impostor texel over the march image: the baked radiance and coverage,
// hidden behind the host's surface by its own depth, with the aerial
// perspective at that depth, times the impostor's weight (the direct march
// has the rest while they cross-fade). Exposed linear, premultiplied, as
// clouds_march.frag writes.
#include "atmosphere/pass_common.glsl"
#define ATMO_AERIAL_NO_UNIFORMS
#include "../host_sdk/include/atmo/atmo_aerial_perspective.glsl"

uniform sampler2DArray u_impostor_colour;
uniform sampler2DArray u_impostor_depth;
#include "clouds/cloud_host_depth.glsl"

in vec2 v_st;
in vec3 v_point;
flat in float v_layer;
flat in float v_weight;
flat in float v_factor;

layout(location = 0) out vec4 out_color;

void main() {
  vec4 texel = texture(u_impostor_colour, vec3(v_st, v_layer));
  if (texel.a <= 1e-4f) discard;
  float depth_m = max(length(v_point) + texture(u_impostor_depth, vec3(v_st, v_layer)).r, 0.0f);
  if (cloud_host_distance_m(ndc_xy()) < depth_m) discard;
  vec2 uv = (gl_FragCoord.xy - u_viewport.xy) / u_viewport.zw;
  vec3 air_inscatter, air_transmittance;
  atmo_aerial_perspective_sample(u_aerial_inscatter, u_aerial_transmittance, uv, depth_m, u_aerial_range_m,
                                 u_aerial_slices, air_inscatter, air_transmittance);
  float coverage = texel.a * v_weight;
  vec3 radiance = v_weight * texel.rgb * v_factor * air_transmittance + coverage * air_inscatter;
  out_color = vec4(radiance * u_exposure, coverage);
}
