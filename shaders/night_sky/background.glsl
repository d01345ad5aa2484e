// background.glsl — the faint diffuse night sky in a view direction: airglow,
// zodiacal light, integrated starlight (the Milky Way), diffuse galactic and
// extragalactic light. ONE source for two compilers, like
// atmosphere/functions.glsl: a pass #includes it, and
// plugin/core/night_sky/night_sky_twin.h compiles it as C++ over GLM (the CPU
// twin, in float like the GPU); tests/core/night_sky_twin_test.cpp checks it
// against the core's double-precision night_background(...).rgb()
// (plugin/core/night_sky/background.h, where the formulas and their sources are).
//
// Float-safe forms of the core's formulas:
// - airglow: the path through the emitting shell from the eye's radius
//   r0 = R + h uses rho^2 - r0^2 = (H - h)(2R + H + h) (H the shell's height)
//   and the two roots of the ray–sphere equation in the form without
//   cancellation (t_near t_far = -(rho^2 - r0^2)), so no ~R^2 terms are
//   subtracted (R^2 = 4e13 m^2 in float would lose ~2e6 m^2);
// - zodiacal light: the elongation from atan(|d x sun|, d·sun) (accurate at
//   0 and 180°, unlike acos), clamped to >= 2° before the powers;
// - galactic coordinates: cos b cos l and sin b are the components of the
//   direction along the galactic centre and the north galactic pole: no
//   trigonometry, nothing undefined at the poles.
//
// Units: luminance in cd/m^2, radiance linear sRGB, OUTSIDE the atmosphere
// (the caller multiplies by the view ray's transmittance). Directions: unit
// vectors. Needs ATMO_FN and IN() defined (pass_common.glsl in GLSL, the twin
// in C++). The per-frame parameters come from make_night_background
// (night_sky_twin.h).

struct NightBackground {
  mat3 icrs_from_enu;                  // rotation: ICRS = icrs_from_enu * ENU
  vec3 sun_icrs;                       // unit vector toward the Sun, ICRS
  float eye_altitude_m;                // above the planet's sphere, >= 0
  float planet_radius_m;               // the sphere (the atmosphere's bottom radius)
  float airglow_zenith_cd_m2;          // the layer at the zenith from the ground (settings.airglow_zenith_s10)
  float airglow_layer_altitude_m;      // centre of the emitting shell
  float airglow_layer_thickness_m;     // its thickness
  float zodiacal_cd_m2_per_unit;       // zodiacal_scale · (1 S10 in cd/m^2) / 1.28: per Leinert table unit
  float starlight_pole_cd_m2;          // settings.starlight_pole_s10 in cd/m^2
  float starlight_plane_excess_cd_m2;  // settings.starlight_plane_excess_s10 in cd/m^2
  float starlight_width_sin_b;
  float starlight_longitude_contrast;
  float diffuse_galactic_fraction;
  float cosmic_cd_m2;                  // settings.cosmic_s10 in cd/m^2
  vec3 airglow_rgb;                    // colours, linear sRGB, luminance 1
  vec3 zodiacal_rgb;
  vec3 starlight_rgb;                  // integrated starlight, diffuse galactic and cosmic light
};

// North ecliptic pole in ICRS (IAU 2006 obliquity at J2000, ecliptic_pole_icrs()).
const vec3 NIGHT_ECLIPTIC_POLE_ICRS = vec3(0.0f, -0.39777696911260596f, 0.9174821430652419f);
// Rows 1 and 3 of the ICRS -> galactic rotation (Hipparcos A_G', galactic_from_icrs()):
// the galactic centre (l = 0, b = 0) and the north galactic pole, in ICRS.
const vec3 NIGHT_GALACTIC_CENTER_ICRS = vec3(-0.0548755604162154f, -0.8734370902348850f, -0.4838350155487132f);
const vec3 NIGHT_GALACTIC_POLE_ICRS = vec3(-0.8676661490190047f, -0.1980763734312015f, 0.4559837761750669f);

const float NIGHT_PI = 3.14159265358979f;
const float NIGHT_DEG = 0.0174532925199433f;
const float NIGHT_SIN_2_DEG = 0.03489949670250097f;

// Length of the part t in [0, t_max] of a ray inside a sphere; b = r0 mu (r0 the
// start's radius, mu the cosine to the local vertical) and q = rho^2 - r0^2
// (rho the sphere's radius), passed in a form free of cancellation.
ATMO_FN float night_length_inside(float b, float q, float t_max) {
  float disc = b * b + q;
  if (!(disc > 0.0f)) return 0.0f;
  float s = sqrt(disc);
  float t_near;
  float t_far;
  if (b >= 0.0f) {
    t_near = -(b + s);
    t_far = -q / t_near;
  } else {
    t_far = s - b;
    t_near = -q / t_far;
  }
  return max(min(t_far, t_max) - max(t_near, 0.0f), 0.0f);
}

