// Puts the clouds' low-resolution image (exposed linear radiance,
// premultiplied, and coverage) over the host's frame: bilinear, encoded for
// the output as the other passes encode, premultiplied (blend ONE,
// ONE_MINUS_SRC_ALPHA).
#define ATMO_FN
#define IN(T) in T
#define OUT(T) out T
#define LUT2D sampler2D
vec3 sample_lut(sampler2D lut, vec2 uv) { return texture(lut, uv).rgb; }
#include "atmosphere/functions.glsl"

uniform sampler2D u_clouds;
uniform vec4 u_viewport;  // x, y, width, height of the host's viewport
uniform int u_output_encoding;

layout(location = 0) out vec4 out_color;

void main() {
  vec2 uv = (gl_FragCoord.xy - u_viewport.xy) / u_viewport.zw;
  vec4 c = texture(u_clouds, uv);
  if (c.a <= 0.0f) {
    out_color = vec4(0.0f);
    return;
  }
  // Encode the un-premultiplied colour (the display curve is not linear), then premultiply.
  vec3 colour = c.rgb / c.a;
  out_color = vec4((u_output_encoding == 1 ? encode_display_srgb(colour) : colour) * c.a, c.a);
}
