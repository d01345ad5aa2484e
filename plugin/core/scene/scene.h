// scene.h — the per-view numbers every pass needs, from the world state and
// the eye: atmosphere parameters on the sphere under the eye, the Sun and the
// Moon in ENU at the eye (core/astro/sky_bodies.h) and the eye's altitude. Pure;
// the GL passes and the CPU twin tests call the same function.
#pragma once

#include "core/atmosphere/atmosphere_model.h"
#include "core/geo/eye_frame.h"
#include "core/astro/sky_bodies.h"

namespace atmo::core {

struct Scene {
  twin::AtmosphereParameters atmosphere;
  double sphere_radius_m = 0.0;              // model sphere (rounded local WGS84 radius)
  glm::dvec3 sun_direction_ecef{0.0, 0.0, 1.0};
  glm::dvec3 sun_direction_enu{0.0, 0.0, 1.0};
  double eye_altitude_m = 1.0;               // above the sphere, clamped to >= 1 m
  SkyBodies bodies;                          // the Sun and the Moon (sun_direction_* repeat its Sun)
};

// The sphere radius is rounded to 10 km (0.16 %) so channels at nearby
// latitudes share one transmittance table.
constexpr double kSphereRadiusQuantumM = 10000.0;

Scene make_scene(const AtmosphereSettings& settings, const SkyBodies& bodies, const EyeFrame& eye);

// The same with the bodies computed here (uncached; ~0.3 ms). Throws
// std::invalid_argument, naming the ephemeris's reason, for a time or an eye
// outside its ranges (core/astro/time_scales.h, core/astro/observer.h): there
// is no low-precision stand-in.
Scene make_scene(const AtmosphereSettings& settings, double utc_posix_s, double dut1_s, const EyeFrame& eye);

// The Sun's and the Moon's illuminance after the air at an altitude (above
// the model sphere, along the eye's zenith), lux per channel: the
// transmittance table along each direction (0 where the ray meets the Earth).
struct BodyIlluminance {
  glm::dvec3 sun_lux{0.0};
  glm::dvec3 moon_lux{0.0};
};
BodyIlluminance body_illuminance(const Scene& scene, const twin::Lut2D& transmittance, double altitude_m);

}  // namespace atmo::core
