#include "core/scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace atmo::core {

Scene make_scene(const AtmosphereSettings& settings, const SkyBodies& bodies, const EyeFrame& eye) {
  Scene s;
  s.sphere_radius_m =
      std::round(local_earth_radius_m(eye.eye.latitude_deg) / kSphereRadiusQuantumM) * kSphereRadiusQuantumM;
  s.atmosphere = make_atmosphere_parameters(settings, s.sphere_radius_m, bodies.sun_distance_au);
  s.sun_direction_enu = bodies.sun_enu;
  s.sun_direction_ecef = eye.ecef_from_enu * bodies.sun_enu;
  s.eye_altitude_m = std::max(eye.eye.height_m, 1.0);
  s.bodies = bodies;
  return s;
}

Scene make_scene(const AtmosphereSettings& settings, double utc_posix_s, double dut1_s, const EyeFrame& eye) {
  std::string error;
  std::optional<SkyBodies> bodies = compute_sky_bodies(utc_posix_s, dut1_s, eye.eye, &error);
  if (!bodies) throw std::invalid_argument("make_scene: the ephemeris refused the time or the eye: " + error);
  return make_scene(settings, *bodies, eye);
}

}  // namespace atmo::core
