#include "core/atmosphere/atmosphere_model.h"

#include "core/spectral/colorimetry.h"
#include "core/spectral/spectral_atmosphere.h"

#include <algorithm>
#include <cmath>

namespace atmo::core {

twin::AtmosphereParameters make_atmosphere_parameters(const AtmosphereSettings& s, double bottom_radius_m,
                                                      double sun_distance_au) {
  // Coefficients at the three wavelengths from the spectral definition of the
  // air (first-principles Rayleigh, ozone cross-sections, the same aerosol rule).
  const spectral::RgbCoefficients c = spectral::rgb_model_coefficients(s.visibility_m, s.aerosol_scale_height_m);
  twin::AtmosphereParameters atm{};
  atm.bottom_radius_m = static_cast<float>(bottom_radius_m);
  atm.top_radius_m = static_cast<float>(bottom_radius_m + kAtmosphereThicknessM);
  atm.rayleigh_scattering = glm::vec3(c.rayleigh_scattering);
  atm.rayleigh_scale_height_m = static_cast<float>(spectral::kRayleighScaleHeightM);
  atm.mie_extinction = glm::vec3(c.mie_extinction);
  atm.mie_scattering = glm::vec3(c.mie_scattering);
  atm.mie_scale_height_m = static_cast<float>(s.aerosol_scale_height_m);
  atm.mie_g = static_cast<float>(spectral::kMieAsymmetryG);
  atm.ozone_absorption = glm::vec3(c.ozone_absorption);
  atm.ozone_center_m = static_cast<float>(spectral::kOzonePeakAltitudeM);
  atm.ozone_half_width_m = static_cast<float>(spectral::kOzoneHalfWidthM);
  atm.sun_illuminance_lux = glm::vec3(sun_rgb_illuminance_at_1au_lux() / (sun_distance_au * sun_distance_au));
  atm.sun_angular_radius = static_cast<float>(kSunAngularRadiusRad);
  atm.ground_albedo = glm::vec3(static_cast<float>(s.ground_albedo));
  return atm;
}

glm::dvec3 sun_rgb_illuminance_at_1au_lux() {
  // The solar spectrum through the CIE 1931 observer, once: each channel then
  // scales that channel's scattering (Bruneton 2017's three-wavelength rendering).
  static const glm::dvec3 rgb = [] {
    const std::vector<double> grid = spectral::wavelength_grid(360.0, 830.0, 5.0);
    std::vector<double> irradiance;
    for (double nm : grid) irradiance.push_back(spectral::solar_irradiance_blackbody(nm));
    return spectral::SpectrumToColor(grid).linear_srgb(irradiance);
  }();
  return rgb;
}

twin::Lut2D compute_transmittance_table(const twin::AtmosphereParameters& atm, int width,
                                                     int height, int integration_steps,
                                                     const TableBuildControl& control) {
  twin::Lut2D table;
  table.width = width;
  table.height = height;
  table.texels.resize(static_cast<size_t>(width) * height);
  const double bottom = atm.bottom_radius_m;
  for (int y = 0; y < height; ++y) {
    if (control.stopped()) return {};
    for (int x = 0; x < width; ++x) {
      // Texel centre -> unit coordinates (the lookup maps x_mu = 0 and 1 to the
      // first and last texel centres) -> (r, mu).
      glm::vec2 unit(x / (width - 1.0f), y / (height - 1.0f));
      glm::vec2 r_mu = twin::transmittance_r_mu_from_unit(atm, unit);
      const double r = r_mu.x, mu = r_mu.y;
      const double length = twin::distance_to_top(atm, static_cast<float>(r), static_cast<float>(mu));
      // The density peaks at the ray's lowest point (perigee, t = -r mu when the
      // ray first descends): integrate from there outwards on each side, with
      // samples spaced quadratically so they crowd where the air is thickest.
      const double perigee = std::clamp(-r * mu, 0.0, length);
      glm::dvec3 tau(0.0);
      auto integrate_from_perigee = [&](double end, int steps) {
        const double span = end - perigee;
        for (int i = 0; i < steps; ++i) {
          const double u = (i + 0.5) / steps;
          const double t = perigee + span * u * u;
          const double weight = std::abs(2.0 * span * u / steps);
          const double altitude = std::sqrt(r * r + t * t + 2.0 * r * mu * t) - bottom;
          tau += glm::dvec3(twin::extinction_at(atm, static_cast<float>(altitude))) * weight;
        }
      };
      const int before = perigee > 0.0 ? integration_steps / 2 : 0;
      integrate_from_perigee(0.0, before);
      integrate_from_perigee(length, integration_steps - before);
      table.texels[static_cast<size_t>(y) * width + x] = glm::vec3(glm::exp(-tau));
    }
    control.report((y + 1.0) / height);
  }
  return table;
}

twin::Lut2D compute_multiple_scattering_table(const twin::AtmosphereParameters& atm, const twin::Lut2D& transmittance,
                                              int width, int height, int directions, int steps,
                                              const TableBuildControl& control) {
  twin::Lut2D table;
  table.width = width;
  table.height = height;
  table.texels.resize(static_cast<size_t>(width) * height);
  const glm::vec2 t_size(transmittance.width, transmittance.height);
  for (int y = 0; y < height; ++y) {
    if (control.stopped()) return {};
    for (int x = 0; x < width; ++x) {
      // Texel centre -> (mu_s, r): the inverse of multiple_scattering_uv.
      float mu_s = x / (width - 1.0f) * 2.0f - 1.0f;
      float r = atm.bottom_radius_m + y / (height - 1.0f) * (atm.top_radius_m - atm.bottom_radius_m);
      r = std::max(r, atm.bottom_radius_m + 1.0f);  // just above the ground, so rays can leave
      table.texels[static_cast<size_t>(y) * width + x] =
          twin::multiple_scattering_texel(atm, transmittance, t_size, r, mu_s, directions, steps);
    }
    control.report((y + 1.0) / height);
  }
  return table;
}

ModelTables compute_model_tables(const AtmosphereSettings& settings, double bottom_radius_m) {
  ModelTables t;
  t.atmosphere = make_atmosphere_parameters(settings, bottom_radius_m, 1.0);
  t.transmittance = compute_transmittance_table(t.atmosphere, kTransmittanceWidth, kTransmittanceHeight);
  t.multiple_scattering = compute_multiple_scattering_table(t.atmosphere, t.transmittance);
  return t;
}

}  // namespace atmo::core
