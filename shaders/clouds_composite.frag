// Puts the clouds' low-resolution image over the host's frame: bilinear,
// premultiplied (blend ONE, ONE_MINUS_SRC_ALPHA).
uniform sampler2D u_clouds;
uniform vec4 u_viewport;  // x, y, width, height of the host's viewport

layout(location = 0) out vec4 out_color;

void main() {
  vec2 uv = (gl_FragCoord.xy - u_viewport.xy) / u_viewport.zw;
  out_color = texture(u_clouds, uv);
}
