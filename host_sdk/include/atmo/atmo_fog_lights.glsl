// atmo_fog_lights.glsl — light from point lights in fog, for the HOST's own
// surface shaders (the runway, terrain, vehicles lit by approach lights and
// headlights in fog) and for the plugin's glow pass, which includes this file
// so that both evaluate one text. docs/FOG.md derives every term.
//
// The model (Sun, Ramamoorthi, Narasimhan & Nayar 2005, with the changes in
// docs/FOG.md): a homogeneous fog of extinction beta (1/m), single-scattering
// albedo and a Henyey-Greenstein phase function, up to an optional top.
//   - airlight (the glow): single scattering along the view ray, from the
//     paper's closed form rewritten so that no two large numbers are
//     subtracted (docs/FOG.md, "the stable form"); the special function is a
//     table (atmo_fog_airlight_table) that folds in the phase function;
//   - surfaces: the direct light dimmed by the fog, plus the light the fog
//     scattered onto the surface (the paper's G tables, one per Phong
//     exponent, atmo_fog_surface_table);
//   - multiple scattering: a diffusion (P1) term that takes over from single
//     scattering with optical thickness (docs/FOG.md, "the handover").
//
// HOST USE (GLSL 3.30+ fragment shader):
//   Each frame, after set_view: api.get_fog_lighting(view, &fog) (AtmoFogLighting).
//   If fog.light_count == 0 nothing here adds light: skip it. It works in
//   clear air as in fog (then only the lights' direct light).
//   Bind (each to its own texture unit, as the sampler type says)
//     fog.surface_table    -> sampler2D  atmo_fog_surface_table
//     fog.light_texture    -> sampler2D  atmo_fog_light_texture
//     fog.cluster_grid     -> usampler2D atmo_fog_cluster_grid
//     fog.far_field        -> sampler3D  atmo_fog_far_field
//   and set the uniforms
//     atmo_fog_cluster_from_position = mat4(fog.cluster_from_position)
//     atmo_fog_cluster_grid_size     = vec4(fog.cluster_grid_size)
//     atmo_fog_cluster_range         = vec2(fog.cluster_range)
//     atmo_fog_enu_from_world        = mat3(fog.enu_from_world)
//     atmo_fog_medium      = vec4(fog.medium)          (extinction, albedo, top above the eye, unused)
//     atmo_fog_diffusion   = vec4(fog.diffusion)       (see AtmoFogLighting)
//     atmo_fog_up          = vec3(fog.up_world)        (unit up at the eye, world axes)
//     atmo_fog_surface_table_size = vec2(fog.surface_table_size)
//   then, per fragment:
//     vec3 L = atmo_fog_lights_surface(position_rel_eye_m, normal, kd, ks, exponent);
//   position_rel_eye_m: the fragment's position minus the eye's, metres, in the
//   view's world axes (what a camera-relative renderer has); normal unit, same
//   axes; kd = albedo / pi and ks the Phong weight (the BRDF is
//   kd + ks * cos^n(angle to the mirror direction), as in the paper). L is the
//   radiance the surface sends towards the eye (cd/m^2, linear RGB) BEFORE the
//   fog between surface and eye: ATMO_PASS_LIGHT_GLOWS applies that (and adds
//   the glows), as ATMO_PASS_AERIAL_PERSPECTIVE does for the air. Multiply by
//   your exposure if you render in scaled units.
//   The cost per fragment is bounded: at most 12 lights (those of its cluster
//   that add the most), the rest of the lights through the cluster's far
//   field (docs/FOG.md "Surfaces at scale").
//
// Everything above the "#ifndef ATMO_TWIN" line is written in the subset the
// plugin's C++ twin compiles (float literals with f, no swizzles), so the CPU
// evaluates the same text as the GPU.
#ifndef ATMO_FOG_LIGHTS_GLSL
#define ATMO_FOG_LIGHTS_GLSL

#ifndef ATMO_FOG_FN
#define ATMO_FOG_FN
#endif
#ifndef ATMO_FOG_TABLE
#define ATMO_FOG_TABLE sampler2D
#define ATMO_FOG_IN(T) T
float atmo_fog_table_fetch(sampler2D table, vec2 uv) { return texture(table, uv).r; }
#endif

