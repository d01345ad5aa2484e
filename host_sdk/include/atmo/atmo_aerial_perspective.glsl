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
// viewport), slice k of n at distance range * ((k + 1) / n)^2 from the eye;
// below the first slice the haze fades linearly (in sqrt(distance)) to none.
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

// Third texture coordinate of a distance, and the weight of the volume there
// (1 from the first slice on). Written in the subset the plugin's C++ twin
// compiles (float literals with f, no swizzles).
ATMO_AP_FN vec2 atmo_aerial_slice_coordinate(float distance_m, float range_m, int slices) {
  float w = sqrt(clamp(distance_m / range_m, 0.0f, 1.0f)) * float(slices);  // continuous slice index + 1
  float weight = clamp(w, 0.0f, 1.0f);
  float z = (max(w - 1.0f, 0.0f) + 0.5f) / float(slices);
  return vec2(z, weight);
}

#ifndef ATMO_TWIN
// In-scattered light (cd/m^2) and transmittance from the eye to distance_m
// along the ray through screen_uv (0..1 over the viewport).
void atmo_aerial_perspective_sample(sampler3D inscatter_volume, sampler3D transmittance_volume, vec2 screen_uv,
                                    float distance_m, float range_m, int slices, out vec3 inscattered,
                                    out vec3 transmittance) {
  vec2 slice = atmo_aerial_slice_coordinate(distance_m, range_m, slices);
  vec3 coord = vec3(screen_uv, slice.x);
  inscattered = texture(inscatter_volume, coord).rgb * slice.y;
  transmittance = mix(vec3(1.0f), texture(transmittance_volume, coord).rgb, slice.y);
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
