// sky_view_table.h — the LUT tier's sky-view table on the CPU: the same
// texels the GPU renders (shaders/sky_view_lut.frag through the shared
// sky_view_texel), and the same lookup the sky pass does. Tests compare the
// GPU with it, and the accuracy tool measures the LUT tier with it.
#pragma once

#include "core/atmosphere/shader_twin.h"

namespace atmo::core {

constexpr int kSkyViewWidth = 192;
constexpr int kSkyViewHeight = 108;  // even: the horizon is a row boundary

// Texel (i, j) is at unit coordinates (i / (width - 1), j / (height - 1)), as
// the GPU's fragment (i + 0.5, j + 0.5) of a width x height target.
twin::Lut2D compute_sky_view_table(const twin::AtmosphereParameters& atm, const twin::Lut2D& transmittance,
                                   const twin::Lut2D& multiple_scattering, float eye_altitude_m,
                                   float sin_sun_elevation, int width = kSkyViewWidth, int height = kSkyViewHeight,
                                   int steps = 32);

// Sky radiance (cd/m^2) along the ENU direction `dir` from the table, with
// the sun's disc added as the sky pass does.
glm::vec3 sky_radiance_from_table(const twin::AtmosphereParameters& atm, const twin::Lut2D& transmittance,
                                  const twin::Lut2D& sky_view, float eye_altitude_m, const glm::vec3& dir,
                                  const glm::vec3& sun_dir);

}  // namespace atmo::core
