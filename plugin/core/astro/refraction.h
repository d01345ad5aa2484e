// refraction.h — astronomical refraction for display: how much higher a body
// appears than its geometric (unrefracted) topocentric elevation.
//
// Two models, blended:
//   above 15°: ERFA's A tan z + B tan^3 z (eraRefco: pressure, temperature,
//     humidity, wavelength; ~1" accurate there), inverted for the unrefracted
//     zenith distance by one Newton step as eraAtioq does;
//   below 5°: Saemundsson (1986), R = 1.02' / tan(h + 10.3/(h + 5.11)) for
//     the true altitude h in degrees, scaled by (P/1010 hPa)(283 K/T) — good
//     to ~0.1' down to the horizon, where A tan z + B tan^3 z fails;
//   5°..15°: a smoothstep blend of the two (they differ by a few arcseconds
//   there).
// Below -1° (visible only from altitude, past the horizon's dip) refraction is
// held at its -1° value down to -1° minus the observer's geometric horizon dip
// acos(R/(R+h)), then fades to zero over 2° (deep below the horizon nothing is
// refracted): finite and continuous, not a ray trace — from high altitude the
// real bending of rays grazing the low atmosphere is larger.
// The default conditions are the US Standard Atmosphere 1976 at the
// observer's height, so refraction fades with altitude (zero by ~100 km).
#pragma once

#include <optional>
#include <string>

namespace atmo::core::astro {

struct RefractionConditions {
  double pressure_hpa = 1013.25;
  double temperature_c = 15.0;
  double relative_humidity = 0.5;  // 0..1
  double wavelength_um = 0.55;     // visual
};

// US Standard Atmosphere 1976 pressure and temperature at a geometric height
// (m; extrapolated below 0 m, isothermal above 86 km), humidity 0.5, 0.55 µm.
RefractionConditions standard_refraction_conditions(double height_m);

// Pressure 0..1200 hPa, temperature -150..100 °C, humidity 0..1, wavelength
// 0.3..30 µm. Returns an error message, or nothing when valid.
std::optional<std::string> validate(const RefractionConditions& c);

// Per-frame constants.
struct RefractionModel {
  double refa = 0.0;                // eraRefco A (radians)
  double refb = 0.0;                // eraRefco B (radians)
  double saemundsson_scale = 0.0;   // (P/1010)(283/(273+T))
  double hold_until_rad = -0.0174533;  // -1° - horizon dip: the held value's end
};
// observer_height_m sets the horizon dip (0 at or below sea level).
RefractionModel make_refraction_model(const RefractionConditions& c, double observer_height_m = 0.0);
inline RefractionModel no_refraction() { return {}; }

// Refraction (radians, >= 0) to add to an unrefracted elevation (radians).
double refraction_rad(const RefractionModel& m, double unrefracted_elevation_rad);

// The two models alone, for tests and documentation.
double refraction_erfa_rad(const RefractionModel& m, double unrefracted_elevation_rad);
double refraction_saemundsson_rad(const RefractionModel& m, double unrefracted_elevation_rad);

}  // namespace atmo::core::astro
