#include "core/astro/sky_bodies.h"

#include <algorithm>
#include <cmath>

#include "core/astro/ephemeris.h"
#include "core/night_sky/moon_photometry.h"

namespace atmo::core {

namespace {

glm::dvec3 refracted(const glm::dvec3& d, const astro::RefractionModel& model) {
  const double e = std::asin(std::clamp(d.z, -1.0, 1.0));
  const double e_seen = e + astro::refraction_rad(model, e);
  const double horizontal = std::hypot(d.x, d.y);
  if (horizontal < 1e-12) return d;  // at the zenith or nadir: nothing to lift
  const double c = std::cos(e_seen) / horizontal;
  return glm::dvec3(d.x * c, d.y * c, std::sin(e_seen));
}

}  // namespace

void apply_refraction(SkyBodies* b, double height_m) {
  const astro::RefractionModel model =
      astro::make_refraction_model(astro::standard_refraction_conditions(height_m), height_m);
  b->sun_enu = refracted(b->sun_enu_unrefracted, model);
  b->moon_enu = refracted(b->moon_enu_unrefracted, model);
}

std::optional<SkyBodies> compute_sky_bodies(double utc_posix_s, double dut1_s, const Geodetic& eye,
                                            std::string* error) {
  astro::TimeScaleOptions time_options;
  time_options.dut1_s = dut1_s;
  std::optional<astro::TimeScales> time = astro::time_scales_from_posix(utc_posix_s, time_options, error);
  if (!time) return std::nullopt;
  std::optional<astro::Observer> observer =
      astro::observer_from_geodetic(eye.latitude_deg, eye.longitude_deg, eye.height_m, error);
  if (!observer) return std::nullopt;
  std::optional<astro::AstrometryFrame> frame = astro::AstrometryFrame::create(*time, *observer, {}, error);
  if (!frame) return std::nullopt;

  const astro::BodyEphemeris sun = frame->body(astro::Body::kSun);
  const astro::BodyEphemeris moon = frame->body(astro::Body::kMoon);
  constexpr double kAu = 149597870700.0;
  SkyBodies b;
  b.sun_enu_unrefracted = sun.direction.enu_unrefracted;
  b.moon_enu_unrefracted = moon.direction.enu_unrefracted;
  b.sun_distance_au = sun.distance_m / kAu;
  b.moon_distance_m = moon.distance_m;
  b.moon_sun_distance_au = moon.sun_distance_m / kAu;
  b.moon_phase_angle_rad = moon.phase_angle_rad;
  b.moon_illuminated_fraction = moon.illuminated_fraction;
  b.moon_angular_radius_rad = moon.angular_radius_rad;
  b.moon_bright_limb_zenith_angle_rad = moon.bright_limb_zenith_angle_rad;
  const night::MoonIlluminance light =
      night::moon_illuminance(moon.phase_angle_rad, moon.distance_m, b.moon_sun_distance_au);
  b.moon_illuminance_rgb_lux = light.total() * night::moon_color_rgb();
  b.note = frame->notes();
  apply_refraction(&b, eye.height_m);  // the one refraction path, cached or not
  return b;
}

std::optional<SkyBodies> SkyBodiesCache::get(double utc_posix_s, double dut1_s, const Geodetic& eye,
                                             const glm::dvec3& eye_ecef_m, std::string* error) {
  if (valid_ && std::abs(utc_posix_s - utc_posix_s_) <= kMaxAgeS && dut1_s == dut1_s_ &&
      glm::length(eye_ecef_m - eye_ecef_m_) <= kMaxMoveM) {
    SkyBodies b = bodies_;
    apply_refraction(&b, eye.height_m);
    return b;
  }
  std::optional<SkyBodies> b = compute_sky_bodies(utc_posix_s, dut1_s, eye, error);
  if (!b) return std::nullopt;
  ++computations_;
  valid_ = true;
  utc_posix_s_ = utc_posix_s;
  dut1_s_ = dut1_s;
  eye_ecef_m_ = eye_ecef_m;
  bodies_ = *b;
  return b;
}

}  // namespace atmo::core
