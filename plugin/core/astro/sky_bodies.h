// sky_bodies.h — the Sun and the Moon as the sky layers and the host's
// lighting need them, at an eye and a time: apparent (refracted) directions in
// east-north-up, distances, the Moon's phase and its light. From the
// ephemeris core (core/astro: ERFA + ELP 2000-82B), which costs about
// 0.3 ms per call; SkyBodiesCache reuses a result while it is good to 1.5".
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <string>

#include "core/geo/geodesy.h"

namespace atmo::core {

struct SkyBodies {
  // Apparent directions as seen through the air (refraction included, faded
  // out below the horizon), unit vectors, ENU at the eye.
  glm::dvec3 sun_enu{0.0, 0.0, 1.0};
  glm::dvec3 moon_enu{0.0, 0.0, 1.0};
  // The same without refraction (what the cache keeps: refraction depends on
  // the eye's height through the horizon's dip, so it is applied per call).
  glm::dvec3 sun_enu_unrefracted{0.0, 0.0, 1.0};
  glm::dvec3 moon_enu_unrefracted{0.0, 0.0, 1.0};
  double sun_distance_au = 1.0;            // eye -> Sun
  double moon_distance_m = 384400e3;       // eye -> Moon (topocentric)
  double moon_sun_distance_au = 1.0;       // Moon -> Sun
  double moon_phase_angle_rad = 0.0;       // Sun-Moon-eye
  double moon_illuminated_fraction = 1.0;
  double moon_angular_radius_rad = 0.0;    // topocentric semi-diameter
  double moon_bright_limb_zenith_angle_rad = 0.0;  // the lit limb's angle from "up" on the disc
  // The Moon's illuminance on a surface facing it, outside the atmosphere
  // (lux, linear sRGB): sunlit part (Krisciunas & Schaefer phase law) plus
  // earthshine (core/night_sky/moon_photometry.h).
  glm::dvec3 moon_illuminance_rgb_lux{0.0};
  std::string note;  // empty, or how the time was modelled (before 1960, after 2100)
};

// nullopt + *error for inputs the time scales or the observer reject
// (non-finite time, |dut1| > 0.9 s, latitude out of range).
std::optional<SkyBodies> compute_sky_bodies(double utc_posix_s, double dut1_s, const Geodetic& eye,
                                            std::string* error);

// Sets sun_enu and moon_enu from the unrefracted directions for an eye at
// height_m (standard atmosphere; core/astro/refraction.h).
void apply_refraction(SkyBodies* bodies, double height_m);

// Reuses the last unrefracted result while it stays within 1.5" of the truth:
// the sky turns 15"/s, so for 0.1 s of simulated time; the Moon's parallax
// moves 0.5" per km, so for 100 m of eye movement. Refraction is applied for
// the eye's height on every call. At 60 Hz the ephemeris runs every sixth
// frame.
class SkyBodiesCache {
 public:
  static constexpr double kMaxAgeS = 0.1;
  static constexpr double kMaxMoveM = 100.0;

  // Throws nothing; returns nullopt (and *error) as compute_sky_bodies does.
  std::optional<SkyBodies> get(double utc_posix_s, double dut1_s, const Geodetic& eye, const glm::dvec3& eye_ecef_m,
                               std::string* error);
  uint64_t computations() const { return computations_; }

 private:
  bool valid_ = false;
  double utc_posix_s_ = 0.0, dut1_s_ = 0.0;
  glm::dvec3 eye_ecef_m_{0.0};
  SkyBodies bodies_;
  uint64_t computations_ = 0;
};

}  // namespace atmo::core
