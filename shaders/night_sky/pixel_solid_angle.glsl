// pixel_solid_angle.glsl — the solid angle (sr) of the pixel at NDC position
// ndc, for the point passes (stars and planets, the host's lights): the
// view-space ray f(x, y) = h.xyz / h.w, h = view_from_clip (x, y, z_near, 1),
// spans |f . (df/dx x df/dy)| / |f|^3 sr per unit NDC area, and a pixel is
// (2 / width) x (2 / height) NDC units. Exact for any projective camera
// (off-axis pixels shrink as cos^3 for a plain perspective).
// depth_convention: AtmoDepthConvention (1: reversed, the near plane at z = 1).
float pixel_solid_angle(mat4 view_from_clip, int depth_convention, vec2 viewport_size, vec2 ndc) {
  float near_z = depth_convention == 1 ? 1.0f : -1.0f;
  vec4 h = view_from_clip * vec4(ndc, near_z, 1.0f);
  vec4 bx = view_from_clip[0];
  vec4 by = view_from_clip[1];
  vec3 f = h.xyz / h.w;
  vec3 fx = (bx.xyz * h.w - h.xyz * bx.w) / (h.w * h.w);
  vec3 fy = (by.xyz * h.w - h.xyz * by.w) / (h.w * h.w);
  float len = length(f);
  return abs(dot(f, cross(fx, fy))) / (len * len * len) * (4.0f / (viewport_size.x * viewport_size.y));
}
