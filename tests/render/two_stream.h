#pragma once
// Shared by the cloud scenarios' physics checks (overcast_low_sun_test.cpp,
// cloud_scenarios_test.cpp): reading a scenario and its render, and the
// diffusion two-stream estimate of a cloud layer's base seen from below.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "atmo/atmo.h"
#include "atmo_scenario/scenario.h"
#include "atmo_support/image.h"
#include "core/clouds/procedural_clouds.h"

namespace atmo::test_render {

inline scenario::Scenario load(const char* path) {
  const auto r = scenario::load_scenario_file(path);
  if (!r.scenario) throw std::runtime_error(r.error);
  return *r.scenario;
}

inline support::Image render_of(const std::string& stem, const std::string& camera) {
  support::Image img;
  std::string error;
  if (!support::read_exr(stem + "_" + camera + ".exr", &img, &error)) throw std::runtime_error(error);
  return img;
}

inline size_t camera_index(const scenario::Scenario& s, const std::string& name) {
  for (size_t i = 0; i < s.cameras.size(); ++i)
    if (s.cameras[i].name == name) return i;
  throw std::runtime_error("no camera " + name);
}

// Pixels from the image's centre (the camera's axis) to pixel (x, y)'s centre.
inline double from_centre(const support::Image& img, int x, int y) {
  return std::hypot(x + 0.5 - 0.5 * img.width, y + 0.5 - 0.5 * img.height);
}

// The mean linear colour (cd/m^2 per channel) within `deg` of the image's centre.
inline glm::dvec3 mean_within(const support::Image& img, const scenario::Camera& cam, double deg) {
  const double pixels_per_deg = cam.height / cam.vertical_fov_deg;
  glm::dvec3 sum(0.0);
  int n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (from_centre(img, x, y) <= deg * pixels_per_deg) {
        const float* c = img.pixel(x, y);
        sum += glm::dvec3(c[0], c[1], c[2]);
        ++n;
      }
  return sum / double(std::max(n, 1));
}

struct ColumnTransmission {
  double tau_mean = 0.0;  // the columns' mean vertical optical depth
  double diffuse = 0.0;   // their mean diffuse transmission
};

// Columns within `radius_m` of the eye (100 m apart), marched in 2 m steps:
// the diffuse transmission of a thick conservative slab, 1 / (1 + 0.75 (1 - g)
// tau) (g 0.85; shaders/atmosphere/functions.glsl cloud_diffuse_transmission).
inline ColumnTransmission column_transmission(const clouds::CloudField& field, double base_m, double top_m,
                                              double radius_m) {
  const double extinction = field.prototypes.at(0).optics.extinction_per_m;
  ColumnTransmission out;
  int columns = 0;
  for (double x = -radius_m; x <= radius_m; x += 100.0)
    for (double y = -radius_m; y <= radius_m; y += 100.0, ++columns) {
      double tau = 0.0;
      for (double z = base_m - 20.0; z < top_m + 20.0; z += 2.0)
        tau += clouds::field_density_at(field, glm::dvec3(x, y, z + 1.0)) * 2.0 * extinction;
      out.tau_mean += tau;
      out.diffuse += 1.0 / (1.0 + 0.75 * (1.0 - 0.85) * tau);
    }
  out.tau_mean /= columns;
  out.diffuse /= columns;
  return out;
}

// The illuminance under a layer of diffuse transmission `t` (lx, on the
// horizontal), lit by `above` (get_lighting without clouds at the top).
// Diffusion theory for a thick conservative slab (e.g. Bohren 1987): a beam
// at mu0 passes u(mu0) = (3/7)(1 + 2 mu0) times the diffuse transmission. The
// ground (albedo a) sends back a share of it, which the layer reflects
// (1 - T) down again: 1 / (1 - a (1 - T)) more.
inline double below_layer_lux(const AtmoLighting& above, double albedo, double t) {
  const double mu0 = std::sin(above.sun_elevation_rad);
  const double u0 = 3.0 / 7.0 * (1.0 + 2.0 * mu0);
  return (above.sun_illuminance_lux[1] * mu0 * u0 + above.sky_illuminance_horizontal_lux[1]) * t /
         (1.0 - albedo * (1.0 - t));
}

// The base's luminance at the zenith (cd/m^2): the light leaves the base with
// radiance (E / pi) u(mu) (u averages 1 over the hemisphere's cosine weight),
// so the zenith reads u(1) = 9/7 of E / pi.
inline double zenith_base_luminance(const AtmoLighting& above, double albedo, double t) {
  return 9.0 / 7.0 * below_layer_lux(above, albedo, t) / 3.14159265358979323846;
}

}  // namespace atmo::test_render
