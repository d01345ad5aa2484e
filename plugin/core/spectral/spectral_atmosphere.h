// spectral_atmosphere.h — the atmosphere of Atmo as a function of wavelength:
// molecules (Rayleigh, from first principles), aerosols (from the
// meteorological visibility), ozone (Chappuis band), and the sun's spectrum
// at the top of the atmosphere. SI units, double precision. Sources and
// uncertainties: docs/REFERENCE.md.
#pragma once

#include <glm/glm.hpp>
#include <vector>

namespace atmo::spectral {

constexpr double kPi = 3.14159265358979323846;

// --- Molecules ---------------------------------------------------------------
constexpr double kAirNumberDensitySeaLevel = 2.545e25;  // m^-3 (US Std. Atm. 1976 sea level; 15 °C, 101325 Pa)
constexpr double kRayleighScaleHeightM = 8000.0;
constexpr double kCo2Ppmv = 400.0;                      // for the King factor only

// Refractivity n - 1 of standard dry air (15 °C, 101325 Pa, 300 ppm CO2),
// Peck & Reeder 1972 (JOSA 62, 958), valid 230–1690 nm.
double air_refractivity(double wavelength_nm);
// King correction factor (6 + 3ρ)/(6 - 7ρ) of air: Bates 1984 for N2 and O2,
// 1.00 for Ar, 1.15 for CO2, weighted by volume mixing ratio (Bodhaine et al. 1999, eq. 23).
double king_factor_air(double wavelength_nm, double co2_ppmv = kCo2Ppmv);
// Rayleigh scattering cross-section per molecule, m^2:
// 24 π³ / (λ⁴ N²) · ((n² - 1)/(n² + 2))² · F_K, with N = kAirNumberDensitySeaLevel.
double rayleigh_cross_section_m2(double wavelength_nm);
// Sea-level Rayleigh scattering coefficient, 1/m.
double rayleigh_scattering_sea_level(double wavelength_nm);

// --- Aerosols ------------------------------------------------------------------
constexpr double kKoschmiederContrast = 0.05;  // MOR: ln(1/0.05) = ln 20 = 2.996
constexpr double kAngstromExponent = 1.3;
constexpr double kAerosolSingleScatteringAlbedo = 0.9;
constexpr double kMieAsymmetryG = 0.8;          // Cornette-Shanks phase function
constexpr double kMinAerosolExtinction = 2e-7;  // 1/m at 550 nm, the floor of aerosol_extinction_550
constexpr double kDefaultAerosolScaleHeightM = 1200.0;

// Sea-level aerosol extinction at 550 nm from the meteorological optical
// range: ln(20)/MOR minus the Rayleigh scattering at 550 nm, floored.
double aerosol_extinction_550(double visibility_m);
// Turbidity as defined by Preetham, Shirley & Smits 1999 (after McCartney
// 1976): T = (τ_molecules + τ_aerosols) / τ_molecules, vertical optical
// thicknesses at 550 nm. With exponential profiles τ = β(0)·H, so
// β_aerosol(0) = (T - 1)·β_R(0)·H_R / H_A and MOR = ln 20 / (β_R(0) + β_aerosol(0)).
double visibility_from_turbidity(double turbidity, double aerosol_scale_height_m = kDefaultAerosolScaleHeightM);
double turbidity_from_visibility(double visibility_m, double aerosol_scale_height_m = kDefaultAerosolScaleHeightM);

// --- Ozone ---------------------------------------------------------------------
constexpr double kDobsonUnit = 2.6867e20;  // molecules per m^2 (0.01 mm of gas at 0 °C, 101325 Pa)
constexpr double kOzoneColumnDu = 300.0;
constexpr double kOzonePeakAltitudeM = 25000.0;
constexpr double kOzoneHalfWidthM = 15000.0;  // tent profile: integral = half width
// Absorption cross-section, m^2 (table at 233 K, 365–835 nm every 10 nm,
// linearly interpolated; clamped to the end values outside).
double ozone_cross_section_m2(double wavelength_nm);
// Number density at the tent's peak for a column in Dobson units, m^-3.
double ozone_peak_number_density(double column_du = kOzoneColumnDu, double half_width_m = kOzoneHalfWidthM);

// --- Sun -------------------------------------------------------------------------
constexpr double kSunTemperatureK = 5772.0;        // IAU 2015 B3 nominal effective temperature
constexpr double kTotalSolarIrradiance = 1361.0;   // W/m^2 at 1 AU (IAU 2015 B3 nominal, Kopp & Lean 2011)
// Spectral irradiance at the top of the atmosphere, W m^-2 nm^-1: a black
// body at `temperature_k` scaled so its integral over all wavelengths is
// `tsi`. An approximation (no Fraunhofer lines, too much UV); replace by a
// measured table through SpectralAtmosphere::solar_irradiance.
double solar_irradiance_blackbody(double wavelength_nm, double temperature_k = kSunTemperatureK,
                                  double tsi = kTotalSolarIrradiance);

// --- The atmosphere ---------------------------------------------------------------
constexpr double kAtmosphereThicknessM = 100000.0;

struct SpectralAtmosphere {
  std::vector<double> wavelengths_nm;
  // Per wavelength, 1/m: sea-level values for Rayleigh and aerosols, peak value for ozone.
  std::vector<double> rayleigh_scattering;
  std::vector<double> mie_scattering;
  std::vector<double> mie_extinction;
  std::vector<double> ozone_absorption;
  std::vector<double> solar_irradiance;  // W m^-2 nm^-1, top of the atmosphere

  double rayleigh_scale_height_m = kRayleighScaleHeightM;
  double mie_scale_height_m = kDefaultAerosolScaleHeightM;
  double mie_g = kMieAsymmetryG;
  double ozone_center_m = kOzonePeakAltitudeM;
  double ozone_half_width_m = kOzoneHalfWidthM;
  double ground_albedo = 0.1;  // Lambertian, grey
  double bottom_radius_m = 6371000.0;
  double top_radius_m = 6371000.0 + kAtmosphereThicknessM;

  // Density profiles, relative to the coefficients above (altitude in m; below 0 counts as 0).
  double rayleigh_density(double altitude_m) const;
  double mie_density(double altitude_m) const;
  double ozone_density(double altitude_m) const;
  size_t size() const { return wavelengths_nm.size(); }
};

// Wavelengths first, first + step, ... up to last (inclusive).
std::vector<double> wavelength_grid(double first_nm = 360.0, double last_nm = 830.0, double step_nm = 10.0);

SpectralAtmosphere make_spectral_atmosphere(double visibility_m, double aerosol_scale_height_m, double ground_albedo,
                                            double bottom_radius_m,
                                            const std::vector<double>& wavelengths_nm = wavelength_grid());

// The same model at the real-time model's three wavelengths (x, y, z = 680,
// 550, 440 nm), to compare with core::make_atmosphere_parameters.
struct RgbCoefficients {
  glm::dvec3 wavelengths_nm{680.0, 550.0, 440.0};
  glm::dvec3 rayleigh_scattering;  // 1/m, sea level
  glm::dvec3 mie_scattering;
  glm::dvec3 mie_extinction;
  glm::dvec3 ozone_absorption;     // 1/m at the peak
  glm::dvec3 solar_irradiance;     // W m^-2 nm^-1
};
RgbCoefficients rgb_model_coefficients(double visibility_m,
                                       double aerosol_scale_height_m = kDefaultAerosolScaleHeightM);

}  // namespace atmo::spectral
