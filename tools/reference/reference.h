// reference.h — brute-force spectral sky radiance with multiple scattering,
// in double precision and without lookup tables, to check the real-time
// model. Method and figures: docs/REFERENCE.md.
//
// Frame: as shaders/atmosphere/functions.glsl, directions in the east-north-up
// axes at the eye, planet centre at (0, 0, -(bottom_radius + eye_altitude)).
// The sun is a point source (no disc, hard Earth shadow); the returned
// radiance excludes the directly transmitted sun.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/spectral/spectral_atmosphere.h"

namespace atmo::reference {

struct Settings {
  int view_steps = 64;            // quadrature nodes along the view ray
  int transmittance_steps = 64;   // nodes per optical-depth march (sun rays, path segments)
  int paths_per_step = 1;         // Monte Carlo paths per view-ray node, for orders >= 2
  int ground_paths = 16;          // Monte Carlo paths for the skylight on a visible ground point
  int max_scattering_order = 1000;  // 1: single scattering (and the sunlit ground) only
  std::uint64_t seed = 1;
};

struct Radiance {
  std::vector<double> spectral;       // W m^-2 sr^-1 nm^-1, per atmosphere wavelength
  std::vector<double> transmittance;  // from the eye to the end of the ray (ground or space)
  bool hits_ground = false;
  glm::dvec3 linear_srgb{0.0};        // Rec.709/D65 primaries scaled so luminance = 0.2126 R + 0.7152 G + 0.0722 B
  double luminance_cd_m2 = 0.0;
};

// `stream` selects an independent random sequence (e.g. the pixel index), so
// that results do not depend on evaluation order or thread count.
Radiance sky_radiance(const spectral::SpectralAtmosphere& atm, double eye_altitude_m, const glm::dvec3& view_dir_enu,
                      const glm::dvec3& sun_dir_enu, const Settings& settings, std::uint64_t stream = 0);

// Unit vector from heading (degrees clockwise from north) and elevation (degrees above the horizon).
glm::dvec3 enu_direction(double heading_deg, double elevation_deg);
// Camera rotation: view space (camera looks down -z, +y up) to ENU, like
// inverse(glm::lookAt(0, forward, up = +z)) for the given heading and pitch.
glm::dmat3 enu_from_view(double heading_deg, double pitch_deg);

struct Camera {
  glm::dmat3 enu_from_view{1.0};
  double vertical_fov_rad = 1.0471975511965976;  // 60°
  int width = 32;
  int height = 24;
};

struct Image {
  int width = 0;
  int height = 0;
  std::vector<glm::dvec3> linear_srgb;  // row 0 is the top row
  std::vector<double> luminance_cd_m2;
};

// Renders every pixel through its centre with sky_radiance (stream = pixel
// index), on `threads` std::threads; the result does not depend on `threads`.
Image render_image(const spectral::SpectralAtmosphere& atm, double eye_altitude_m, const Camera& camera,
                   const glm::dvec3& sun_dir_enu, const Settings& settings, int threads = 2);

}  // namespace atmo::reference
