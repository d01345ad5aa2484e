#include "core/sky/sky_view_table.h"

namespace atmo::core {

twin::Lut2D compute_sky_view_table(const twin::AtmosphereParameters& atm, const twin::Lut2D& transmittance,
                                   const twin::Lut2D& multiple_scattering, float eye_altitude_m,
                                   float sin_sun_elevation, int width, int height, int steps) {
  twin::Lut2D table;
  table.width = width;
  table.height = height;
  table.texels.resize(static_cast<size_t>(width) * height);
  const glm::vec2 t_size(transmittance.width, transmittance.height);
  const glm::vec2 ms_size(multiple_scattering.width, multiple_scattering.height);
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      const glm::vec2 x(static_cast<float>(i) / static_cast<float>(width - 1),
                        static_cast<float>(j) / static_cast<float>(height - 1));
      table.texels[static_cast<size_t>(j) * width + i] =
          twin::sky_view_texel(atm, transmittance, t_size, multiple_scattering, ms_size, eye_altitude_m, x,
                               sin_sun_elevation, steps);
    }
  }
  return table;
}

glm::vec3 sky_radiance_from_table(const twin::AtmosphereParameters& atm, const twin::Lut2D& transmittance,
                                  const twin::Lut2D& sky_view, float eye_altitude_m, const glm::vec3& dir,
                                  const glm::vec3& sun_dir) {
  const glm::vec2 size(sky_view.width, sky_view.height);
  const glm::vec3 diffuse = twin::sample_lut(sky_view, twin::sky_view_uv(atm, eye_altitude_m, dir, sun_dir, size));
  return twin::sky_radiance_with_sun(atm, transmittance, glm::vec2(transmittance.width, transmittance.height), diffuse,
                                     eye_altitude_m, dir, sun_dir);
}

}  // namespace atmo::core
