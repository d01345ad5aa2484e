// colorimetry.h — CIE 1931 2° colour-matching functions, CIE D65, and the
// conversion of a sampled spectrum into XYZ, linear sRGB/Rec.709 (D65) and
// luminance. The tables come from Debian's colord-data (data/*.csv, embedded
// at build time).
#pragma once

#include <glm/glm.hpp>
#include <vector>

namespace atmo::spectral {

// Maximum luminous efficacy of radiation, lm/W (SI definition of the candela: 683 at 540 THz).
constexpr double kMaxLuminousEfficacy = 683.0;

struct CmfSample {
  double wavelength_nm;
  double x, y, z;
};

// CIE 1931 2° observer, 360–830 nm every 5 nm (95 rows).
const std::vector<CmfSample>& cie1931_2deg_5nm();
// Linear interpolation of the table; zero outside 360–830 nm.
glm::dvec3 cie1931_2deg(double wavelength_nm);

struct SpdSample {
  double wavelength_nm;
  double value;
};

// CIE standard illuminant D65, relative (100 at 560 nm is 1.0 here), 300–830 nm every 5 nm.
const std::vector<SpdSample>& cie_d65_5nm();
double cie_d65(double wavelength_nm);

// Linear sRGB / Rec.709 primaries with the D65 white, derived from the
// chromaticities of IEC 61966-2-1 (R 0.64,0.33  G 0.30,0.60  B 0.15,0.06  W 0.3127,0.3290).
glm::dmat3 linear_srgb_from_xyz();

// Integrates spectra sampled on an arbitrary increasing wavelength grid
// against the CMFs: the spectrum is taken as piecewise linear between the
// samples (constant beyond the ends) and multiplied by the 5 nm table,
// itself linearly interpolated, in 1 nm sub-steps.
class SpectrumToColor {
 public:
  explicit SpectrumToColor(const std::vector<double>& wavelengths_nm);

  // XYZ = integral of values(λ) · cmf(λ) dλ (units of values times nm).
  glm::dvec3 xyz(const std::vector<double>& values) const;
  // Luminance (cd/m^2 for spectral radiance in W m^-2 sr^-1 nm^-1) = 683 · Y.
  double luminance(const std::vector<double>& values) const;
  // 683 · (linear sRGB from XYZ): Rec.709 radiance in the same photometric units as luminance.
  glm::dvec3 linear_srgb(const std::vector<double>& values) const;

  const std::vector<double>& wavelengths_nm() const { return wavelengths_; }
  const std::vector<glm::dvec3>& weights() const { return weights_; }

 private:
  std::vector<double> wavelengths_;
  std::vector<glm::dvec3> weights_;  // per sample, nm
};

}  // namespace atmo::spectral
