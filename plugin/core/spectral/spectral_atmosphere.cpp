#include "core/spectral/spectral_atmosphere.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace atmo::spectral {

namespace detail {
extern const double kOzoneCrossSectionTable[][2];
extern const int kOzoneCrossSectionTableRows;
}  // namespace detail

double air_refractivity(double wavelength_nm) {
  const double s2 = std::pow(1000.0 / wavelength_nm, 2.0);  // (1/λ in µm)^2
  return (8060.51 + 2480990.0 / (132.274 - s2) + 17455.7 / (39.32957 - s2)) * 1e-8;
}

double king_factor_air(double wavelength_nm, double co2_ppmv) {
  const double l2 = std::pow(wavelength_nm * 1e-3, 2.0);  // λ² in µm²
  const double f_n2 = 1.034 + 3.17e-4 / l2;
  const double f_o2 = 1.096 + 1.385e-3 / l2 + 1.448e-4 / (l2 * l2);
  const double c_co2 = co2_ppmv * 1e-4;  // percent by volume
  return (78.084 * f_n2 + 20.946 * f_o2 + 0.934 * 1.00 + c_co2 * 1.15) / (78.084 + 20.946 + 0.934 + c_co2);
}

double rayleigh_cross_section_m2(double wavelength_nm) {
  const double n = 1.0 + air_refractivity(wavelength_nm);
  const double lambda = wavelength_nm * 1e-9;
  const double ll = (n * n - 1.0) / (n * n + 2.0);
  const double N = kAirNumberDensitySeaLevel;
  return 24.0 * kPi * kPi * kPi / (std::pow(lambda, 4.0) * N * N) * ll * ll * king_factor_air(wavelength_nm);
}

double rayleigh_scattering_sea_level(double wavelength_nm) {
  return kAirNumberDensitySeaLevel * rayleigh_cross_section_m2(wavelength_nm);
}

double aerosol_extinction_550(double visibility_m) {
  const double total = std::log(1.0 / kKoschmiederContrast) / visibility_m;
  return std::max(total - rayleigh_scattering_sea_level(550.0), kMinAerosolExtinction);
}

double visibility_from_turbidity(double turbidity, double aerosol_scale_height_m) {
  const double beta_r = rayleigh_scattering_sea_level(550.0);
  const double beta_a = std::max(turbidity - 1.0, 0.0) * beta_r * kRayleighScaleHeightM / aerosol_scale_height_m;
  return std::log(1.0 / kKoschmiederContrast) / (beta_r + std::max(beta_a, kMinAerosolExtinction));
}

double turbidity_from_visibility(double visibility_m, double aerosol_scale_height_m) {
  const double beta_r = rayleigh_scattering_sea_level(550.0);
  return 1.0 + aerosol_extinction_550(visibility_m) * aerosol_scale_height_m / (beta_r * kRayleighScaleHeightM);
}

double ozone_cross_section_m2(double wavelength_nm) {
  const auto* t = detail::kOzoneCrossSectionTable;
  const int n = detail::kOzoneCrossSectionTableRows;
  if (wavelength_nm <= t[0][0]) return t[0][1];
  if (wavelength_nm >= t[n - 1][0]) return t[n - 1][1];
  int i = 0;
  while (t[i + 1][0] < wavelength_nm) ++i;
  const double a = (wavelength_nm - t[i][0]) / (t[i + 1][0] - t[i][0]);
  return t[i][1] * (1.0 - a) + t[i + 1][1] * a;
}

double ozone_peak_number_density(double column_du, double half_width_m) {
  return column_du * kDobsonUnit / half_width_m;
}

double solar_irradiance_blackbody(double wavelength_nm, double temperature_k, double tsi) {
  constexpr double h = 6.62607015e-34, c = 299792458.0, k = 1.380649e-23;  // SI 2019, exact
  constexpr double stefan_boltzmann = 5.670374419e-8;
  const double l = wavelength_nm * 1e-9;
  // Planck spectral radiance B_λ (W m^-2 sr^-1 m^-1); π B_λ integrates to σT⁴.
  const double b = 2.0 * h * c * c / std::pow(l, 5.0) / std::expm1(h * c / (l * k * temperature_k));
  return tsi * kPi * b / (stefan_boltzmann * std::pow(temperature_k, 4.0)) * 1e-9;  // per nm
}

double SpectralAtmosphere::rayleigh_density(double altitude_m) const {
  return std::exp(-std::max(altitude_m, 0.0) / rayleigh_scale_height_m);
}
double SpectralAtmosphere::mie_density(double altitude_m) const {
  return std::exp(-std::max(altitude_m, 0.0) / mie_scale_height_m);
}
double SpectralAtmosphere::ozone_density(double altitude_m) const {
  return std::max(0.0, 1.0 - std::abs(altitude_m - ozone_center_m) / ozone_half_width_m);
}

std::vector<double> wavelength_grid(double first_nm, double last_nm, double step_nm) {
  if (!(step_nm > 0.0) || last_nm < first_nm) throw std::invalid_argument("wavelength_grid: bad range");
  std::vector<double> w;
  const int n = static_cast<int>(std::floor((last_nm - first_nm) / step_nm + 1e-9)) + 1;
  for (int i = 0; i < n; ++i) w.push_back(first_nm + i * step_nm);
  return w;
}

SpectralAtmosphere make_spectral_atmosphere(double visibility_m, double aerosol_scale_height_m, double ground_albedo,
                                            double bottom_radius_m, const std::vector<double>& wavelengths_nm) {
  SpectralAtmosphere a;
  a.wavelengths_nm = wavelengths_nm;
  a.mie_scale_height_m = aerosol_scale_height_m;
  a.ground_albedo = ground_albedo;
  a.bottom_radius_m = bottom_radius_m;
  a.top_radius_m = bottom_radius_m + kAtmosphereThicknessM;
  const double aerosol_550 = aerosol_extinction_550(visibility_m);
  const double ozone_n = ozone_peak_number_density();
  for (double w : wavelengths_nm) {
    a.rayleigh_scattering.push_back(rayleigh_scattering_sea_level(w));
    const double ext = aerosol_550 * std::pow(w / 550.0, -kAngstromExponent);
    a.mie_extinction.push_back(ext);
    a.mie_scattering.push_back(ext * kAerosolSingleScatteringAlbedo);
    a.ozone_absorption.push_back(ozone_n * ozone_cross_section_m2(w));
    a.solar_irradiance.push_back(solar_irradiance_blackbody(w));
  }
  return a;
}

RgbCoefficients rgb_model_coefficients(double visibility_m, double aerosol_scale_height_m) {
  RgbCoefficients c;
  SpectralAtmosphere a = make_spectral_atmosphere(visibility_m, aerosol_scale_height_m, 0.1, 6371000.0,
                                                  {c.wavelengths_nm.x, c.wavelengths_nm.y, c.wavelengths_nm.z});
  for (int i = 0; i < 3; ++i) {
    c.rayleigh_scattering[i] = a.rayleigh_scattering[i];
    c.mie_scattering[i] = a.mie_scattering[i];
    c.mie_extinction[i] = a.mie_extinction[i];
    c.ozone_absorption[i] = a.ozone_absorption[i];
    c.solar_irradiance[i] = a.solar_irradiance[i];
  }
  return c;
}

}  // namespace atmo::spectral
