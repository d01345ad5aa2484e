#include "core/scene.h"

#include <algorithm>
#include <cmath>

#include "core/solar_position.h"

namespace atmo::core {

Scene make_scene(const AtmosphereSettings& settings, double utc_posix_s, double dut1_s, const EyeFrame& eye) {
  Scene s;
  s.sphere_radius_m =
      std::round(local_earth_radius_m(eye.eye.latitude_deg) / kSphereRadiusQuantumM) * kSphereRadiusQuantumM;
  SunPosition sun = solar_position(utc_posix_s, dut1_s);
  s.atmosphere = make_atmosphere_parameters(settings, s.sphere_radius_m, sun.distance_au);
  s.sun_direction_ecef = sun.direction_ecef;
  s.sun_direction_enu = enu_from_ecef_direction(eye, sun.direction_ecef);
  s.eye_altitude_m = std::max(eye.eye.height_m, 1.0);
  return s;
}

}  // namespace atmo::core
