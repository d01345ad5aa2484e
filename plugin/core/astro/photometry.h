// photometry.h — brightness and appearance of the Sun, the Moon and the
// planets: apparent V magnitude, illuminated fraction, the Moon's bright limb.
//
// Planets: Mallama & Hilton (2018), "Computing apparent planetary magnitudes
// for The Astronomical Almanac", Astronomy and Computing 25, 10-24 — the
// geocentric-phase-angle fits (Mars without its rotational/orbital terms,
// Saturn with its rings).
// Moon: Krisciunas & Schaefer (1991) phase law V = -12.73 + 0.026|a| +
// 4e-9 a^4 (a in degrees, at 1 au from the Sun and 384 400 km), plus the
// inverse-square distance terms, up to a = 150°; past it (a crescent within
// 30° of the Sun, beyond the photometry that law was fitted to) the flux falls
// as (180° - a)^3, joined continuously at 150° — the steep crescent fall-off
// that the Vreijs law of the Swiss Ephemeris also shows (docs/EPHEMERIS.md).
// Sun: V = -26.76 at 1 au (Willmer 2018, ApJS 236, 47).
#pragma once

#include "core/astro/solar_system.h"

namespace atmo::core::astro {

// Radii (m): the Sun (IAU 2015 nominal), the Moon (mean), planets (equatorial).
double body_radius_m(Body body);

// Apparent V magnitude. sun_distance_au: body-Sun; observer_distance_au:
// body-observer; phase_angle_rad: Sun-body-observer; saturn_ring_tilt_rad:
// the observer's latitude above Saturn's ring plane (ignored for the others).
double apparent_magnitude(Body body, double sun_distance_au, double observer_distance_au, double phase_angle_rad,
                          double saturn_ring_tilt_rad = 0.0);

// Fraction of the disc's area that is lit: (1 + cos phase) / 2.
double illuminated_fraction(double phase_angle_rad);

// Position angle of the bright limb's midpoint, measured from the north point
// of the disc through east (Meeus, Astronomical Algorithms, eq. 48.5), from
// the apparent RA/Dec of the Sun (ra0, dec0) and of the body (ra, dec).
// Radians in [0, 2 pi).
double bright_limb_position_angle(double ra_sun, double dec_sun, double ra, double dec);

// Parallactic angle q (position angle of the zenith on the disc, from north
// through east) from the hour angle, declination and latitude (Meeus 14.1,
// written without tan(latitude) so the poles are finite).
double parallactic_angle(double hour_angle, double dec, double latitude);

// Saturn's north pole (IAU WGCCRE), ICRS unit vector at a TT Julian date.
glm::dvec3 saturn_pole_icrs(JulianDate tt);

}  // namespace atmo::core::astro
