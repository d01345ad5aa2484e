// cloud_host_depth.glsl — the host's surface under a pixel of the clouds'
// low-resolution image (1/u_divisor of the host's viewport per axis), for the
// march and the impostors. Needs pass_common.glsl.
uniform int u_divisor;
uniform vec4 u_full_viewport;  // the host's viewport, window pixels

// Distance from the eye to the host's surface under `image_px` (a pixel of
// the low-resolution image, from its viewport's corner), m (1e30 without
// depth or on the far plane).
float cloud_host_distance_at_m(vec2 image_px, vec2 ndc) {
  if (u_has_depth == 0) return 1e30f;
  ivec2 full = ivec2(u_full_viewport.xy + image_px * float(u_divisor));
  full = min(full, ivec2(u_full_viewport.xy + u_full_viewport.zw) - 1);
  vec4 p = view_point_from_depth(u_view_from_clip, ndc, texelFetch(u_depth, full - u_depth_origin, 0).r, u_depth_convention,
                                 u_log_far_m, u_log_coefficient);
  return p.w > 0.0f ? length(p.xyz) : 1e30f;
}

// The same under this fragment.
float cloud_host_distance_m(vec2 ndc) { return cloud_host_distance_at_m(gl_FragCoord.xy - u_viewport.xy, ndc); }
