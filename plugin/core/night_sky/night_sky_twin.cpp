#include "core/night_sky/night_sky_twin.h"

#include <algorithm>
#include <cmath>

#include "core/night_sky/star_photometry.h"

namespace atmo::core::night {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// Leinert et al. 1998: 1 S10 = 1.28 of his table units (background.cpp, zodiacal_s10).
constexpr double kZodiacalTableUnitsPerS10 = 1.28;
// Elongation margin of the zodiacal bound for refraction (0.6° at the horizon).
constexpr double kRefractionMarginRad = 1.0 * kDeg;

glm::dvec3 unit_or_up(const glm::dvec3& v) {
  const double l = glm::length(v);
  return l > 0.0 && std::isfinite(l) ? v / l : glm::dvec3(0.0, 0.0, 1.0);
}

// The background's clamps (background.cpp).
double clamped_altitude(double eye_altitude_m) { return std::max(eye_altitude_m, 0.0); }
double clamped_radius(double planet_radius_m) { return std::max(planet_radius_m, 1.0); }
double clamped_thickness(const BackgroundSettings& s) { return std::max(s.airglow_layer_thickness_m, 1.0); }

// The largest airglow slant factor over all rays (see the header).
double max_airglow_slant(double eye_altitude_m, double planet_radius_m, const BackgroundSettings& s) {
  const double radius = clamped_radius(planet_radius_m);
  const double thickness = clamped_thickness(s);
  const double r0 = radius + clamped_altitude(eye_altitude_m);
  const double inner = std::max(radius + s.airglow_layer_altitude_m - 0.5 * thickness, 0.0);
  const double outer = inner + thickness;
  auto chord = [](double a, double b) { return std::sqrt(std::max((a - b) * (a + b), 0.0)); };  // sqrt(a^2 - b^2)
  double path = 0.0;
  if (r0 <= inner)
    path = chord(outer, r0) - chord(inner, r0);  // the horizontal ray
  else if (r0 <= outer)
    path = chord(r0, inner) + chord(outer, inner);  // down, grazing the inner sphere, and out
  else
    path = 2.0 * chord(outer, inner);  // in and out, grazing the inner sphere
  return path / thickness;
}

// The components' luminance bounds: airglow, zodiacal light, starlight + diffuse galactic + cosmic.
glm::dvec3 component_bounds(const glm::dmat3& icrs_from_enu, const glm::dvec3& sun_icrs, double eye_altitude_m,
                            double planet_radius_m, const BackgroundSettings& s) {
  const double airglow =
      std::max(luminance_from_s10(s.airglow_zenith_s10), 0.0) * max_airglow_slant(eye_altitude_m, planet_radius_m, s);
  // Smallest elongation of a direction above -dip from the Sun.
  const double radius = clamped_radius(planet_radius_m);
  const double dip = std::acos(radius / (radius + clamped_altitude(eye_altitude_m)));
  const glm::dvec3 sun_enu = glm::transpose(icrs_from_enu) * unit_or_up(sun_icrs);
  const double sun_elevation = std::asin(std::clamp(sun_enu.z / std::max(glm::length(sun_enu), 1e-300), -1.0, 1.0));
  const double min_elongation = std::max(-dip - sun_elevation - kRefractionMarginRad, 2.0 * kDeg);
  const double e = min_elongation / (90.0 * kDeg);
  const double zodiacal_units = std::max(-44.76 + 149.85 * std::pow(e, -2.459) + 171.0 + 67.28, 0.0);
  const double zodiacal =
      std::max(s.zodiacal_scale, 0.0) * zodiacal_units / kZodiacalTableUnitsPerS10 * luminance_from_s10(1.0);
  const double starlight_s10 =
      std::max(s.starlight_pole_s10, 0.0) +
      std::max(s.starlight_plane_excess_s10, 0.0) * (1.0 + std::abs(s.starlight_longitude_contrast));
  const double galactic = luminance_from_s10(starlight_s10) * (1.0 + std::max(s.diffuse_galactic_fraction, 0.0)) +
                          std::max(luminance_from_s10(s.cosmic_s10), 0.0);
  return {airglow, zodiacal, galactic};
}
}  // namespace