const float ATMO_FOG_PI = 3.14159265358979f;
// "No surface on this ray" / "no fog top": distances and heights beyond this.
const float ATMO_FOG_FAR = 1.0e30f;
// Phong exponents with a surface table layer: 2^0 .. 2^8 (layer 0 is the Lambertian cosine).
const float ATMO_FOG_SURFACE_LAYERS = 9.0f;

// Texture coordinate of sample position x in [0, 1] on a grid of n samples
// that includes both ends (texel i holds x = i / (n - 1)).
ATMO_FOG_FN float atmo_fog_grid(float x, float n) { return (clamp(x, 0.0f, 1.0f) * (n - 1.0f) + 0.5f) / n; }

// Table coordinate of an optical thickness or of u in [0, inf): sqrt(u / (1 + u)),
// dense near 0 where the functions have a u log u term, and reaching u = inf at 1.
ATMO_FOG_FN float atmo_fog_thickness_coordinate(float u) { return sqrt(u / (1.0f + u)); }

// The shape of Ghat near v = pi/2 (y = pi/2 - v small), where it changes
// from q y (y >> u) to q y^2 / u (y << u) within a sliver no grid resolves:
// Ghat -> q(pi) y K(u / y), K(a) = 1 - a e^a E_1(a) (E_1 from Abramowitz &
// Stegun 5.1.53 and 5.1.56). The table holds Ghat / (y K(u / y)), smooth
// everywhere; only this function's smoothness matters, not its accuracy, as
// the table is built with the same function.
ATMO_FOG_FN float atmo_fog_ghat_scale(float u, float y) {
  float a = min(u / max(y, 1.0e-30f), 1.0e30f);  // inf / inf would be NaN
  float k;
  if (a < 1.0f) {
    float e1_plus_log = -0.57721566f + a * (0.99999193f + a * (-0.24991055f + a * (0.05519968f +
                        a * (-0.00976004f + a * 0.00107857f))));
    k = 1.0f - a * exp(a) * (e1_plus_log - log(max(a, 1.0e-30f)));
  } else {
    k = (0.995924f * a + 1.430913f) / (a * a + 3.330657f * a + 1.681534f);
  }
  return y * k;
}

// The phase-weighted special function of the stable form,
//   Ghat(u, v) = integral_v^{pi/2} 4 pi p(2 xi) exp(-u (tan xi - tan v)) d xi,
// from the table, which holds Ghat / atmo_fog_ghat_scale on the grid
// (thickness coordinate of u) x (v / (pi/2)). Ghat(0, v) = pi/2 - v for
// isotropic scattering.
ATMO_FOG_FN float atmo_fog_ghat(ATMO_FOG_IN(ATMO_FOG_TABLE) table, float size, float u, float v) {
  float x = atmo_fog_thickness_coordinate(u);
  float y = v * (2.0f / ATMO_FOG_PI);
  return atmo_fog_table_fetch(table, vec2(atmo_fog_grid(x, size), atmo_fog_grid(y, size))) *
         atmo_fog_ghat_scale(u, max(0.5f * ATMO_FOG_PI - v, 0.0f));
}

// Fraction of the straight path between heights z0 and z1 (metres, any
// reference) that lies below the fog top `top` (same reference): the fog's
// optical thickness along the path is extinction * length * this.
ATMO_FOG_FN float atmo_fog_inside_fraction(float z0, float z1, float top) {
  float lo = min(z0, z1);
  float hi = max(z0, z1);
  if (hi - lo < 1.0e-3f) return lo < top ? 1.0f : 0.0f;
  return clamp((top - lo) / (hi - lo), 0.0f, 1.0f);
}

// A cone light's relative intensity towards unit direction `dir` (from the
// light); 1 for an omnidirectional light (cos_outer < -1.5). lobes 2: the
// cone shines both ways along its axis (ATMO_LIGHT_BIDIRECTIONAL).
ATMO_FOG_FN float atmo_fog_cone(vec3 axis, float cos_inner, float cos_outer, float lobes, vec3 dir) {
  if (cos_outer < -1.5f) return 1.0f;
  float c = dot(axis, dir);
  return smoothstep(cos_outer, cos_inner, lobes > 1.5f ? abs(c) : c);
}

