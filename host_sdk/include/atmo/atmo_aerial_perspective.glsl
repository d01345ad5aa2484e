// atmo_aerial_perspective.glsl — aerial perspective for the HOST's own
// transparent objects (glass, particles, lights' halos...), the same haze the
// plugin's ATMO_PASS_AERIAL_PERSPECTIVE puts on opaque geometry. The plugin's
// own pass includes this file, so both use one function.
//
// Use (GLSL 3.30+ fragment shader, after the plugin's aerial pass this frame):
//   #include or paste this file (hosts without #include: concatenate it).
//   From get_lighting (AtmoLighting): bind aerial_inscatter_texture and
//   aerial_transmittance_texture (GL_TEXTURE_3D, GL_LINEAR, CLAMP_TO_EDGE) to
//   the samplers below, set atmo_aerial_range_m = aerial_range_m,
//   atmo_aerial_slices = aerial_slices, atmo_viewport = the view's viewport
//   (x, y, width, height in pixels) and atmo_exposure = the view's exposure
//   scale (the multiplier from cd/m^2 to the host's linear units).
//   Then:  colour = atmo_apply_aerial_perspective(colour, distance_m);
//   with distance_m the fragment's distance from the eye in metres (length of
//   the view-space position). Premultiplied-alpha blending: apply it to the
//   premultiplied colour and scale the in-scattered term by alpha, i.e. use
//   atmo_aerial_perspective_terms() and combine as shown there.
//
// The volume: screen-aligned froxels (u, v = the pixel's position in the
// viewport), slice k of n at distance range * ((k + 1) / n)^2 from the eye.
// Between two slices (and between the eye and the first) the segment is taken
// as homogeneous: its transmittance T_seg = T_far / T_near and in-scattered
// light L_seg = (L_far - L_near) / T_near, and at a fraction f of its length
// (in distance) T = T_near T_seg^f, L = L_near + T_near L_seg (1 - T_seg^f) /
// (1 - T_seg) — exact for uniform air, so the result does not depend on where
// the slices fall (the range, i.e. the far plane, or an infinite one).
// Units: in-scattered light in cd/m^2 (linear Rec.709), transmittance 0..1.
#ifndef ATMO_AERIAL_PERSPECTIVE_GLSL
#define ATMO_AERIAL_PERSPECTIVE_GLSL

#ifndef ATMO_AP_FN
#define ATMO_AP_FN
#endif

// Distance (metres) that slice `slice` of `slices` reaches.
ATMO_AP_FN float atmo_aerial_slice_distance(int slice, int slices, float range_m) {
  float w = (float(slice) + 1.0f) / float(slices);
  return range_m * w * w;
}

#ifndef ATMO_AP_OUT
#define ATMO_AP_OUT(T) out T
#endif

// The two slices around a distance: (third texture coordinate of the nearer
// slice, of the farther one, fraction f of the way between them in distance,
// 1 when the nearer end is the eye itself (no texel: L = 0, T = 1), else 0).
// Beyond the last slice f is 1 at the last slice. Written in the subset the
// plugin's C++ twin compiles (float literals with f, no swizzles).
ATMO_AP_FN vec4 atmo_aerial_slice_pair(float distance_m, float range_m, int slices) {
  float n = float(slices);
  float w = sqrt(clamp(distance_m / range_m, 0.0f, 1.0f)) * n;  // continuous slice index + 1
  int far_slice = int(min(floor(w), n - 1.0f));
  float near_m = far_slice > 0 ? atmo_aerial_slice_distance(far_slice - 1, slices, range_m) : 0.0f;
  float far_m = atmo_aerial_slice_distance(far_slice, slices, range_m);
  float f = clamp((distance_m - near_m) / (far_m - near_m), 0.0f, 1.0f);
  float z_far = (float(far_slice) + 0.5f) / n;
  return vec4(z_far - 1.0f / n, z_far, f, far_slice > 0 ? 0.0f : 1.0f);
}

