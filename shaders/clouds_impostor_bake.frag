// Renders one cloud's impostor (Harris & Lastra 2001): the cloud as the eye
// sees it now, through the square billboard at its centre, into one layer of
// the impostor atlas. Instance 0 of the batch is the cloud. Output 0: radiance
// times u_radiance_scale (cd/m^2 normalised by the light, so RGBA16F keeps
// night and day alike), premultiplied by coverage; output 1: where along each
// ray the cloud's opacity-weighted depth lies, relative to the billboard
// point on that ray (m), so the draw can place it from another eye.
#include "atmosphere/pass_common.glsl"
#include "clouds/cloud_functions.glsl"
#include "clouds/cloud_instance.glsl"

uniform vec4 u_board_centre;  // the billboard's centre from the eye, half size m
uniform vec3 u_board_right;   // unit, the eye's ENU axes
uniform vec3 u_board_up;
uniform float u_radiance_scale;
uniform float u_tile_texels;

layout(location = 0) out vec4 out_color;
layout(location = 1) out float out_depth_offset;

void main() {
  vec2 st = gl_FragCoord.xy / u_tile_texels * 2.0f - 1.0f;
  vec3 point = u_board_centre.xyz + u_board_centre.w * (st.x * u_board_right + st.y * u_board_up);
  float t_board = length(point);
  vec3 dir = point / t_board;
  CloudSample s = cloud_instance_march(0, dir, 1e30f);
  float coverage = 1.0f - s.transmittance;
  out_color = vec4(s.radiance * u_radiance_scale, coverage);
  out_depth_offset = coverage > 0.0f ? s.depth_m - t_board : 0.0f;
}