// Single-scattered light (airlight) per unit intensity arriving at the eye
// along a view ray, from a point light `distance` metres away at cos_gamma to
// the ray, the ray ending on a surface at d_vp metres (ATMO_FOG_FAR: none).
// beta: extinction (1/m); multiply by albedo and the intensity (cd) for cd/m^2.
//   La = beta / (2 pi h) [exp(-beta D) Ghat(beta h, gamma/2)
//                         - exp(-beta (d_vp + d_sp)) Ghat(beta h, v1)]
// with h = D sin(gamma) the light's distance from the ray's line, d_sp the
// light's distance from the surface point and v1 = pi/4 + atan2(d_vp - D cos(gamma), h) / 2.
// Both terms are positive and well scaled, whatever the angle (docs/FOG.md).
// min_sin: floor of sin(gamma), 0.2836 of a pixel's angle: then the pixel
// on the light gets the mean of the 1/gamma core over the square pixel
// (tests/fog_reference/fog_airlight_accuracy_test.cpp).
ATMO_FOG_FN float atmo_fog_airlight(ATMO_FOG_IN(ATMO_FOG_TABLE) table, float size, float beta, float distance,
                                    float cos_gamma, float d_vp, float min_sin) {
  if (d_vp <= 0.0f) return 0.0f;
  float cg = clamp(cos_gamma, -1.0f, 1.0f);
  float sg = max(sqrt(max(1.0f - cg * cg, 0.0f)), min_sin);
  float gamma = atan(sg, cg);
  float h = max(distance * sg, 1.0e-4f);
  float u = beta * h;
  float near_term = exp(-beta * distance) * atmo_fog_ghat(table, size, u, 0.5f * gamma);
  float along = d_vp - distance * cg;
  float d_sp = sqrt(along * along + h * h);
  float v1 = 0.25f * ATMO_FOG_PI + 0.5f * atan(along, h);
  float far_term = d_vp >= ATMO_FOG_FAR ? 0.0f : exp(-beta * (d_vp + d_sp)) * atmo_fog_ghat(table, size, u, v1);
  return beta / (2.0f * ATMO_FOG_PI * h) * max(near_term - far_term, 0.0f);
}

// Steps of a cone light's glow integral (atmo_fog_glow).
const float ATMO_FOG_CONE_STEPS = 8.0f;

// One light's glow along the unit view ray `dir` from the eye, per unit
// intensity and albedo (as atmo_fog_airlight). to_light: the light minus the
// eye, m; axis, cos_inner, cos_outer, lobes: its cone (atmo_fog_cone; cos_outer < -1.5: omni).
// Seen from the light, the ray's points t = t0 + h tan(theta) (t0 the closest
// approach) carry equal weight per d(theta) under the 1/d^2 law, and the
// stable form's terms at theta are exp(-beta (t0 + h tan v)) Ghat(beta h, v),
// v = pi/4 + theta/2. A cone light's integral is therefore split into
// ATMO_FOG_CONE_STEPS equal steps of theta from the eye to d_vp, each the
// difference of the terms at its ends (exact) times the cone's profile at
// its middle (the approximation; docs/FOG.md measures it). The steps
// telescope: with profile 1 they sum to atmo_fog_airlight.
ATMO_FOG_FN float atmo_fog_glow(ATMO_FOG_IN(ATMO_FOG_TABLE) table, float size, float beta, vec3 to_light, vec3 dir,
                                vec3 axis, float cos_inner, float cos_outer, float lobes, float d_vp,
                                float min_sin) {
  float distance = length(to_light);
  float cos_gamma = dot(dir, to_light) / max(distance, 1.0e-3f);
  if (cos_outer < -1.5f) return atmo_fog_airlight(table, size, beta, distance, cos_gamma, d_vp, min_sin);
  if (d_vp <= 0.0f) return 0.0f;
  float cg = clamp(cos_gamma, -1.0f, 1.0f);
  float sg = max(sqrt(max(1.0f - cg * cg, 0.0f)), min_sin);
  float h = max(distance * sg, 1.0e-4f);
  float t0 = distance * cg;
  float u = beta * h;
  // Unit vector from the ray's closest point to the light (any perpendicular when the light is on the ray).
  vec3 across = to_light - dir * t0;
  vec3 n = length(across) > 1.0e-6f * distance ? normalize(across) : normalize(cross(dir, vec3(0.577f, 0.577f, 0.577f)));
  float theta_eye = atan(-t0, h);
  float theta_end = d_vp >= ATMO_FOG_FAR ? 0.5f * ATMO_FOG_PI : atan(d_vp - t0, h);
  float step = (theta_end - theta_eye) / ATMO_FOG_CONE_STEPS;
  float previous = exp(-beta * distance) * atmo_fog_ghat(table, size, u, 0.5f * atan(sg, cg));
  float sum = 0.0f;
  for (int k = 1; k <= int(ATMO_FOG_CONE_STEPS); ++k) {
    float theta = theta_eye + float(k) * step;
    float v = 0.25f * ATMO_FOG_PI + 0.5f * theta;
    float term = theta >= 0.5f * ATMO_FOG_PI - 1.0e-5f
                     ? 0.0f
                     : exp(-beta * max(t0 + h * tan(v), 0.0f)) * atmo_fog_ghat(table, size, u, v);
    float middle = theta - 0.5f * step;
    vec3 from_light = dir * sin(middle) - n * cos(middle);
    sum += atmo_fog_cone(axis, cos_inner, cos_outer, lobes, from_light) * max(previous - term, 0.0f);
    previous = term;
  }
  return beta / (2.0f * ATMO_FOG_PI * h) * sum;
}

