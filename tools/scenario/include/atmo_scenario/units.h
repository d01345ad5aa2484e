// Unit conversions at the edges (weather reports, aviation, photography)
// to the SI values Atmo uses inside.
#ifndef ATMO_SCENARIO_UNITS_H
#define ATMO_SCENARIO_UNITS_H

#include <algorithm>
#include <cmath>

namespace atmo::scenario::units {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kMetresPerFoot = 0.3048;  // exact, international foot
inline constexpr double kZeroCelsiusK = 273.15;
inline constexpr double kPaPerHpa = 100.0;

// Koschmieder: meteorological optical range (MOR) is where a black object's
// contrast falls to 5 %, so beta = -ln(0.05) / MOR = 2.9957 / MOR (1/m).
// atmo.h rounds the constant to 3.0; the 0.1 % difference is immaterial.
inline constexpr double kMorContrastThreshold = 0.05;
inline constexpr double kKoschmiederConstant = 2.995732273553991;  // -ln(0.05)

constexpr double degrees_to_radians(double deg) { return deg * (kPi / 180.0); }
constexpr double radians_to_degrees(double rad) { return rad * (180.0 / kPi); }

constexpr double feet_to_metres(double ft) { return ft * kMetresPerFoot; }
constexpr double metres_to_feet(double m) { return m / kMetresPerFoot; }

constexpr double celsius_to_kelvin(double c) { return c + kZeroCelsiusK; }
constexpr double kelvin_to_celsius(double k) { return k - kZeroCelsiusK; }

constexpr double hpa_to_pa(double hpa) { return hpa * kPaPerHpa; }
constexpr double pa_to_hpa(double pa) { return pa / kPaPerHpa; }

// Cloud cover: 8 oktas = fully covered sky.
constexpr double oktas_to_fraction(double oktas) { return oktas / 8.0; }
constexpr double fraction_to_oktas(double fraction) { return fraction * 8.0; }
// The okta a METAR would report (WMO code 2700): 0 only for a clear sky and 8
// only for a fully covered one, so any trace of cloud is at least 1 and any
// gap at most 7.
inline int fraction_to_okta_code(double fraction) {
  if (!(fraction > 0.0)) return 0;
  if (fraction >= 1.0) return 8;
  return std::clamp(static_cast<int>(std::lround(fraction * 8.0)), 1, 7);
}

// MOR (m) <-> extinction coefficient (1/m), see kKoschmiederConstant.
constexpr double mor_to_extinction(double mor_m) { return kKoschmiederConstant / mor_m; }
constexpr double extinction_to_mor(double beta_per_m) { return kKoschmiederConstant / beta_per_m; }

// Photographic exposure: the multiplier from cd/m^2 to output units for a
// camera set to EV100 (ISO 100), 1 / (1.2 * 2^EV100); 1.2 = 78 / (0.65 * 100),
// the saturation-based calibration of ISO 12232 with lens transmission 0.65.
inline double ev100_to_exposure_scale(double ev100) { return 1.0 / (1.2 * std::exp2(ev100)); }
inline double exposure_scale_to_ev100(double scale) { return std::log2(1.0 / (1.2 * scale)); }

}  // namespace atmo::scenario::units

#endif  // ATMO_SCENARIO_UNITS_H
