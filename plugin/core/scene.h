// scene.h — the per-view numbers every pass needs, from the world state and
// the eye: atmosphere parameters on the sphere under the eye, the sun in ENU
// at the eye and the eye's altitude. Pure; the GL passes and the CPU twin
// tests call the same function.
#pragma once

#include "core/atmosphere_model.h"
#include "core/eye_frame.h"

namespace atmo::core {

struct Scene {
  twin::AtmosphereParameters atmosphere;
  double sphere_radius_m = 0.0;              // model sphere (rounded local WGS84 radius)
  glm::dvec3 sun_direction_ecef{0.0, 0.0, 1.0};
  glm::dvec3 sun_direction_enu{0.0, 0.0, 1.0};
  double eye_altitude_m = 1.0;               // above the sphere, clamped to >= 1 m
};

// The sphere radius is rounded to 10 km (0.16 %) so channels at nearby
// latitudes share one transmittance table.
constexpr double kSphereRadiusQuantumM = 10000.0;

Scene make_scene(const AtmosphereSettings& settings, double utc_posix_s, double dut1_s, const EyeFrame& eye);

}  // namespace atmo::core