// The surface table's G_n(T, theta) (the paper's eq. 16 with the phase
// function folded in; n = 1 is the Lambertian G_0): rows are layers of
// exponent 2^k, k = 0..8, each `size.y` rows of theta in [0, pi] by `size.x`
// columns of the thickness coordinate of T (the last column holds T = 100);
// texels hold e^T G_n, which varies slowly (5.9 at T = 2, 3.4 at T = 100 for
// n = 1, theta = 0, g = 0.85).
// Between exponents the layers are interpolated in log2(n). Returns e^T G_n.
ATMO_FOG_FN float atmo_fog_surface_g(ATMO_FOG_IN(ATMO_FOG_TABLE) table, vec2 size, float thickness, float theta,
                                     float exponent) {
  float x = atmo_fog_grid(atmo_fog_thickness_coordinate(thickness), size.x);
  float k = clamp(log2(max(exponent, 1.0f)), 0.0f, ATMO_FOG_SURFACE_LAYERS - 1.0f);
  float k0 = min(floor(k), ATMO_FOG_SURFACE_LAYERS - 2.0f);
  float row = clamp(theta / ATMO_FOG_PI, 0.0f, 1.0f) * (size.y - 1.0f) + 0.5f;  // texel row inside a layer
  float rows = size.y * ATMO_FOG_SURFACE_LAYERS;
  float g0 = atmo_fog_table_fetch(table, vec2(x, (k0 * size.y + row) / rows));
  float g1 = atmo_fog_table_fetch(table, vec2(x, ((k0 + 1.0f) * size.y + row) / rows));
  return mix(g0, g1, k - k0);
}

// Diffusion (P1) light of a point light, per unit intensity, at `distance`
// metres: x = fluence (per sr-weighted cd: cd/m^2 * sr), y = net flux (lux per
// cd, away from the light). diffusion = (sigma_tr, mu, rate, cap):
// sigma_tr = beta (1 - albedo g) the transport coefficient, mu the decay
// (absorption and escape through the top), rate the handover: with
// t = min(thickness, cap) the fluence is scaled by 1 - exp(-rate t) and the
// flux by (1 - exp(-0.4 rate t))^2, ~0 where single scattering holds. The
// flux hands over later: near the light the P1 flux is mostly the
// unscattered beam's, which only the glow shows, and its cosine lobe would
// spread the narrow forward lobe of the scattered light over wide angles
// (docs/measurements/fog_multiple_scattering.md: the form and the rate
// fitted to the Monte Carlo). cap is the layer's vertical optical thickness
// (a photon in a thin layer escapes before it scatters much), 0: multiple
// scattering off.
// thickness: the fog's optical thickness between the light and the point.
// on_surface: the flux for a surface's irradiance hands over with the
// fluence (a surface facing the light needs it: 0.97-0.75 of the Monte
// Carlo's irradiance at T 1-8 with it, 0.80-0.58 with the view's lag).
ATMO_FOG_FN vec2 atmo_fog_diffusion_light(vec4 diffusion, float distance, float thickness, bool on_surface) {
  float r = max(distance, 0.5f);
  float t = min(thickness, diffusion.w);
  float handover_fluence = 1.0f - exp(-diffusion.z * t);
  float handover_flux = on_surface ? sqrt(handover_fluence) : 1.0f - exp(-0.4f * diffusion.z * t);
  float e = exp(-diffusion.y * r);
  return vec2(3.0f * diffusion.x * e / r * handover_fluence,
              (1.0f + diffusion.y * r) * e / (r * r) * (handover_flux * handover_flux));
}

