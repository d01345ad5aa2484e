// preetham.h — the ANALYTIC sky tier on the CPU: Preetham, Shirley & Smits
// 1999 ("A Practical Analytic Model for Daylight", SIGGRAPH 99, Appendix A).
// Computes the Perez distribution coefficients and zenith values for the
// shader (shaders/atmosphere/preetham.glsl, compiled here as the CPU twin), a
// turbidity from the host's visibility, and a validity verdict that says when
// the fit can be trusted and when to hand over to the LUT tier (with a
// confidence that ramps smoothly so the caller can cross-fade).
//
// Units: the paper gives the zenith luminance Y_z in kcd/m^2;
// PreethamCoefficients::zenith_Yxy.x is in cd/m^2 (x 1000), so the shader
// returns cd/m^2. Angles in radians. See docs/PREETHAM.md.
#pragma once

#include <string>

#include "core/atmosphere/shader_twin.h"
#include "core/spectral/spectral_atmosphere.h"

// The shared GLSL source as C++ (no-op if shader_twin.h already included it:
// preetham.glsl carries its own include guard, valid in GLSL and C++).
namespace atmo::twin {
#include "core/twin/glsl_begin.h"
#include "atmosphere/preetham.glsl"
#include "core/twin/glsl_end.h"
}  // namespace atmo::twin

namespace atmo::core {

// Validity region (docs/PREETHAM.md explains each bound). Hard bounds: outside
// them `valid` is false. Confidence is 1 inside the "full" bounds and falls
// smoothly (smoothstep) to 0 at the hard bounds.
constexpr double kPreethamMinTurbidity = 1.7;       // 1 + A_Y e^{B_Y} crosses 0 at T ~ 1.64
constexpr double kPreethamFullMinTurbidity = 2.2;
constexpr double kPreethamFullMaxTurbidity = 8.5;
constexpr double kPreethamMaxTurbidity = 10.0;      // upper end of the range the fit is used for
constexpr double kPreethamMinSunElevationRad = 2.0 * 3.14159265358979323846 / 180.0;
constexpr double kPreethamFullSunElevationRad = 6.0 * 3.14159265358979323846 / 180.0;
constexpr double kPreethamFullMaxEyeAltitudeM = 500.0;
constexpr double kPreethamMaxEyeAltitudeM = 2000.0;  // ground-observer fit

// Coefficients for the shader, from the paper's formulas in double precision,
// stored as float. Turbidity and sun zenith angle are used as given (no
// clamping of T: check preetham_validity); theta_s is clamped to [0, pi]. Past
// the horizon (theta_s > pi/2) the chromaticity polynomials are held at their
// horizon value and Y_z (which the formula keeps positive far below the
// horizon) is floored at 0.
twin::PreethamCoefficients preetham_coefficients(double turbidity, double sun_zenith_rad);

// The paper's zenith luminance formula, raw, in kcd/m^2 (may be negative far
// below the horizon):
//   Y_z = (4.0453 T - 4.9710) tan(chi) - 0.2155 T + 2.4192,  chi = (4/9 - T/120)(pi - 2 theta_s).
double preetham_zenith_luminance_kcd(double turbidity, double sun_zenith_rad);

// The paper's zenith chromaticity polynomials (x_z, y_z), theta_s in radians.
void preetham_zenith_chromaticity(double turbidity, double sun_zenith_rad, double& x_z, double& y_z);

// Turbidity from the meteorological optical range, by the definition the paper
// uses, T = (tau_molecules + tau_haze) / tau_molecules (vertical optical
// thickness at 550 nm), with the air of the spectral model, the LUT tier's
// (spectral::turbidity_from_visibility: first-principles Rayleigh, 1.1496e-5 /m
// at 550 nm x 8000 m = 0.0920; haze from Koschmieder at 5 % contrast,
// beta_haze = ln(20) / MOR - beta_Rayleigh, floored at 2e-7 /m; tau_haze =
// beta_haze x aerosol scale height). MOR is floored at 1 m.
double preetham_turbidity_from_visibility(double visibility_m,
                                          double aerosol_scale_height_m = spectral::kDefaultAerosolScaleHeightM);
// The inverse, MOR in metres (T <= 1 gives the MOR of the aerosol floor, 256 km).
double preetham_visibility_from_turbidity(double turbidity,
                                          double aerosol_scale_height_m = spectral::kDefaultAerosolScaleHeightM);

struct PreethamValidity {
  bool valid = false;       // inside the hard bounds: the analytic tier may be drawn
  double confidence = 0.0;  // 0..1, 1 = well inside the fitted range; continuous
  std::string reason;       // which bound fails or is near, with the values
};

// Verdict for the analytic tier. Sun elevation in radians above the horizon,
// eye altitude in metres above sea level. Non-finite input is invalid.
PreethamValidity preetham_validity(double turbidity, double sun_elevation_rad, double eye_altitude_m);

}  // namespace atmo::core