twin::MoonDisc make_moon_disc(const glm::dvec3& moon_enu, double angular_radius_rad, const glm::dvec3& moon_to_sun_enu,
                              const MoonDiscLighting& lighting) {
  constexpr double k = 2.0 / (3.0 * kPi);
  twin::MoonDisc m;
  m.direction = glm::vec3(unit_or_up(moon_enu));
  m.angular_radius_rad = static_cast<float>(std::isfinite(angular_radius_rad) ? std::max(angular_radius_rad, 0.0) : 0.0);
  m.to_sun = glm::vec3(unit_or_up(moon_to_sun_enu));
  m.sun_radiance = glm::vec3(k * lighting.sun_albedo_lux * lighting.sun_bs * lighting.color_rgb);
  m.earthshine_radiance = glm::vec3(k * 0.5 * lighting.earthshine_albedo_lux * lighting.earthshine_bs * lighting.color_rgb);
  return m;
}

glm::dvec3 moon_to_sun_direction(const glm::dvec3& sun_dir, double sun_distance, const glm::dvec3& moon_dir,
                                 double moon_distance) {
  return unit_or_up(unit_or_up(sun_dir) * sun_distance - unit_or_up(moon_dir) * moon_distance);
}

twin::NightBackground make_night_background(const glm::dmat3& icrs_from_enu, const glm::dvec3& sun_icrs,
                                           double eye_altitude_m, double planet_radius_m,
                                           const BackgroundSettings& s) {
  twin::NightBackground b;
  b.icrs_from_enu = glm::mat3(icrs_from_enu);
  b.sun_icrs = glm::vec3(unit_or_up(sun_icrs));
  b.eye_altitude_m = static_cast<float>(clamped_altitude(eye_altitude_m));
  b.planet_radius_m = static_cast<float>(clamped_radius(planet_radius_m));
  b.airglow_zenith_cd_m2 = static_cast<float>(luminance_from_s10(s.airglow_zenith_s10));
  b.airglow_layer_altitude_m = static_cast<float>(s.airglow_layer_altitude_m);
  b.airglow_layer_thickness_m = static_cast<float>(clamped_thickness(s));
  b.zodiacal_cd_m2_per_unit =
      static_cast<float>(s.zodiacal_scale * luminance_from_s10(1.0) / kZodiacalTableUnitsPerS10);
  b.starlight_pole_cd_m2 = static_cast<float>(luminance_from_s10(s.starlight_pole_s10));
  b.starlight_plane_excess_cd_m2 = static_cast<float>(luminance_from_s10(s.starlight_plane_excess_s10));
  b.starlight_width_sin_b = static_cast<float>(std::max(s.starlight_width_sin_b, 1e-3));
  b.starlight_longitude_contrast = static_cast<float>(s.starlight_longitude_contrast);
  b.diffuse_galactic_fraction = static_cast<float>(s.diffuse_galactic_fraction);
  b.cosmic_cd_m2 = static_cast<float>(luminance_from_s10(s.cosmic_s10));
  b.airglow_rgb = glm::vec3(airglow_color_rgb());
  b.zodiacal_rgb = glm::vec3(zodiacal_color_rgb());
  b.starlight_rgb = glm::vec3(starlight_color_rgb());
  return b;
}

double night_background_max_luminance(const glm::dmat3& icrs_from_enu, const glm::dvec3& sun_icrs,
                                      double eye_altitude_m, double planet_radius_m, const BackgroundSettings& s) {
  const glm::dvec3 c = component_bounds(icrs_from_enu, sun_icrs, eye_altitude_m, planet_radius_m, s);
  return c.x + c.y + c.z;
}

glm::dvec3 night_background_max_rgb(const glm::dmat3& icrs_from_enu, const glm::dvec3& sun_icrs,
                                    double eye_altitude_m, double planet_radius_m, const BackgroundSettings& s) {
  const glm::dvec3 c = component_bounds(icrs_from_enu, sun_icrs, eye_altitude_m, planet_radius_m, s);
  return c.x * airglow_color_rgb() + c.y * zodiacal_color_rgb() + c.z * starlight_color_rgb();
}

}  // namespace atmo::core::night