// One colour channel at fraction f of a homogeneous segment from a point with
// (in-scattered l0, transmittance t0) to one with (l1, t1): (l, t) there.
ATMO_AP_FN vec2 atmo_aerial_segment(float l0, float t0, float l1, float t1, float f) {
  float t_seg = clamp(t1 / max(t0, 1e-30f), 1e-30f, 1.0f);
  float l_seg = max(l1 - l0, 0.0f) / max(t0, 1e-30f);
  float t_f = exp2(f * log2(t_seg));
  // (1 - T^f) / (1 - T) tends to f as T -> 1 (optically thin): no 0/0.
  float grown = 1.0f - t_seg > 1e-4f ? (1.0f - t_f) / (1.0f - t_seg) : f;
  return vec2(l0 + t0 * l_seg * grown, t0 * t_f);
}

// The three channels: in-scattered light and transmittance at fraction f
// between the slice values (l0, t0) and (l1, t1).
ATMO_AP_FN void atmo_aerial_between(vec3 l0, vec3 t0, vec3 l1, vec3 t1, float f, ATMO_AP_OUT(vec3) inscattered,
                                    ATMO_AP_OUT(vec3) transmittance) {
  for (int c = 0; c < 3; ++c) {
    vec2 at = atmo_aerial_segment(l0[c], t0[c], l1[c], t1[c], f);
    inscattered[c] = at.x;
    transmittance[c] = at.y;
  }
}

#ifndef ATMO_TWIN
// In-scattered light (cd/m^2) and transmittance from the eye to distance_m
// along the ray through screen_uv (0..1 over the viewport).
void atmo_aerial_perspective_sample(sampler3D inscatter_volume, sampler3D transmittance_volume, vec2 screen_uv,
                                    float distance_m, float range_m, int slices, out vec3 inscattered,
                                    out vec3 transmittance) {
  vec4 pair = atmo_aerial_slice_pair(distance_m, range_m, slices);
  vec3 l0 = vec3(0.0f);
  vec3 t0 = vec3(1.0f);
  if (pair.w < 0.5f) {
    l0 = texture(inscatter_volume, vec3(screen_uv, pair.x)).rgb;
    t0 = texture(transmittance_volume, vec3(screen_uv, pair.x)).rgb;
  }
  vec3 l1 = texture(inscatter_volume, vec3(screen_uv, pair.y)).rgb;
  vec3 t1 = texture(transmittance_volume, vec3(screen_uv, pair.y)).rgb;
  atmo_aerial_between(l0, t0, l1, t1, pair.z, inscattered, transmittance);
}

#ifndef ATMO_AERIAL_NO_UNIFORMS
uniform sampler3D atmo_aerial_inscatter;
uniform sampler3D atmo_aerial_transmittance;
uniform float atmo_aerial_range_m;
uniform int atmo_aerial_slices;
uniform vec4 atmo_viewport;
uniform float atmo_exposure;

// The two terms at this fragment: colour_out = colour * transmittance + inscattered
// (for premultiplied alpha: colour_out = colour * transmittance + inscattered * alpha).
// inscattered is already in the host's units (times atmo_exposure).
void atmo_aerial_perspective_terms(float distance_m, out vec3 inscattered, out vec3 transmittance) {
  vec2 uv = (gl_FragCoord.xy - atmo_viewport.xy) / atmo_viewport.zw;
  atmo_aerial_perspective_sample(atmo_aerial_inscatter, atmo_aerial_transmittance, uv, distance_m,
                                 atmo_aerial_range_m, atmo_aerial_slices, inscattered, transmittance);
  inscattered *= atmo_exposure;
}

vec3 atmo_apply_aerial_perspective(vec3 colour, float distance_m) {
  vec3 inscattered;
  vec3 transmittance;
  atmo_aerial_perspective_terms(distance_m, inscattered, transmittance);
  return colour * transmittance + inscattered;
}
#endif  // ATMO_AERIAL_NO_UNIFORMS
#endif  // ATMO_TWIN
#endif  // ATMO_AERIAL_PERSPECTIVE_GLSL
