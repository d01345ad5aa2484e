// occlusion_scenes.h — the configurations the sky-occlusion method is measured
// on against the ray-traced reference (tests/shadow_reference's accuracy test
// and bench/sky_occlusion_error_cost share them): one sphere at 10..70 degrees,
// many small spheres, intersecting spheres, a receiver under a wing, between
// two vehicles, near a wall. A configuration is spheres (object-relative
// world, z up, m) and receivers (position, unit normal); the sky is one
// analytic radiance function (cd/m^2) that the reference integrates as is and
// the method sees through its order-n SH projection.
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace atmo::shadow_reference {

struct Receiver {
  glm::dvec3 position_m;
  glm::dvec3 normal;
};

struct OcclusionConfig {
  std::string name;
  std::vector<glm::dvec4> spheres;  // centre, radius (one object)
  std::vector<Receiver> receivers;
};

std::vector<OcclusionConfig> occlusion_configs();

// A clear sky: brighter towards the zenith and the Sun's side; a dim ground below the horizon.
glm::dvec3 test_sky_radiance(const glm::dvec3& direction);
// Its projection to order `order` (order^2 coefficients), by quadrature on a fine grid.
std::vector<glm::dvec3> test_sky_sh(int order);

}  // namespace atmo::shadow_reference
