// The impostors of one batch as billboards: instance i is a square (two
// triangles, no vertex buffers) at its baked place, seen from this eye.
// Per impostor, 4 vec4s (gl/cloud_renderer.cpp): centre from the eye and half
// size m; right axis and atlas layer; up axis and impostor weight; radiance
// factor (atlas value to cd/m^2).
const int kVec4PerBoard = 4;
const int kMaxBoards = 64;
uniform vec4 u_boards[kVec4PerBoard * kMaxBoards];
uniform mat4 u_clip_from_enu;  // projection times the view's rotation (eye at the origin)
uniform vec2 u_ndc_scale;      // the march image's used part over its full size

out vec2 v_st;             // [0, 1]^2 across the impostor
out vec3 v_point;          // from the eye, m
flat out float v_layer;
flat out float v_weight;
flat out float v_factor;

void main() {
  int b = gl_InstanceID * kVec4PerBoard;
  const vec2 corners[6] = vec2[6](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
  vec2 c = corners[gl_VertexID];
  vec4 centre = u_boards[b];
  vec3 point = centre.xyz + centre.w * (c.x * u_boards[b + 1].xyz + c.y * u_boards[b + 2].xyz);
  v_st = c * 0.5f + 0.5f;
  v_point = point;
  v_layer = u_boards[b + 1].w;
  v_weight = u_boards[b + 2].w;
  v_factor = u_boards[b + 3].x;
  vec4 clip = u_clip_from_enu * vec4(point, 1.0f);
  clip.xy = (clip.xy + clip.w) * u_ndc_scale - clip.w;  // the march image's viewport is a fraction of its texels
  gl_Position = clip;
}
