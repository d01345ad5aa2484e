// One triangle that covers the viewport; no vertex buffers (an empty VAO).
// z = 0.5 lies inside the clip volume for both GL depth conventions.
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(p * 2.0f - 1.0f, 0.5f, 1.0f);
}
