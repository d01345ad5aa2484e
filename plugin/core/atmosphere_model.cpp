#include "core/atmosphere_model.h"

#include <algorithm>
#include <cmath>

namespace atmo::core {

namespace {
const glm::dvec3 kWavelengthsNm(680.0, 550.0, 440.0);
const glm::dvec3 kRayleighScattering(5.802e-6, 13.558e-6, 33.1e-6);
const glm::dvec3 kOzoneAbsorption(0.650e-6, 1.881e-6, 0.085e-6);
constexpr double kAerosolSingleScatteringAlbedo = 0.9;
constexpr double kAngstromExponent = 1.3;
constexpr double kMinAerosolExtinction = 2e-7;
}  // namespace

twin::AtmosphereParameters make_atmosphere_parameters(const AtmosphereSettings& s, double bottom_radius_m,
                                                      double sun_distance_au) {
  twin::AtmosphereParameters atm{};
  atm.bottom_radius_m = static_cast<float>(bottom_radius_m);
  atm.top_radius_m = static_cast<float>(bottom_radius_m + kAtmosphereThicknessM);
  atm.rayleigh_scattering = glm::vec3(kRayleighScattering);
  atm.rayleigh_scale_height_m = 8000.0f;

  const double total_550 = std::log(20.0) / s.visibility_m;
  const double aerosol_550 = std::max(total_550 - kRayleighScattering.y, kMinAerosolExtinction);
  glm::dvec3 aerosol_ext;
  for (int c = 0; c < 3; ++c) aerosol_ext[c] = aerosol_550 * std::pow(kWavelengthsNm[c] / 550.0, -kAngstromExponent);
  atm.mie_extinction = glm::vec3(aerosol_ext);
  atm.mie_scattering = glm::vec3(aerosol_ext * kAerosolSingleScatteringAlbedo);
  atm.mie_scale_height_m = static_cast<float>(s.aerosol_scale_height_m);
  atm.mie_g = 0.8f;

  atm.ozone_absorption = glm::vec3(kOzoneAbsorption);
  atm.ozone_center_m = 25000.0f;
  atm.ozone_half_width_m = 15000.0f;

  atm.sun_illuminance_lux = glm::vec3(static_cast<float>(kSunIlluminanceAt1AuLux / (sun_distance_au * sun_distance_au)));
  atm.sun_angular_radius = static_cast<float>(kSunAngularRadiusRad);
  atm.ground_albedo = glm::vec3(static_cast<float>(s.ground_albedo));
  return atm;
}

twin::Lut2D compute_transmittance_table(const twin::AtmosphereParameters& atm, int width,
                                                     int height, int integration_steps) {
  twin::Lut2D table;
  table.width = width;
  table.height = height;
  table.texels.resize(static_cast<size_t>(width) * height);
  const double bottom = atm.bottom_radius_m;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      // Texel centre -> unit coordinates (the lookup maps x_mu = 0 and 1 to the
      // first and last texel centres) -> (r, mu).
      glm::vec2 unit(x / (width - 1.0f), y / (height - 1.0f));
      glm::vec2 r_mu = twin::transmittance_r_mu_from_unit(atm, unit);
      const double r = r_mu.x, mu = r_mu.y;
      const double length = twin::distance_to_top(atm, static_cast<float>(r), static_cast<float>(mu));
      const double dt = length / integration_steps;
      glm::dvec3 tau(0.0);
      for (int i = 0; i < integration_steps; ++i) {
        double t = (i + 0.5) * dt;
        double ri = std::sqrt(r * r + t * t + 2.0 * r * mu * t);
        double altitude = ri - bottom;
        tau += glm::dvec3(twin::extinction_at(atm, static_cast<float>(altitude))) * dt;
      }
      table.texels[static_cast<size_t>(y) * width + x] = glm::vec3(glm::exp(-tau));
    }
  }
  return table;
}

twin::Lut2D compute_multiple_scattering_table(const twin::AtmosphereParameters& atm, const twin::Lut2D& transmittance,
                                              int size, int directions, int steps) {
  twin::Lut2D table;
  table.width = table.height = size;
  table.texels.resize(static_cast<size_t>(size) * size);
  const glm::vec2 t_size(transmittance.width, transmittance.height);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      // Texel centre -> (mu_s, r): the inverse of multiple_scattering_uv.
      float mu_s = x / (size - 1.0f) * 2.0f - 1.0f;
      float r = atm.bottom_radius_m + y / (size - 1.0f) * (atm.top_radius_m - atm.bottom_radius_m);
      r = std::max(r, atm.bottom_radius_m + 1.0f);  // just above the ground, so rays can leave
      table.texels[static_cast<size_t>(y) * size + x] =
          twin::multiple_scattering_texel(atm, transmittance, t_size, r, mu_s, directions, steps);
    }
  }
  return table;
}

}  // namespace atmo::core