// The fog pass (shaders/fog_medium.frag), per view ray. Length, metres, of
// the part of [0, d] along a ray from the eye that lies below the fog top:
// dir_z the ray direction's up component, top the top's height above the eye
// (ATMO_FOG_FAR: no top). The eye in the fog: up to where the ray leaves it;
// above it: from where the ray enters.
ATMO_FOG_FN float atmo_fog_ray_length(float d, float dir_z, float top) {
  if (top >= ATMO_FOG_FAR) return d;
  if (top > 0.0f) return dir_z > 0.0f ? min(d, top / dir_z) : d;
  return dir_z < 0.0f ? max(d - top / dir_z, 0.0f) : 0.0f;
}

// Transmittance of `length` metres of fog of extinction beta (1/m); lengths
// beyond 1e6 m (an open-sky ray, ATMO_FOG_FAR) count as 1e6 m.
ATMO_FOG_FN float atmo_fog_transmittance(float beta, float length) { return exp(-beta * min(length, 1.0e6f)); }

// Radiance (cd/m^2 per channel) of the lights' diffusion field seen along the
// unit direction dir: (fluence + 3 flux . dir) / 4 pi, floored at 0 (the P1
// radiance). fluence: per channel, summed over the lights (intensity times
// atmo_fog_diffusion_light's x); flux: column c is channel c's net flux
// towards the lights (intensity times y times the unit vector eye -> light).
ATMO_FOG_FN vec3 atmo_fog_diffusion_radiance(vec3 fluence, ATMO_FOG_IN(mat3) flux, vec3 dir) {
  return max((fluence + 3.0f * (transpose(flux) * dir)) / (4.0f * ATMO_FOG_PI), vec3(0.0f));
}

// The fog's own light along a view ray, cd/m^2: (1 - transmittance) times the
// isotropic ambient (cd/m^2) plus the diffusion radiance.
ATMO_FOG_FN vec3 atmo_fog_medium_light(float transmittance, vec3 ambient, vec3 fluence, ATMO_FOG_IN(mat3) flux,
                                       vec3 dir) {
  return (1.0f - transmittance) * (ambient + atmo_fog_diffusion_radiance(fluence, flux, dir));
}

// Radiance per unit intensity that a surface at distance d_sp from a light
// sends out through the light's direct and single-scattered light, for BRDF
// kd + ks cos^n: x = the kd part, y = the ks part. thickness = the fog's
// optical thickness light -> surface, cos_s = cos of the angle normal-light,
// cos_r = cos of the angle mirror direction-light.
ATMO_FOG_FN vec2 atmo_fog_surface_terms_single(ATMO_FOG_IN(ATMO_FOG_TABLE) table, vec2 size, float beta_path,
                                               float albedo, float d_sp, float thickness, float cos_s, float cos_r,
                                               float exponent) {
  float d = max(d_sp, 1.0e-3f);
  float direct = exp(-thickness) / (d * d);
  float diffuse = direct * max(cos_s, 0.0f);
  float specular = direct * pow(max(cos_r, 0.0f), exponent);
  if (beta_path > 0.0f) {  // clear air: no scattered light (and no table fetches)
    float scattered = albedo * beta_path / (2.0f * ATMO_FOG_PI * d) * exp(-thickness);
    float theta_s = acos(clamp(cos_s, -1.0f, 1.0f));
    float theta_r = acos(clamp(cos_r, -1.0f, 1.0f));
    diffuse += scattered * atmo_fog_surface_g(table, size, thickness, theta_s, 1.0f);
    specular += scattered * atmo_fog_surface_g(table, size, thickness, theta_r, exponent);
  }
  return vec2(diffuse, specular);
}

