// The layer march's temporal upsampling (core/clouds/cloud_temporal.h): this
// frame traced one pixel of each 2x2 block of the clouds' image (u_trace,
// pixel 2 * texel + u_offset); every other pixel takes the view's last image
// where its cloud point was, the point placed at the opacity-weighted depth of
// its block's fresh sample (a direction where that is clear sky), clamped to
// the fresh samples around it as far as the view moved (at rest an image pixel
// keeps its own trace of up to 3 frames ago: nothing moved, nothing is
// clamped); without a history (a cut, the first frame) it interpolates the
// fresh samples. Output: the view's new image (premultiplied radiance,
// coverage), which clouds_composite puts over the host's frame.
#define ATMO_FN
#define IN(T) in T
#define OUT(T) out T
#define LUT2D sampler2D
vec3 sample_lut(sampler2D lut, vec2 uv) { return texture(lut, uv).rgb; }
#include "atmosphere/functions.glsl"

uniform sampler2D u_trace;        // ceil(w / 2) x ceil(h / 2), linear
uniform sampler2D u_trace_depth;  // R32F, m (1e30 beyond the clouds and the host's geometry)
uniform sampler2D u_history;      // the view's last image, w x h, linear
uniform int u_has_history;
uniform ivec2 u_offset;           // the traced pixel of each block
uniform vec2 u_size;              // w, h
uniform mat4 u_view_from_clip;
uniform mat3 u_enu_from_view;
uniform int u_depth_convention;
uniform mat4 u_last_clip_from_enu;  // a point relative to the eye, ENU -> the last frame's clip space

layout(location = 0) out vec4 out_color;

// Beyond this a cloud point is taken as a direction (sky, the far field).
const float kFarM = 1.0e7f;
// The history is clamped fully from half an image pixel of motion on.
const float kClampMotionPx = 0.5f;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 block = p / 2;
  ivec2 trace_size = textureSize(u_trace, 0);
  vec4 fresh = texelFetch(u_trace, block, 0);
  if (p - 2 * block == u_offset) {
    out_color = fresh;
    return;
  }
  // The fresh samples' own grid: texel i holds image pixel 2 i + offset.
  vec2 s = (vec2(p - u_offset)) * 0.5f + 0.5f;
  vec4 spatial = texture(u_trace, s / vec2(trace_size));
  if (u_has_history == 0) {
    out_color = spatial;
    return;
  }
  vec2 ndc = (vec2(p) + 0.5f) / u_size * 2.0f - 1.0f;
  vec3 dir = normalize(u_enu_from_view * view_ray_from_ndc(u_view_from_clip, ndc, u_depth_convention));
  float depth_m = texelFetch(u_trace_depth, block, 0).r;
  vec4 last = u_last_clip_from_enu * (depth_m < kFarM ? vec4(dir * depth_m, 1.0f) : vec4(dir, 0.0f));
  vec2 uv_last = last.xy / max(last.w, 1e-30f) * 0.5f + 0.5f;
  if (last.w <= 0.0f || any(lessThan(uv_last, vec2(0.0f))) || any(greaterThan(uv_last, vec2(1.0f)))) {
    out_color = spatial;  // it was outside the last frame
    return;
  }
  vec4 history = texture(u_history, uv_last);
  vec4 lo = fresh, hi = fresh;
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      vec4 n = texelFetch(u_trace, clamp(block + ivec2(i, j), ivec2(0), trace_size - 1), 0);
      lo = min(lo, n);
      hi = max(hi, n);
    }
  float motion_px = length((uv_last * u_size) - (vec2(p) + 0.5f));
  out_color = mix(history, clamp(history, lo, hi), clamp(motion_px / kClampMotionPx, 0.0f, 1.0f));
}
