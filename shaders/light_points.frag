// The host's lights as points: one fragment per pixel of a light's square.
// The pixel receives the light's illuminance integrated over the pixel
// (night_sky/point_footprint.glsl, the stars' footprint at the light's own
// width), over whatever is drawn (the vertex shader already hid a light
// behind the host's geometry).
// LINEAR_HDR: exposure · L added (blend ONE, ONE). DISPLAY_SRGB: the
// framebuffer holds encoded values, which cannot be added to: this writes
// encode(exposure · L) blended with MAX, so a light shows at least as
// bright as itself and never darkens what is there (the encoded sum would
// need the linear background, which the host's geometry does not give).
#include "atmosphere/pass_common.glsl"
#include "night_sky/point_footprint.glsl"

flat in vec2 v_center_px;
flat in vec3 v_radiance;
flat in float v_sigma_px;

out vec4 out_color;

void main() {
  vec2 d = gl_FragCoord.xy - v_center_px;
  out_color = vec4(encode_output(v_radiance * point_footprint_weight(d.x, d.y, v_sigma_px)), 0.0f);
}
