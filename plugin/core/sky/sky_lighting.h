// sky_lighting.h — the sky as a light for the host's own shading: irradiance
// from the whole sky (sun excluded; it is a separate directional light) as 9
// spherical-harmonic coefficients (Ramamoorthi & Hanrahan 2001), plus the sky's
// average radiance and its illuminance on an upward-facing surface.
//
// Axes: ENU at the eye (x = east, y = north, z = up). Real SH, index k:
//   0: Y00 = 0.282095
//   1: Y1-1 = 0.488603 y     2: Y10 = 0.488603 z     3: Y11 = 0.488603 x
//   4: Y2-2 = 1.092548 xy    5: Y2-1 = 1.092548 yz   6: Y20 = 0.315392 (3z^2 - 1)
//   7: Y21 = 1.092548 xz     8: Y22 = 0.546274 (x^2 - y^2)
// Irradiance on a surface with unit normal n: E(n) = sum_k E_k Y_k(n), lux.
#pragma once

#include <array>
#include <glm/glm.hpp>

#include "core/scene/scene.h"

namespace atmo::core {

struct SkyLighting {
  std::array<glm::dvec3, 9> irradiance_sh9{};  // E_k, lux, linear RGB
  glm::dvec3 horizontal_illuminance_lux{0.0};   // E(up), sky only, by direct quadrature (not through the SH)
  glm::dvec3 average_radiance{0.0};             // cd/m^2, mean over the upper hemisphere, sky only
  // The radiance itself to order 4 (16 coefficients, core/shadows/sh.h's basis, cd/m^2, ENU), for the sky's
  // occlusion by the host's objects (atmo_sky_occlusion.glsl).
  std::array<glm::dvec3, 16> radiance_sh16{};
};

// The 9 basis functions at a unit direction.
std::array<double, 9> sh9_basis(const glm::dvec3& n);

// E(n) from irradiance coefficients.
glm::dvec3 sh9_irradiance(const std::array<glm::dvec3, 9>& irradiance_sh9, const glm::dvec3& n);

// Projects the diffuse sky (and the ground seen through the air, below the
// horizon) of `scene` on the sphere with an equal-area grid of
// `zenith_bands` x `azimuths` directions, each integrated with `steps` samples.
SkyLighting compute_sky_lighting(const Scene& scene, const twin::Lut2D& transmittance,
                                 const twin::Lut2D& multiple_scattering, int zenith_bands = 16, int azimuths = 32,
                                 int steps = 16);

}  // namespace atmo::core
