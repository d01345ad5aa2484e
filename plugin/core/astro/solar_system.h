// solar_system.h — where the bodies are: positions in the BCRS with ICRS
// axes (astronomical units), at a Terrestrial Time (TDB - TT, below 2 ms, is
// neglected: under 2 m of lunar motion).
//
//   Earth and Sun: eraEpv00 (ERFA; Earth's heliocentric position good to a
//     few km over 1900-2100).
//   Moon: ELP 2000-82B (Chapront-Touze & Chapront), the full theory as
//     implemented by libnova (ln_get_lunar_geo_posn), series truncated at
//     1e-8 rad; geocentric, inertial mean ecliptic and equinox of J2000,
//     rotated to the ICRS here. ERFA's eraMoon98 (a truncated ELP) misses the
//     10" target (docs/EPHEMERIS.md); it gives the Moon's velocity only.
//   Planets: VSOP87 (Bretagnon & Francou) as implemented by libnova
//     (ln_get_*_helio_coords): heliocentric ecliptic coordinates; measured
//     against DE431 they are referred to the J2000 ecliptic (libnova applies
//     Meeus' FK5 correction, ~0.1"), rotated to the ICRS here. ERFA's
//     eraPlan94 misses the 1' target for Mars, Jupiter and Saturn.
//
// libnova keeps static state (caches, truncation levels); every call here is
// serialized by a mutex, so these functions are thread-safe.
#pragma once

#include <glm/glm.hpp>

#include "core/astro/time_scales.h"

namespace atmo::core::astro {

enum class Body { kSun = 0, kMoon, kMercury, kVenus, kMars, kJupiter, kSaturn };
constexpr int kBodyCount = 7;
const char* to_string(Body body);
inline bool is_planet(Body b) { return b != Body::kSun && b != Body::kMoon; }

// Earth (geocentre) and Sun: barycentric and heliocentric position (au) and
// velocity (au/day). in_range: eraEpv00's 1900-2100 range.
struct EarthSun {
  glm::dvec3 earth_barycentric_au{0.0};
  glm::dvec3 earth_barycentric_velocity_au_d{0.0};
  glm::dvec3 earth_heliocentric_au{0.0};
  glm::dvec3 sun_barycentric_au{0.0};
  glm::dvec3 sun_barycentric_velocity_au_d{0.0};
  bool in_range = true;
};
EarthSun earth_and_sun(JulianDate tt);

// The Moon relative to the geocentre, ICRS axes, au (ELP 2000-82B).
glm::dvec3 moon_geocentric_au(JulianDate tt);
// Its velocity, au/day (eraMoon98: good to ~1e-4 relative, enough for the
// 1.3 s light time).
glm::dvec3 moon_geocentric_velocity_au_d(JulianDate tt);

// A planet relative to the Sun, ICRS axes, au (VSOP87). body must be a planet.
glm::dvec3 planet_heliocentric_au(Body body, JulianDate tt);

// The same from ERFA's approximate routines, for comparison only
// (eraMoon98, eraPlan94 + eraEpv00).
glm::dvec3 moon_geocentric_moon98_au(JulianDate tt);
glm::dvec3 planet_heliocentric_plan94_au(Body body, JulianDate tt);

}  // namespace atmo::core::astro