// The same with the light's diffusion (multiple-scattering) term added: the whole light of one light.
ATMO_FOG_FN vec2 atmo_fog_surface_terms(ATMO_FOG_IN(ATMO_FOG_TABLE) table, vec2 size, float beta_path, float albedo,
                                        vec4 diffusion, float d_sp, float thickness, float cos_s, float cos_r,
                                        float exponent) {
  vec2 single = atmo_fog_surface_terms_single(table, size, beta_path, albedo, d_sp, thickness, cos_s, cos_r,
                                              exponent);
  vec2 p1 = atmo_fog_diffusion_light(diffusion, max(d_sp, 1.0e-3f), thickness, true);
  return single + vec2(max(0.25f * p1.x + 0.5f * p1.y * cos_s, 0.0f),
                       max(p1.x + 3.0f * p1.y * cos_r, 0.0f) / (2.0f * (exponent + 1.0f)));
}

// The cluster (screen tile x slice of distance) a point falls in, from its
// clip position (clip_from_rel times the point) and its distance: (tile x,
// tile y, slice), and the fractional slice in w. grid = (tiles x, tiles y,
// slices, 0); range = (near m, log(far / near)).
ATMO_FOG_FN vec4 atmo_fog_cluster_of(vec4 clip, float distance, vec4 grid, vec2 range) {
  vec2 ndc = clip.w > 1.0e-6f ? clamp(vec2(clip.x, clip.y) / clip.w, -1.0f, 1.0f) : vec2(0.0f, 0.0f);
  float k = clamp(log(max(distance, range.x) / range.x) / range.y * grid.z, 0.0f, grid.z - 1.0e-3f);
  float tx = min(floor((ndc.x * 0.5f + 0.5f) * grid.x), grid.x - 1.0f);
  float ty = min(floor((ndc.y * 0.5f + 0.5f) * grid.y), grid.y - 1.0f);
  return vec4(tx, ty, floor(k), k);
}

#ifndef ATMO_TWIN
// The summed glows (cd/m^2 per channel, intensities times the albedo) of one
// screen tile's list along the unit ENU direction dir up to d_vp metres,
// sin gamma floored at min_sin: the list's entries index the glows texture
// (4 RGBA32F texels a glow, 256 a row: position relative to the eye (ENU m)
// and extinction; intensity x albedo and cos_inner; cone axis and cos_outer;
// lobes). The plugin's glow pass and atmo_fog_translucent share it.
vec3 atmo_fog_tile_glows(sampler2D table, float table_size, usampler2D lists, sampler2D glows, uint first,
                         uint count, vec3 dir, float d_vp, float min_sin) {
  vec3 sum = vec3(0.0);
  for (uint j = 0u; j < count; ++j) {
    uint entry = first + j;
    int i = int(texelFetch(lists, ivec2(int(entry % 4096u), int(entry / 4096u)), 0).r);
    ivec2 at = ivec2(4 * (i % 256), i / 256);
    vec4 t0 = texelFetch(glows, at, 0);
    vec4 t1 = texelFetch(glows, at + ivec2(1, 0), 0);
    vec4 t2 = texelFetch(glows, at + ivec2(2, 0), 0);
    vec4 t3 = texelFetch(glows, at + ivec2(3, 0), 0);
    sum += t1.rgb * atmo_fog_glow(table, table_size, t0.w, t0.xyz, dir, t2.xyz, t1.w, t2.w, t3.x, d_vp, min_sin);
  }
  return sum;
}

#ifndef ATMO_FOG_NO_UNIFORMS
uniform sampler2D atmo_fog_surface_table;
// The clusters' lights, each cluster's together: 3 texels a light, 1024 lights a row (see below).
uniform sampler2D atmo_fog_light_texture;
uniform usampler2D atmo_fog_cluster_grid;  // RG32UI, per cluster: (its first light, its lights)
uniform sampler3D atmo_fog_far_field;      // RGBA32F, 6 stacks of slices: faces +E, -E, +N, -N, +U, -U (lux)
uniform mat3 atmo_fog_enu_from_world;      // the eye's ENU axes from the view's world axes
uniform mat4 atmo_fog_cluster_from_position;  // clip from the position relative to the eye (world axes)
uniform vec4 atmo_fog_cluster_grid_size;   // tiles across, tiles up, slices, 0
uniform vec2 atmo_fog_cluster_range;       // near m, log(far / near)
uniform vec4 atmo_fog_medium;              // extinction 1/m, albedo, top height above the eye m, unused
uniform vec4 atmo_fog_diffusion;           // sigma_tr 1/m, mu 1/m, handover rate, thickness cap (0: off)
uniform vec3 atmo_fog_up;                  // unit up at the eye, world axes
uniform vec2 atmo_fog_surface_table_size;

