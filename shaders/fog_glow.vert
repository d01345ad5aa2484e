// One light's glow core: a screen rectangle (NDC) that bounds its core angle
// (or less, where its glow falls under the threshold sooner; computed on the
// CPU, core/lights/glow_tiles.h); instanced, one instance per light.
layout(location = 0) in vec4 a_rect;        // x0, y0, x1, y1 in NDC
layout(location = 1) in vec4 a_light;       // position relative to the eye (ENU m), effective extinction 1/m
layout(location = 2) in vec4 a_intensity;   // cd per channel (times the albedo), cos_inner
layout(location = 3) in vec4 a_axis;        // cone axis (ENU), cos_outer
layout(location = 4) in vec4 a_cone;        // cone lobes (1, or 2: both ways), unused

flat out vec4 v_light;
flat out vec4 v_intensity;
flat out vec4 v_axis;
flat out float v_lobes;

void main() {
  int corner = gl_VertexID % 6;  // two triangles: 0 1 2, 2 1 3
  int c = corner < 3 ? corner : (corner == 3 ? 2 : (corner == 4 ? 1 : 3));
  vec2 t = vec2(float(c & 1), float(c >> 1));
  gl_Position = vec4(mix(a_rect.xy, a_rect.zw, t), 0.5, 1.0);
  v_light = a_light;
  v_intensity = a_intensity;
  v_axis = a_axis;
  v_lobes = a_cone.x;
}
