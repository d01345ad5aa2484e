// The spectral atmosphere definition: CIE tables, colour conversion, and the
// first-principles coefficients against published magnitudes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/spectral/colorimetry.h"
#include "core/spectral/spectral_atmosphere.h"

using namespace atmo::spectral;

TEST(Colorimetry, Cie1931TableHasTheKnownSums) {
  const auto& t = cie1931_2deg_5nm();
  ASSERT_EQ(t.size(), 95u);
  EXPECT_DOUBLE_EQ(t.front().wavelength_nm, 360.0);
  EXPECT_DOUBLE_EQ(t.back().wavelength_nm, 830.0);
  glm::dvec3 sum(0.0);
  for (const auto& s : t) sum += glm::dvec3(s.x, s.y, s.z);
  std::printf("[ cmf ] sums at 5 nm: x %.5f y %.5f z %.5f (CIE: 21.3714 for each)\n", sum.x, sum.y, sum.z);
  // The three CMFs of the 1931 observer have equal areas (equal-energy white
  // E); in the 5 nm table they agree to 0.04 % (z is the furthest).
  EXPECT_NEAR(sum.y, 21.3714, 2e-3);
  EXPECT_NEAR(sum.x, sum.y, 1e-2);
  EXPECT_NEAR(sum.z, sum.y, 1e-2);
  EXPECT_DOUBLE_EQ(cie1931_2deg(555.0).y, 1.0);
  EXPECT_NEAR(cie1931_2deg(552.5).y, 0.5 * (0.9949501 + 1.0), 1e-12);

  // A flat spectrum through the integration weights of a 5 nm and a 10 nm grid.
  for (double step : {5.0, 10.0}) {
    SpectrumToColor c(wavelength_grid(360.0, 830.0, step));
    glm::dvec3 xyz = c.xyz(std::vector<double>(c.wavelengths_nm().size(), 1.0));
    std::printf("[ cmf ] flat spectrum, %2.0f nm grid: integral of ybar = %.4f nm (table sum x 5 nm = %.4f)\n", step,
                xyz.y, sum.y * 5.0);
    EXPECT_NEAR(xyz.y / (sum.y * 5.0), 1.0, 1e-3);
  }
}

TEST(Colorimetry, D65IsWhiteInLinearSrgb) {
  const auto& d65 = cie_d65_5nm();
  ASSERT_EQ(d65.size(), 107u);
  std::vector<double> w, v;
  for (const auto& s : d65)
    if (s.wavelength_nm >= 360.0) {
      w.push_back(s.wavelength_nm);
      v.push_back(s.value);
    }
  SpectrumToColor c(w);
  glm::dvec3 xyz = c.xyz(v);
  glm::dvec3 rgb = linear_srgb_from_xyz() * (xyz / xyz.y);
  std::printf("[ d65 ] chromaticity x %.5f y %.5f, linear sRGB / Y = %.5f %.5f %.5f\n", xyz.x / (xyz.x + xyz.y + xyz.z),
              xyz.y / (xyz.x + xyz.y + xyz.z), rgb.r, rgb.g, rgb.b);
  EXPECT_NEAR(rgb.r, 1.0, 2e-3);
  EXPECT_NEAR(rgb.g, 1.0, 2e-3);
  EXPECT_NEAR(rgb.b, 1.0, 2e-3);
  // The matrix's second row is the luminance of the primaries.
  glm::dmat3 rgb_to_xyz = glm::inverse(linear_srgb_from_xyz());
  EXPECT_NEAR(rgb_to_xyz[0].y, 0.2126, 1e-4);
  EXPECT_NEAR(rgb_to_xyz[1].y, 0.7152, 1e-4);
  EXPECT_NEAR(rgb_to_xyz[2].y, 0.0722, 1e-4);
}

TEST(SpectralAtmosphere, RayleighFromFirstPrinciples) {
  // Bodhaine et al. 1999 give sigma(550 nm) ~ 4.5e-27 cm^2 and F_air(550) ~ 1.049.
  EXPECT_NEAR(air_refractivity(550.0), 2.778e-4, 1e-6);
  EXPECT_NEAR(king_factor_air(550.0), 1.049, 1e-3);
  const double beta = rayleigh_scattering_sea_level(550.0);
  std::printf("[ air ] sigma(550) = %.4e m^2, beta(550) = %.4e /m; beta(440, 680) = %.4e, %.4e /m\n",
              rayleigh_cross_section_m2(550.0), beta, rayleigh_scattering_sea_level(440.0),
              rayleigh_scattering_sea_level(680.0));
  EXPECT_GT(beta, 1.1e-5);
  EXPECT_LT(beta, 1.4e-5);
  // Steeper than lambda^-4 (dispersion of n and the King factor).
  EXPECT_GT(rayleigh_scattering_sea_level(400.0) / rayleigh_scattering_sea_level(800.0), 16.0);
}

