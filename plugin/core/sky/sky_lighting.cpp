#include "core/sky/sky_lighting.h"

#include <cmath>

#include "core/shadows/sh.h"

namespace atmo::core {

namespace {
// Convolution of radiance SH with the clamped cosine: A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4.
constexpr double kCosineLobe[9] = {M_PI, 2.0 * M_PI / 3.0, 2.0 * M_PI / 3.0, 2.0 * M_PI / 3.0, M_PI / 4.0,
                                   M_PI / 4.0, M_PI / 4.0, M_PI / 4.0, M_PI / 4.0};
}  // namespace

std::array<double, 9> sh9_basis(const glm::dvec3& n) {
  const double x = n.x, y = n.y, z = n.z;
  return {0.282095,         0.488603 * y,     0.488603 * z,
          0.488603 * x,     1.092548 * x * y, 1.092548 * y * z,
          0.315392 * (3.0 * z * z - 1.0), 1.092548 * x * z, 0.546274 * (x * x - y * y)};
}

glm::dvec3 sh9_irradiance(const std::array<glm::dvec3, 9>& e, const glm::dvec3& n) {
  std::array<double, 9> y = sh9_basis(n);
  glm::dvec3 sum(0.0);
  for (int k = 0; k < 9; ++k) sum += e[k] * y[k];
  return sum;
}

SkyLighting compute_sky_lighting(const Scene& scene, const twin::Lut2D& transmittance,
                                 const twin::Lut2D& multiple_scattering, int zenith_bands, int azimuths, int steps) {
  const glm::vec2 t_size(transmittance.width, transmittance.height);
  const glm::vec2 ms_size(multiple_scattering.width, multiple_scattering.height);
  const glm::vec3 sun(scene.sun_direction_enu);
  const float altitude = static_cast<float>(scene.eye_altitude_m);
  const int count = zenith_bands * azimuths;
  const double solid_angle = 4.0 * M_PI / count;  // equal-area cells: uniform in cos(theta) and phi

  SkyLighting out;
  std::array<glm::dvec3, 9> radiance_sh{};
  glm::dvec3 upper_sum(0.0), horizontal(0.0);
  int upper_count = 0;
  for (int b = 0; b < zenith_bands; ++b) {
    const double z = 1.0 - 2.0 * (b + 0.5) / zenith_bands;
    const double ring = std::sqrt(std::max(0.0, 1.0 - z * z));
    for (int a = 0; a < azimuths; ++a) {
      // Rings are staggered by half a cell so no azimuth is favoured.
      const double phi = 2.0 * M_PI * (a + 0.5 * (b % 2)) / azimuths;
      const glm::dvec3 n(ring * std::cos(phi), ring * std::sin(phi), z);
      const twin::SkyRadiance r = twin::sky_radiance_parts(scene.atmosphere, transmittance, t_size,
                                                          multiple_scattering, ms_size, altitude, glm::vec3(n), sun,
                                                          steps);
      const glm::dvec3 radiance(r.diffuse);
      const std::array<double, 9> y = sh9_basis(n);
      for (int k = 0; k < 9; ++k) radiance_sh[k] += radiance * (y[k] * solid_angle);
      const std::vector<double> y16 = shadows::sh_basis(4, n);
      for (int k = 0; k < 16; ++k) out.radiance_sh16[k] += radiance * (y16[k] * solid_angle);
      if (z > 0.0) {
        horizontal += radiance * (z * solid_angle);
        upper_sum += radiance;
        ++upper_count;
      }
    }
  }
  for (int k = 0; k < 9; ++k) out.irradiance_sh9[k] = radiance_sh[k] * kCosineLobe[k];
  // Directly from the samples: the SH ring at the horizon's step would bias it.
  out.horizontal_illuminance_lux = horizontal;
  out.average_radiance = upper_count ? upper_sum / static_cast<double>(upper_count) : glm::dvec3(0.0);
  return out;
}

}  // namespace atmo::core
