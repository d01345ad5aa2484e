// moon_disc.glsl — the radiance of the Moon's disc in a view direction: ONE
// source for two compilers, like atmosphere/functions.glsl. A pass #includes
// it; plugin/core/night_sky/night_sky_twin.h compiles it as C++ over GLM (the
// CPU twin, in float like the GPU), and tests/core/night_sky_twin_test.cpp
// checks it against the core's double-precision moon_disc_normal +
// moon_disc_radiance_rgb (plugin/core/night_sky/moon_photometry.h).
//
// Model (docs/NIGHT_SKY.md): orthographic disc coordinates (the point seen in
// direction `dir` has the outward normal n = xy + sqrt(1 - |xy|^2) to_observer,
// xy = the part of `dir` across the Moon's direction over sin(angular radius));
// Hapke / Lommel–Seeliger radiance
//   L = sun_radiance · mu0 / (mu0 + mu) [mu0 > 0] + earthshine_radiance,
// mu0 = n·to_sun, mu = n·to_observer, with no limb darkening. The prefactors
// are per frame (make_moon_disc, night_sky_twin.h): sun_radiance = 2/(3 pi)
// C_s E_s B(phi) S(phi) colour, earthshine_radiance = 2/(3 pi) C_e E_e B(0)
// S(0) / 2 colour. The phase and the orientation of the terminator both follow
// from `to_sun`: the bright limb faces the Sun.
//
// Antialiasing: the limb gets a coverage ramp one pixel wide centred on it
// (0.5 on the geometric limb), the pixel's angular size given by the caller.
// The outer half-pixel band of the surface (where mu -> 0 and the radiance
// changes fastest) is drawn stretched over the ramp with its light kept (see
// below), so the disc integrates to the Moon's illuminance at any pixel size
// and phase (tests/core/night_sky_twin_test.cpp). Inside the ramp it is the
// point-sampled disc of the core. The ramp is never wider than the disc's
// radius, so a Moon smaller than a pixel does not spread its light.
// Robust: 0 on the far hemisphere, finite at the centre, on the limb, for a
// Moon of radius 0 and for pixel_angle_rad = 0 (a hard edge).
//
// Units: radiance in cd/m^2, linear sRGB, OUTSIDE the atmosphere (the caller
// multiplies by the view ray's transmittance). Directions: unit vectors, ENU.
// Needs ATMO_FN and IN() defined (pass_common.glsl in GLSL, the twin in C++).

struct MoonDisc {
  vec3 direction;             // unit ENU direction of the Moon's centre (apparent)
  float angular_radius_rad;   // apparent angular radius (semi-diameter), used clamped to [0, 1.5]
  vec3 to_sun;                // unit vector from the Moon toward the Sun, ENU
  vec3 sun_radiance;          // cd/m^2 RGB: 2/(3 pi) C_s E_s B(phi) S(phi) colour
  vec3 earthshine_radiance;   // cd/m^2 RGB: 2/(3 pi) C_e E_e B(0) S(0) / 2 colour
};

// Fraction of a pixel covered by the disc, for a pixel centre `edge_rad`
// inside the limb (negative outside): a linear ramp `width_rad` wide centred
// on the limb; a step when width_rad <= 0.
ATMO_FN float moon_disc_coverage(float edge_rad, float width_rad) {
  if (width_rad > 0.0f) return clamp(0.5f + edge_rad / width_rad, 0.0f, 1.0f);
  return edge_rad >= 0.0f ? 1.0f : 0.0f;
}

// sin(x) by its Taylor series to x^9: relative error below 1e-10 for |x| <=
// 0.5 rad, 3e-6 at 1.5 (the Moon's radius is 0.0045; it is clamped to 1.5).
// GPU sin() can have an ABSOLUTE error of ~1e-6 after its range reduction,
// 2e-4 of sin(0.0045).
ATMO_FN float moon_small_sin(float x) {
  float x2 = x * x;
  return x * (1.0f - x2 / 6.0f * (1.0f - x2 / 20.0f * (1.0f - x2 / 42.0f * (1.0f - x2 / 72.0f))));
}

ATMO_FN vec3 moon_disc_radiance(IN(MoonDisc) m, IN(vec3) dir, float pixel_angle_rad) {
  float cos_t = dot(dir, m.direction);
  if (!(cos_t > 0.0f)) return vec3(0.0f);  // the far hemisphere (and NaN)
  // Across the Moon's direction: |lateral| = sin(theta), theta the angle from
  // the centre. Not dir - cos_t direction: its components (~1) round to ~6e-8,
  // 1.3e-5 of a disc 4.5e-3 rad wide, which near the limb and the terminator
  // moves the radiance by 1e-3. dir - direction is exact near the Moon
  // (Sterbenz), and the small projection adds rounding relative to itself only.
  vec3 delta = dir - m.direction;
  vec3 lateral = delta - dot(delta, m.direction) * m.direction;
  float sin_t = length(lateral);
  float radius = clamp(m.angular_radius_rad, 0.0f, 1.5f);
  float sin_radius = moon_small_sin(radius);
  float cos_radius = sqrt(max(1.0f - sin_radius * sin_radius, 0.0f));
  // sin(radius - theta): the angle inside the limb (negative outside) to
  // (radius - theta)^3 / 6, accurate to ~1e-9 rad (no atan, no GPU sin).
  float edge = sin_radius * cos_t - cos_radius * sin_t;
  float width = min(max(pixel_angle_rad, 0.0f), radius);
  float coverage = moon_disc_coverage(edge, width);
  if (coverage <= 0.0f) return vec3(0.0f);
  // Disc coordinates (times the disc axes): lateral / sin(radius).
  vec3 xy = lateral / max(sin_radius, 1e-30f);
  float weight = 1.0f;
  if (coverage < 1.0f) {
    // The ramp (theta > radius - width/2 > 0): the pixel shows the surface at
    // theta_s = radius - width/2 coverage^2, weighted by coverage
    // sin(theta_s) / sin(theta). d(theta_s) = coverage d(theta), so the band
    // [radius - width/2, radius] of the surface is spread over the ramp with
    // its light kept: the disc still integrates to the Moon's illuminance, a
    // crescent thinner than a pixel included.
    float theta_s = radius - 0.5f * width * coverage * coverage;
    float sin_s = moon_small_sin(theta_s);
    float inv_sin_t = 1.0f / max(sin_t, 1e-30f);
    xy = lateral * (inv_sin_t * sin_s / max(sin_radius, 1e-30f));
    weight = coverage * sin_s * inv_sin_t;
  }
  float mu = sqrt(max(1.0f - dot(xy, xy), 0.0f));  // n · to_observer
  // n · to_sun (to_observer = -direction), with to_sun split along and across
  // the line of sight, so that no rounding residue of xy along the direction
  // reaches mu0 (at full Moon to_sun = -direction and it would all go there).
  float along = dot(m.to_sun, m.direction);
  float mu0 = dot(xy, m.to_sun - along * m.direction) - mu * along;
  float sunlit = mu0 > 0.0f ? mu0 / (mu0 + mu) : 0.0f;             // mu0 > 0: the denominator is > 0
  return weight * (sunlit * m.sun_radiance + m.earthshine_radiance);
}
