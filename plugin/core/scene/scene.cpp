#include "core/scene/scene.h"

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

BodyIlluminance body_illuminance(const Scene& scene, const twin::Lut2D& transmittance, double altitude_m) {
  const twin::AtmosphereParameters& atm = scene.atmosphere;
  const float r = atm.bottom_radius_m + static_cast<float>(altitude_m);
  const glm::vec2 size(transmittance.width, transmittance.height);
  const glm::vec3 sun_t =
      twin::transmittance_to_sun(atm, transmittance, size, r, static_cast<float>(scene.sun_direction_enu.z));
  const glm::vec3 moon_t =
      twin::transmittance_to_sun(atm, transmittance, size, r, static_cast<float>(scene.bodies.moon_enu.z));
  BodyIlluminance b;
  for (int i = 0; i < 3; ++i) {
    b.sun_lux[i] = static_cast<double>(atm.sun_illuminance_lux[i] * sun_t[i]);
    b.moon_lux[i] = scene.bodies.moon_illuminance_rgb_lux[i] * static_cast<double>(moon_t[i]);
  }
  return b;
}

Scene make_scene(const AtmosphereSettings& settings, double utc_posix_s, double dut1_s, const EyeFrame& eye) {
  std::string error;
  std::optional<SkyBodies> bodies = compute_sky_bodies(utc_posix_s, dut1_s, eye.eye, &error);
  if (!bodies) throw std::invalid_argument("make_scene: the ephemeris refused the time or the eye: " + error);
  return make_scene(settings, *bodies, eye);
}

}  // namespace atmo::core
