// night_sky_twin.h — compiles shaders/night_sky/moon_disc.glsl and
// shaders/night_sky/background.glsl as C++ over GLM, so the CPU evaluates
// exactly the Moon's disc and the night-sky background the GPU draws (in
// float, like the GPU); and builds their per-frame parameter structs from the
// core's double-precision quantities. The core's moon_disc_radiance_rgb
// (moon_photometry.h) and night_background(...).rgb() (background.h) are the
// same formulas in double; tests/core/night_sky_twin_test.cpp checks they
// agree and docs/NIGHT_SKY.md quotes the figures.
#pragma once

#include <glm/glm.hpp>

#include "core/night_sky/background.h"
#include "core/night_sky/moon_photometry.h"

namespace atmo::twin {

using namespace glm;

#include "core/twin/glsl_begin.h"
#include "night_sky/moon_disc.glsl"
#include "night_sky/background.glsl"
#include "core/twin/glsl_end.h"

}  // namespace atmo::twin

namespace atmo::core::night {

// --- The Moon's disc ------------------------------------------------------------------

// The per-frame MoonDisc of moon_disc.glsl. moon_enu: the (apparent) direction
// of the Moon's centre; angular_radius_rad: its semi-diameter (asin(kMoonRadiusM
// / distance), SkyBodies::moon_angular_radius_rad); moon_to_sun_enu: from the
// Moon toward the Sun (moon_to_sun_enu() below), which sets the orientation of
// the terminator; `lighting`: moon_disc_lighting() for the phase angle between
// moon_to_sun_enu and -moon_enu (the caller keeps the two consistent). Vectors
// need not be unit (normalised here; a zero vector becomes +up). Sun term
// 2/(3 pi) sun_albedo_lux sun_bs colour, earthshine term 2/(3 pi)
// earthshine_albedo_lux earthshine_bs / 2 colour (moon_disc_luminance).
twin::MoonDisc make_moon_disc(const glm::dvec3& moon_enu, double angular_radius_rad, const glm::dvec3& moon_to_sun_enu,
                              const MoonDiscLighting& lighting);

// The unit vector from the Moon toward the Sun from both directions (unit, any
// frame) and distances from the observer (same unit): sun·d_sun - moon·d_moon,
// normalised. Differs from the Sun's direction seen from the eye by up to
// d_moon / d_sun ~ 0.15°, which is what puts the terminator right near
// quarter phase.
glm::dvec3 moon_to_sun_direction(const glm::dvec3& sun_dir, double sun_distance, const glm::dvec3& moon_dir,
                                 double moon_distance);

// --- The background -------------------------------------------------------------------

// The per-frame NightBackground of background.glsl: the rotation ICRS <- ENU
// at the eye (columns: east, north, up in ICRS), the Sun's ICRS direction (need
// not be unit), the eye's altitude above the sphere of planet_radius_m (the
// atmosphere's bottom radius), the settings (S10 converted to cd/m^2 here,
// the clamps of background.cpp applied: altitude >= 0, radius and layer
// thickness >= 1 m) and the components' colours.
twin::NightBackground make_night_background(const glm::dmat3& icrs_from_enu, const glm::dvec3& sun_icrs,
                                           double eye_altitude_m, double planet_radius_m,
                                           const BackgroundSettings& settings = {});

// A cheap per-frame upper bound of the background's luminance (cd/m^2,
// outside the air: the sum of the components, each with a luminance-1 colour)
// over every direction whose ray escapes the planet (elevation above -dip,
// dip = acos(R / (R + h))); rays that meet the ground get transmittance 0 in
// the sky pass. If exposure · transmittance · this bound cannot change a
// display value, the pass can skip the background. Terms:
// - airglow: the zenith value times the largest slant factor over all rays,
//   in closed form (eye below the shell: the horizontal ray, the van Rhijn
//   horizon value ~6; in the shell: the ray grazing its inner sphere; above
//   it: twice the chord of the grazing ray);
// - zodiacal light: the fit's ecliptic (beta = 0) value at the smallest
//   elongation any such direction can have, the Sun's depression below -dip
//   less 1° for refraction (clamped >= 2°), plus the Gegenschein term's
//   maximum (the ecliptic term falls monotonically with elongation);
// - starlight: pole + excess · (1 + |contrast|), the galactic centre; times
//   (1 + diffuse galactic fraction), plus the cosmic light.
// Measured (tests/core/night_sky_twin_test.cpp): never exceeded; 1.05–3.8 times
// the largest value sampled over the sky (the components peak in different
// directions) for the Sun 5–90° below the horizon and the eye at 0–150 km.
// At sea level with the Sun 30° below: 2.8e-3 cd/m^2 (3350 S10), of which
// the zodiacal light at 29° elongation is 2050 S10 and the airglow at the
// horizon 870 S10.
double night_background_max_luminance(const glm::dmat3& icrs_from_enu, const glm::dvec3& sun_icrs,
                                      double eye_altitude_m, double planet_radius_m,
                                      const BackgroundSettings& settings = {});
// The same bound per channel: each component's bound times its colour.
glm::dvec3 night_background_max_rgb(const glm::dmat3& icrs_from_enu, const glm::dvec3& sun_icrs,
                                    double eye_altitude_m, double planet_radius_m,
                                    const BackgroundSettings& settings = {});

}  // namespace atmo::core::night
