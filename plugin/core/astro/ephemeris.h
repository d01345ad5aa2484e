// ephemeris.h — topocentric apparent places of the Sun, the Moon, the planets
// and catalog stars for an observer at a time: azimuth, elevation with and
// without refraction, distance, apparent RA/Dec, magnitude, phase, the
// Moon's bright limb.
//
// One AstrometryFrame per rendered frame holds ERFA's astrometry context for
// the observer (eraApco: the observer's barycentric position and velocity,
// diurnal aberration included; bias-precession-nutation IAU 2006/2000A; Earth
// rotation angle from UT1; polar motion). Then, per body:
//   solar-system body: its barycentric position at t - tau (light time from
//     the observer, iterated) minus the observer's (so the Moon's ~1°
//     parallax is exact), light deflection by the Sun for the body's real
//     distance (eraLd), aberration (eraAb), BPN -> CIRS;
//   star: eraAtciq (proper motion, parallax, deflection, aberration, BPN);
//   then CIRS -> local east-north-up by one rotation (Earth rotation angle,
//   polar motion, longitude, latitude; built from eraAtioq), and refraction
//   (core/astro/refraction.h) for display.
// Azimuth: from north through east. Angles in radians, distances in metres.
// docs/EPHEMERIS.md: models, measured errors, conventions.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "core/astro/observer.h"
#include "core/astro/refraction.h"
#include "core/astro/solar_system.h"
#include "core/astro/star_catalog.h"
#include "core/astro/time_scales.h"

namespace atmo::core::astro {

struct EphemerisOptions {
  bool refraction = true;                               // false: refracted == unrefracted
  std::optional<RefractionConditions> conditions;       // default: standard atmosphere at the observer's height
  double polar_motion_x_rad = 0.0;                      // IERS xp, yp (|.| <= 1")
  double polar_motion_y_rad = 0.0;
};

// A topocentric apparent direction.
struct SkyDirection {
  double azimuth_rad = 0.0;              // from north through east, [0, 2 pi)
  double elevation_rad = 0.0;            // unrefracted (geometric + aberration + deflection)
  double elevation_refracted_rad = 0.0;  // as seen through the air: for display
  double ra_cirs_rad = 0.0;              // right ascension from the CIO, [0, 2 pi)
  double ra_equinox_rad = 0.0;           // from the true equinox of date: ra_cirs - eo
  double dec_rad = 0.0;                  // declination, true equator of date
  double hour_angle_rad = 0.0;           // local apparent hour angle, (-pi, pi]
  glm::dvec3 enu{0.0, 0.0, 1.0};               // unit vector, refracted (east, north, up)
  glm::dvec3 enu_unrefracted{0.0, 0.0, 1.0};   // unit vector, unrefracted
};

struct BodyEphemeris {
  Body body = Body::kSun;
  SkyDirection direction;
  double distance_m = 0.0;              // observer -> body at light emission
  double light_time_s = 0.0;
  double sun_distance_m = 0.0;          // body -> Sun (0 for the Sun)
  double phase_angle_rad = 0.0;         // Sun-body-observer (0 for the Sun)
  double illuminated_fraction = 1.0;    // lit fraction of the disc's area
  double apparent_magnitude = 0.0;      // V
  double angular_radius_rad = 0.0;      // apparent semi-diameter (equatorial for planets)
  double saturn_ring_tilt_rad = 0.0;    // observer's latitude above the ring plane (Saturn only)
  // Orientation of the lit side (meaningful for the Moon and the inner planets):
  double bright_limb_position_angle_rad = 0.0;  // chi: from the disc's north point through east (Meeus 48.5)
  double parallactic_angle_rad = 0.0;           // q: position angle of the zenith
  double bright_limb_zenith_angle_rad = 0.0;    // chi - q in [0, 2 pi): from "up" on the disc, counterclockwise
                                                // as the observer sees the sky
  glm::dvec3 bright_limb_enu{0.0, 0.0, 1.0};    // unit vector across the disc toward the bright limb (ENU)
};

// A star's catalog astrometry at epoch J2000.0 (ICRS).
struct StarAstrometry {
  double ra_rad = 0.0;
  double dec_rad = 0.0;
  double pm_ra_rad_per_year = 0.0;   // dRA/dt (not multiplied by cos dec)
  double pm_dec_rad_per_year = 0.0;
  double parallax_arcsec = 0.0;
  double radial_velocity_km_s = 0.0;
};

inline StarAstrometry star_astrometry(const CatalogStar& c) {
  StarAstrometry s;
  s.ra_rad = c.ra_rad;
  s.dec_rad = c.dec_rad;
  s.pm_ra_rad_per_year = c.pm_ra_rad_per_year;
  s.pm_dec_rad_per_year = c.pm_dec_rad_per_year;
  s.parallax_arcsec = c.parallax_arcsec;
  return s;
}

class AstrometryFrame {
 public:
  // nullopt + message on invalid options (refraction conditions, polar motion).
  static std::optional<AstrometryFrame> create(const TimeScales& time, const Observer& observer,
                                               const EphemerisOptions& options, std::string* error);

  const TimeScales& time() const;
  const Observer& observer() const;
  const RefractionConditions& conditions() const;  // those used (also when refraction is off)
  bool refraction_enabled() const;
  double equation_of_origins_rad() const;  // eo = ERA - GST: ra_equinox = ra_cirs - eo
  double earth_rotation_angle_rad() const;
  // Notes on degraded accuracy (time scale extrapolated, outside 1900-2100).
  const std::string& notes() const;

  BodyEphemeris body(Body b) const;
  std::array<BodyEphemeris, kBodyCount> bodies() const;

  // Stars: the full result, one or many (the context is shared: ~1 µs a star).
  SkyDirection star(const StarAstrometry& s) const;
  void stars(const StarAstrometry* s, std::size_t n, SkyDirection* out) const;
  // The cheaper split for renderers: CIRS unit vectors change slowly (cache
  // them for minutes); enu_from_cirs() changes every frame.
  glm::dvec3 star_cirs(const StarAstrometry& s) const;
  glm::dmat3 enu_from_cirs() const;
  SkyDirection direction_from_cirs(const glm::dvec3& cirs_unit) const;
  double refraction_rad(double unrefracted_elevation_rad) const;

 private:
  struct Impl;
  explicit AstrometryFrame(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<const Impl> impl_;
};

}  // namespace atmo::core::astro