vec4 atmo_fog_light_texel(uint light, int k) {
  return texelFetch(atmo_fog_light_texture, ivec2(3 * int(light % 1024u) + k, int(light / 1024u)), 0);
}

// The light the plugin's lights (set_lights) send towards the eye from a
// surface point, cd/m^2, before the fog between surface and eye: the lights
// of the point's cluster one by one (at most 12), and the cluster's far field
// (the other lights that reach it, and every light's diffusion in fog)
// filtered between cluster centres, on the kd part.
vec3 atmo_fog_lights_surface(vec3 position_rel_eye_m, vec3 normal, vec3 kd, vec3 ks, float exponent) {
  vec3 sum = vec3(0.0);
  vec3 to_eye = normalize(-position_rel_eye_m);
  vec3 mirror = reflect(-to_eye, normal);
  float z_point = dot(position_rel_eye_m, atmo_fog_up);
  vec4 clip = atmo_fog_cluster_from_position * vec4(position_rel_eye_m, 1.0);
  vec4 cell = atmo_fog_cluster_of(clip, length(position_rel_eye_m), atmo_fog_cluster_grid_size,
                                  atmo_fog_cluster_range);
  uvec2 list = texelFetch(atmo_fog_cluster_grid,
                          ivec2(cell.x, cell.z * atmo_fog_cluster_grid_size.y + cell.y), 0).xy;
  for (uint j = 0u; j < list.y; ++j) {
    uint i = list.x + j;
    vec4 t0 = atmo_fog_light_texel(i, 0);  // position rel eye, range m
    vec3 to_light = t0.xyz - position_rel_eye_m;
    float d = length(to_light);
    if (d > t0.w) continue;
    vec4 t1 = atmo_fog_light_texel(i, 1);  // intensity * colour (cd), cos_inner
    vec4 t2 = atmo_fog_light_texel(i, 2);  // cone axis x (1 + extent m), cos_outer (+ 4: both ways)
    vec3 l = to_light / max(d, 1.0e-3);
    float extent = length(t2.xyz) - 1.0;
    bool both_ways = t2.w > 2.5;
    float cone = atmo_fog_cone(t2.xyz / (1.0 + extent), t1.w, both_ways ? t2.w - 4.0 : t2.w, both_ways ? 2.0 : 1.0,
                               -l);
    if (cone <= 0.0) continue;
    // A merged light stands for lights spread about it: no nearer than their extent.
    d = max(d, extent);
    float beta = atmo_fog_medium.x * atmo_fog_inside_fraction(z_point, dot(t0.xyz, atmo_fog_up), atmo_fog_medium.z);
    vec2 terms = atmo_fog_surface_terms_single(atmo_fog_surface_table, atmo_fog_surface_table_size, beta,
                                               atmo_fog_medium.y, d, beta * d, dot(normal, l), dot(mirror, l),
                                               exponent);
    sum += t1.rgb * cone * (kd * terms.x + ks * terms.y);
  }
  // The far field, an ambient cube in the eye's ENU axes: E(n) = sum n_i^2 E(face of n_i's sign), linear
  // between the cluster centres, along the slices and across the tiles (the texels sit at the tiles'
  // centres: a field held per cluster shows no tile's edge).
  vec3 n = atmo_fog_enu_from_world * normal;
  vec2 uv = clip.w > 1.0e-6 ? clamp(clip.xy / clip.w, -1.0, 1.0) * 0.5 + 0.5
                            : (vec2(cell.x, cell.y) + 0.5) / atmo_fog_cluster_grid_size.xy;
  float slices = atmo_fog_cluster_grid_size.z;
  float k = clamp(cell.w, 0.5, slices - 0.5);
  vec3 face = vec3(n.x < 0.0 ? 1.0 : 0.0, n.y < 0.0 ? 3.0 : 2.0, n.z < 0.0 ? 5.0 : 4.0);
  vec3 e = n.x * n.x * texture(atmo_fog_far_field, vec3(uv, (k + face.x * slices) / (6.0 * slices))).rgb +
           n.y * n.y * texture(atmo_fog_far_field, vec3(uv, (k + face.y * slices) / (6.0 * slices))).rgb +
           n.z * n.z * texture(atmo_fog_far_field, vec3(uv, (k + face.z * slices) / (6.0 * slices))).rgb;
  sum += kd * e;
  return sum;
}

