// preetham.glsl — the ANALYTIC sky tier: Preetham, Shirley & Smits 1999, "A
// Practical Analytic Model for Daylight" (the Perez et al. 1993 all-weather
// distribution with turbidity-dependent coefficients). Include it AFTER
// functions.glsl (it uses ATMO_FN, IN() and ATMO_PI); it is written in the same
// GLSL/C++ subset, so plugin/core/sky/preetham.h compiles it as the CPU twin.
//
// The coefficients depend only on (turbidity, sun zenith angle): the CPU
// computes them (atmo::core::preetham_coefficients, double precision) and the
// pass evaluates the distribution per pixel:
//
//   F(theta, gamma) = (1 + A exp(B / cos theta)) (1 + C exp(D gamma) + E cos^2 gamma)
//   Y = Y_z F(theta, gamma) / F(0, theta_s), and the same for x and y
//
// theta: view zenith angle, gamma: angle between view and sun, theta_s: sun
// zenith angle. Units: the paper's Y_z is in kcd/m^2; the struct carries it in
// cd/m^2 (already multiplied by 1000 on the CPU), so the result is cd/m^2.
// Output colour: Yxy -> CIE XYZ -> linear Rec.709/sRGB primaries, D65 white
// (IEC 61966-2-1 matrix), the project's radiance convention.
//
// Where the formulas break (see docs/PREETHAM.md; preetham_validity on the
// CPU says when to hand over to the LUT tier):
//  - cos theta -> 0 at the horizon: cos theta is clamped to PREETHAM_MIN_COS,
//    so B / cos theta is finite; for B < 0 the term is ~0 there anyway.
//  - below the horizon (view z < 0) the model says nothing: we return the
//    HORIZON value at the same azimuth (direction projected onto the
//    horizontal plane), a mirror of the horizon ring that is continuous at the
//    horizon; the nadir (no azimuth) gets gamma = 90 degrees.
//  - T < ~1.64: 1 + A_Y exp(B_Y) (the zenith normalisation) crosses zero; the
//    denominator is floored at PREETHAM_MIN_F0 and the result at 0, so the
//    output stays finite (but meaningless) — the validity verdict flags it.
//  - out-of-gamut chromaticities give negative Rec.709 components: clamped to 0.
#ifndef ATMO_PREETHAM_GLSL
#define ATMO_PREETHAM_GLSL

// Distribution coefficients of the Perez function, one vec3 per parameter with
// components (Y, x, y), and the zenith values (Y_z in cd/m^2, x_z, y_z).
struct PreethamCoefficients {
  vec3 A;           // horizon darkening / brightening
  vec3 B;           // luminance gradient near the horizon
  vec3 C;           // circumsolar intensity
  vec3 D;           // circumsolar width
  vec3 E;           // backscattered light
  vec3 zenith_Yxy;  // (Y_z cd/m^2, x_z, y_z)
};

const float PREETHAM_MIN_COS = 0.01f;   // ~0.57 degrees above the horizon
const float PREETHAM_MIN_F0 = 1e-4f;    // floor of the zenith normalisation F(0, theta_s)
const float PREETHAM_MAX_EXPONENT = 60.0f;

// Perez distribution for the three channels (Y, x, y) at view zenith cosine
// cos_theta (already clamped), angle to the sun gamma (radians) and its cosine.
ATMO_FN vec3 preetham_perez(IN(PreethamCoefficients) c, float cos_theta, float gamma, float cos_gamma) {
  vec3 horizon = vec3(1.0f) + c.A * exp(min(c.B / cos_theta, vec3(PREETHAM_MAX_EXPONENT)));
  vec3 sun = vec3(1.0f) + c.C * exp(c.D * gamma) + c.E * (cos_gamma * cos_gamma);
  return horizon * sun;
}

// Sky colour as (Y cd/m^2, x, y) along the ENU direction view_dir (unit), for
// the unit direction to the sun sun_dir (ENU). Never NaN/Inf for finite input.
ATMO_FN vec3 preetham_sky_Yxy(IN(PreethamCoefficients) c, IN(vec3) view_dir, IN(vec3) sun_dir) {
  // Lower hemisphere: the horizon value at the same azimuth.
  vec3 v = vec3(view_dir.x, view_dir.y, max(view_dir.z, 0.0f));
  v = v / max(length(v), 1e-6f);  // nadir: v = 0, so cos gamma = 0
  float cos_theta = max(v.z, PREETHAM_MIN_COS);
  float cos_gamma = clamp(dot(v, sun_dir), -1.0f, 1.0f);
  float gamma = acos(cos_gamma);
  float cos_theta_s = clamp(sun_dir.z, -1.0f, 1.0f);
  float theta_s = acos(cos_theta_s);

  vec3 f = preetham_perez(c, cos_theta, gamma, cos_gamma);
  // F(0, theta_s): view at the zenith, so gamma = theta_s and cos theta = 1.
  vec3 f0 = preetham_perez(c, 1.0f, theta_s, cos_theta_s);
  vec3 ratio = f / max(f0, vec3(PREETHAM_MIN_F0));
  vec3 Yxy = c.zenith_Yxy * ratio;
  return vec3(max(Yxy.x, 0.0f), clamp(Yxy.y, 0.0f, 1.0f), clamp(Yxy.z, 1e-4f, 1.0f));
}

// (Y, x, y) -> CIE XYZ; y is kept away from 0 by the caller.
ATMO_FN vec3 preetham_xyz_from_Yxy(IN(vec3) Yxy) {
  float Y = Yxy.x;
  float x = Yxy.y;
  float y = max(Yxy.z, 1e-4f);
  return vec3(x / y * Y, Y, (1.0f - x - y) / y * Y);
}

// CIE XYZ -> linear Rec.709 / sRGB primaries, D65 white (IEC 61966-2-1).
ATMO_FN vec3 preetham_rec709_from_xyz(IN(vec3) xyz) {
  return vec3(dot(vec3(3.2406f, -1.5372f, -0.4986f), xyz),
              dot(vec3(-0.9689f, 1.8758f, 0.0415f), xyz),
              dot(vec3(0.0557f, -0.2040f, 1.0570f), xyz));
}

// Sky radiance as CIE XYZ (Y = luminance, cd/m^2).
ATMO_FN vec3 preetham_sky_xyz(IN(PreethamCoefficients) c, IN(vec3) view_dir, IN(vec3) sun_dir) {
  return preetham_xyz_from_Yxy(preetham_sky_Yxy(c, view_dir, sun_dir));
}

// Sky radiance in linear Rec.709 RGB, cd/m^2 (luminance 0.2126 R + 0.7152 G +
// 0.0722 B), negative (out-of-gamut) components clamped to 0. No sun disc.
ATMO_FN vec3 preetham_sky_rgb(IN(PreethamCoefficients) c, IN(vec3) view_dir, IN(vec3) sun_dir) {
  return max(preetham_rec709_from_xyz(preetham_sky_xyz(c, view_dir, sun_dir)), vec3(0.0f));
}

#endif  // ATMO_PREETHAM_GLSL