// airglow_slant_factor (background.h): the path through the emitting shell
// before the ray meets the ground, over the shell's thickness.
ATMO_FN float night_airglow_slant(IN(NightBackground) b, float cos_zenith) {
  float radius = max(b.planet_radius_m, 1.0f);
  float h = max(b.eye_altitude_m, 0.0f);
  float thickness = max(b.airglow_layer_thickness_m, 1.0f);
  float mu = clamp(cos_zenith, -1.0f, 1.0f);
  float r0 = radius + h;
  float bb = r0 * mu;
  // The ground (height 0): q = -h (2R + h); met only going down.
  float t_max = 1e30f;
  float q_ground = -h * (2.0f * radius + h);
  float disc_ground = bb * bb + q_ground;
  if (mu < 0.0f && disc_ground >= 0.0f) t_max = -q_ground / (sqrt(disc_ground) - bb);  // the near root
  float h_inner = b.airglow_layer_altitude_m - 0.5f * thickness;
  float h_outer = b.airglow_layer_altitude_m + 0.5f * thickness;
  float q_inner = (h_inner - h) * (2.0f * radius + h_inner + h);
  float q_outer = (h_outer - h) * (2.0f * radius + h_outer + h);
  float path = night_length_inside(bb, q_outer, t_max) - night_length_inside(bb, q_inner, t_max);
  return max(path, 0.0f) / thickness;
}

// zodiacal_s10 (background.h) times 1.28: Leinert's table units, from the
// cosine and sine of the elongation and |sin| of the ecliptic latitude.
ATMO_FN float night_zodiacal_units(float cos_e, float sin_e, float abs_sin_beta) {
  float eps = clamp(atan(max(sin_e, 1e-30f), cos_e), 2.0f * NIGHT_DEG, NIGHT_PI);
  float e = eps / (90.0f * NIGHT_DEG);
  // |sin beta| <= sin(min(eps, 90°)) (eps >= 2°): keeps impossible pairs finite, as the core does.
  float sin_beta = min(abs_sin_beta, cos_e > 0.0f ? max(sin_e, NIGHT_SIN_2_DEG) : 1.0f);
  float ecliptic = 149.85f * pow(e, -2.459f) + 171.0f;
  float w = sin_beta / (1.0635f * e);
  float g = (NIGHT_PI - eps) / (36.28f * NIGHT_DEG);
  return max(-44.76f + ecliptic * exp(-pow(max(w, 0.0f), 0.7259f)) + 67.28f * exp(-g * g), 0.0f);
}

// The components' luminances, cd/m^2: (airglow, zodiacal light, integrated
// starlight, diffuse galactic + cosmic light) — the core's
// BackgroundLuminance {airglow, zodiacal, starlight, diffuse_galactic + cosmic}.
ATMO_FN vec4 night_background_luminances(IN(NightBackground) b, IN(vec3) dir_enu) {
  vec3 d = b.icrs_from_enu * dir_enu;
  float airglow = b.airglow_zenith_cd_m2 * night_airglow_slant(b, dir_enu.z);
  float zodiacal = b.zodiacal_cd_m2_per_unit *
                   night_zodiacal_units(dot(d, b.sun_icrs), length(cross(d, b.sun_icrs)),
                                        abs(dot(d, NIGHT_ECLIPTIC_POLE_ICRS)));
  float width = max(b.starlight_width_sin_b, 1e-3f);
  float cos_b_cos_l = dot(d, NIGHT_GALACTIC_CENTER_ICRS);
  float abs_sin_b = abs(dot(d, NIGHT_GALACTIC_POLE_ICRS));
  float starlight = b.starlight_pole_cd_m2 + b.starlight_plane_excess_cd_m2 *
                                                (1.0f + b.starlight_longitude_contrast * cos_b_cos_l) *
                                                exp(-abs_sin_b / width);
  return vec4(airglow, zodiacal, starlight, b.diffuse_galactic_fraction * starlight + b.cosmic_cd_m2);
}

// night_background(...).rgb(): linear sRGB radiance, cd/m^2, outside the air.
ATMO_FN vec3 night_background_radiance(IN(NightBackground) b, IN(vec3) dir_enu) {
  vec4 l = night_background_luminances(b, dir_enu);
  return l.x * b.airglow_rgb + l.y * b.zodiacal_rgb + (l.z + l.w) * b.starlight_rgb;
}