// TRANSLUCENT SURFACES (glass, water, smoke, a canopy): the plugin's fog and
// glows are drawn over the OPAQUE depth, so a host draws its translucent
// surfaces after ATMO_PASS_LIGHT_GLOWS (and ATMO_PASS_LIGHT_POINTS), each
// with the fog between it and the eye applied in its own shader:
//     vec4 f = atmo_fog_translucent(position_rel_eye_m);
//     colour.rgb = colour.rgb * f.a + f.rgb;   // then blend "over" as usual
// (its own light, lit or not, times the fog's transmittance f.a, plus the fog's
// light in front of it f.rgb: the fog's ambient and diffusion light and the
// lights' glows, cd/m^2). Behind it the plugin's fog and glows are already in
// the framebuffer and the blend weighs them. Bind, besides the fields above,
//     fog.airlight_table -> sampler2D  atmo_fog_airlight_table
//     fog.glow_tiles     -> usampler2D atmo_fog_glow_tiles
//     fog.glow_lists     -> usampler2D atmo_fog_glow_lists
//     fog.glow_entries   -> sampler2D  atmo_fog_glow_entries
//   and set atmo_fog_glow_grid = vec4(fog.glow_grid), atmo_fog_ambient =
//   vec3(fog.ambient), atmo_fog_fluence = vec3(fog.fluence), atmo_fog_flux =
//   mat3(fog.flux). Without fog it returns (0, 0, 0, 1). A glow's core in front
//   of a translucent surface is drawn by the plugin before it, so the blend
//   dims it (docs/FOG.md "Translucent surfaces").
uniform sampler2D atmo_fog_airlight_table;
uniform usampler2D atmo_fog_glow_tiles;
uniform usampler2D atmo_fog_glow_lists;
uniform sampler2D atmo_fog_glow_entries;
uniform vec4 atmo_fog_glow_grid;           // tiles across, up, airlight table size, the pixel's floor of sin gamma
uniform vec3 atmo_fog_ambient;             // cd/m^2
uniform vec3 atmo_fog_fluence;
uniform mat3 atmo_fog_flux;

vec4 atmo_fog_translucent(vec3 position_rel_eye_m) {
  float d = length(position_rel_eye_m);
  if (!(d > 0.0) || atmo_fog_medium.x <= 0.0) return vec4(0.0, 0.0, 0.0, 1.0);
  vec3 dir = atmo_fog_enu_from_world * (position_rel_eye_m / d);
  float transmittance = atmo_fog_transmittance(atmo_fog_medium.x, atmo_fog_ray_length(d, dir.z, atmo_fog_medium.z));
  vec3 light = atmo_fog_medium_light(transmittance, atmo_fog_ambient, atmo_fog_fluence, atmo_fog_flux, dir);
  // The glows of the surface's screen tile, in-scattered up to the surface (or to where the ray leaves the fog).
  vec4 clip = atmo_fog_cluster_from_position * vec4(position_rel_eye_m, 1.0);
  if (atmo_fog_glow_grid.x > 0.0 && clip.w > 1.0e-6) {
    vec2 ndc = clamp(clip.xy / clip.w, -1.0, 1.0);
    ivec2 tile = ivec2(min(floor((ndc * 0.5 + 0.5) * atmo_fog_glow_grid.xy), atmo_fog_glow_grid.xy - 1.0));
    uvec2 list = texelFetch(atmo_fog_glow_tiles, tile, 0).xy;
    float top = atmo_fog_medium.z;
    float d_vp = top < ATMO_FOG_FAR && top > 0.0 && dir.z > 0.0 ? min(d, top / dir.z) : d;
    light += atmo_fog_tile_glows(atmo_fog_airlight_table, atmo_fog_glow_grid.z, atmo_fog_glow_lists,
                                 atmo_fog_glow_entries, list.x, list.y, dir, d_vp, atmo_fog_glow_grid.w);
  }
  return vec4(light, transmittance);
}
#endif  // ATMO_FOG_NO_UNIFORMS
#endif  // ATMO_TWIN

#endif  // ATMO_FOG_LIGHTS_GLSL