TEST(SpectralAtmosphere, ThreeWavelengthCoefficientsAgainstTheRgbModel) {
  RgbCoefficients c = rgb_model_coefficients(40000.0);
  // The real-time model (plugin/core/atmosphere/atmosphere_model.cpp), for the record.
  const glm::dvec3 rgb_rayleigh(5.802e-6, 13.558e-6, 33.1e-6), rgb_ozone(0.650e-6, 1.881e-6, 0.085e-6);
  for (int i = 0; i < 3; ++i)
    std::printf("[ rgb ] %3.0f nm: rayleigh %.4e (RGB model %.4e, %+5.1f %%), ozone %.4e (%.4e, %+5.1f %%), "
                "aerosol ext %.4e, sun %.4f W/m^2/nm\n",
                c.wavelengths_nm[i], c.rayleigh_scattering[i], rgb_rayleigh[i],
                100.0 * (c.rayleigh_scattering[i] / rgb_rayleigh[i] - 1.0), c.ozone_absorption[i], rgb_ozone[i],
                100.0 * (c.ozone_absorption[i] / rgb_ozone[i] - 1.0), c.mie_extinction[i], c.solar_irradiance[i]);
  // Same Koschmieder rule: Rayleigh + aerosol extinction at 550 nm = ln 20 / MOR.
  EXPECT_NEAR(c.rayleigh_scattering.y + c.mie_extinction.y, std::log(20.0) / 40000.0, 1e-12);
  EXPECT_NEAR(c.mie_scattering.y / c.mie_extinction.y, 0.9, 1e-12);
  EXPECT_NEAR(c.mie_extinction.z / c.mie_extinction.x, std::pow(440.0 / 680.0, -1.3), 1e-9);
  // Very clear air: the aerosol floor.
  EXPECT_DOUBLE_EQ(rgb_model_coefficients(300000.0).mie_extinction.y, 2e-7);
  // The ozone column: peak density x tent area = 300 DU.
  EXPECT_NEAR(ozone_peak_number_density() * kOzoneHalfWidthM / kDobsonUnit, 300.0, 1e-9);
  // Chappuis maximum near 600 nm, ~5e-25 m^2 (5e-21 cm^2).
  EXPECT_NEAR(ozone_cross_section_m2(605.0), 5.0e-25, 0.3e-25);
}

TEST(SpectralAtmosphere, TurbidityAndVisibility) {
  for (double t : {2.0, 3.0, 5.0, 10.0}) {
    const double v = visibility_from_turbidity(t);
    std::printf("[ turbidity ] T = %4.1f -> MOR = %7.0f m (aerosol scale height 1200 m)\n", t, v);
    EXPECT_NEAR(turbidity_from_visibility(v), t, 1e-9);
  }
  EXPECT_GT(visibility_from_turbidity(2.0), visibility_from_turbidity(3.0));
}

TEST(SpectralAtmosphere, SunIsA5772KBlackBodyWithTheSolarConstant) {
  // Integral over a wide range recovers the TSI (the tails beyond 100 nm–100 µm are < 0.1 %).
  double total = 0.0;
  for (double w = 100.0; w < 100000.0; w += 1.0) total += solar_irradiance_blackbody(w + 0.5);
  EXPECT_NEAR(total, 1361.0, 1.5);
  // Wien: peak at 2.8978e6 nm K / 5772 K = 502 nm.
  EXPECT_GT(solar_irradiance_blackbody(502.0), solar_irradiance_blackbody(480.0));
  EXPECT_GT(solar_irradiance_blackbody(502.0), solar_irradiance_blackbody(525.0));
  SpectralAtmosphere a = make_spectral_atmosphere(40000.0, 1200.0, 0.1, 6371000.0, wavelength_grid(360, 830, 5));
  SpectrumToColor c(a.wavelengths_nm);
  const double lux = c.luminance(a.solar_irradiance);
  const glm::dvec3 rgb = c.linear_srgb(a.solar_irradiance);
  std::printf("[ sun ] 360-830 nm: %.1f W/m^2, illuminance %.0f lux (RGB model: 128000), "
              "linear sRGB %.0f %.0f %.0f\n",
              [&] { double s = 0; for (double e : a.solar_irradiance) s += e * 5.0; return s; }(), lux, rgb.r, rgb.g,
              rgb.b);
  EXPECT_GT(lux, 120000.0);
  EXPECT_LT(lux, 135000.0);
}
