#include "core/night_sky/moon_photometry.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/atmosphere/atmosphere_model.h"
#include "core/night_sky/star_photometry.h"
#include "core/spectral/colorimetry.h"
#include "core/spectral/spectral_atmosphere.h"

namespace atmo::core::night {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kEndGuardRad = 1e-6;

double clamp_phase(double phase_rad) { return std::clamp(std::abs(phase_rad), 0.0, kPi); }

// The Sun's illuminance at the Moon, lux (distances below 0.001 au are taken as 0.001 au).
double sun_at(double sun_distance_au) {
  const double r = std::max(sun_distance_au, 1e-3);
  return sun_illuminance_at_1au_lux() / (r * r);
}

// (r_m / d)^2: the solid angle of the disc over pi.
double disc_factor(double observer_distance_m) {
  const double d = std::max(observer_distance_m, 2.0 * kMoonRadiusM);
  return (kMoonRadiusM / d) * (kMoonRadiusM / d);
}

// Jensen's reddening ramp, relative albedo: 0.70 at 340 nm to 1.35 at 740 nm, constant beyond.
double lunar_ramp(double wavelength_nm) {
  const double a = std::clamp((wavelength_nm - 340.0) / (740.0 - 340.0), 0.0, 1.0);
  return 0.70 + (1.35 - 0.70) * a;
}

// E_Hapke(phi) of the sunlit part for C = 1 at the mean distance and 1 au, lux.
double hapke_sun_unit_albedo(double phase_rad) {
  const double p = clamp_phase(phase_rad);
  return disc_factor(kMoonMeanDistanceM) / 3.0 * hapke_retrodirective(p) * hapke_scattering(p) *
         lommel_seeliger_phase(p) * sun_illuminance_at_1au_lux();
}
}  // namespace

double lommel_seeliger_phase(double phase_rad) {
  const double p = clamp_phase(phase_rad);
  if (p < kEndGuardRad) return 1.0;
  if (p > kPi - kEndGuardRad) return 0.0;
  const double v = 1.0 - std::sin(0.5 * p) * std::tan(0.5 * p) * std::log(1.0 / std::tan(0.25 * p));
  return std::clamp(v, 0.0, 1.0);
}

double hapke_retrodirective(double phase_rad, double g) {
  const double p = clamp_phase(phase_rad);
  if (p >= 0.5 * kPi) return 1.0;
  const double tan_p = std::tan(p);
  if (tan_p < 1e-9) return 2.0;  // g / tan(phi) -> inf: the limit
  const double x = g / tan_p;
  const double e = std::exp(-x);
  // (1 - e^-x) by expm1: exact as x -> 0 (phi -> pi/2), where B -> 1.
  const double b = 2.0 - tan_p / (2.0 * g) * (-std::expm1(-x)) * (3.0 - e);
  return std::clamp(b, 1.0, 2.0);
}

double hapke_scattering(double phase_rad, double t) {
  const double p = clamp_phase(phase_rad);
  const double c = std::cos(p);
  return (std::sin(p) + (kPi - p) * c) / kPi + t * (1.0 - 0.5 * c) * (1.0 - 0.5 * c);
}

double hapke_brdf(double cos_i, double cos_r, double phase_rad) {
  if (!(cos_i > 0.0) || !(cos_r > 0.0)) return 0.0;
  return 2.0 / (3.0 * kPi) * hapke_retrodirective(phase_rad) * hapke_scattering(phase_rad) * cos_i / (cos_i + cos_r);
}

double earthshine_fraction(double moon_phase_rad) {
  const double earth_phase = kPi - clamp_phase(moon_phase_rad);
  return kJensenFullEarthshineWm2 * 0.5 * lommel_seeliger_phase(earth_phase) / kJensenSunAtMoonWm2;
}

double sun_illuminance_at_1au_lux() {
  static const double lux = rgb_luminance(core::sun_rgb_illuminance_at_1au_lux());
  return lux;
}

glm::dvec3 moon_color_rgb() {
  static const glm::dvec3 rgb = [] {
    const std::vector<double> grid = spectral::wavelength_grid(360.0, 830.0, 5.0);
    std::vector<double> spectrum;
    for (double nm : grid) spectrum.push_back(spectral::solar_irradiance_blackbody(nm) * lunar_ramp(nm));
    const glm::dvec3 c = glm::max(spectral::SpectrumToColor(grid).linear_srgb(spectrum), glm::dvec3(0.0));
    return c / rgb_luminance(c);
  }();
  return rgb;
}

double moon_magnitude_krisciunas_schaefer(double phase_rad, double observer_distance_m, double sun_distance_au) {
  const double a = clamp_phase(phase_rad) * 180.0 / kPi;
  const double d = std::max(observer_distance_m, 2.0 * kMoonRadiusM) / kMoonMeanDistanceM;
  const double r = std::max(sun_distance_au, 1e-3);
  return -12.73 + 0.026 * a + 4e-9 * a * a * a * a + 5.0 * std::log10(d * r);
}

double moon_illuminance_jensen_lux(double phase_rad, double observer_distance_m, double sun_distance_au,
                                   double albedo) {
  const double p = clamp_phase(phase_rad);
  const double sun = sun_at(sun_distance_au);
  const double earth = earthshine_fraction(p) * sun;  // Jensen: full earthshine at the mean distance
  return 2.0 / 3.0 * albedo * disc_factor(observer_distance_m) * (earth + sun * lommel_seeliger_phase(p));
}

MoonIlluminance moon_illuminance_hapke(double phase_rad, double observer_distance_m, double sun_distance_au,
                                       double sun_albedo, double earthshine_albedo) {
  const double p = clamp_phase(phase_rad);
  const double sun = sun_at(sun_distance_au);
  // The Earth is lit by the same Sun; its light at the Moon falls off with the Earth-Moon distance.
  const double d_ratio = kMoonMeanDistanceM / std::max(observer_distance_m, 2.0 * kMoonRadiusM);
  const double earth = earthshine_fraction(p) * sun * d_ratio * d_ratio;
  const double k = disc_factor(observer_distance_m) / 3.0;
  MoonIlluminance e;
  e.sun_lux = k * sun_albedo * hapke_retrodirective(p) * hapke_scattering(p) * lommel_seeliger_phase(p) * sun;
  e.earthshine_lux = k * earthshine_albedo * hapke_retrodirective(0.0) * hapke_scattering(0.0) * earth;
  return e;
}

double moon_calibrated_albedo(double phase_rad) {
  const double p = std::min(clamp_phase(phase_rad), kMoonPhaseLawLimitRad);
  const double measured = illuminance_from_magnitude(moon_magnitude_krisciunas_schaefer(p));
  return measured / hapke_sun_unit_albedo(p);
}

MoonIlluminance moon_illuminance(double phase_rad, double observer_distance_m, double sun_distance_au) {
  return moon_illuminance_hapke(phase_rad, observer_distance_m, sun_distance_au, moon_calibrated_albedo(phase_rad),
                                moon_calibrated_albedo(0.0));
}

MoonDiscLighting moon_disc_lighting(double phase_rad, double observer_distance_m, double sun_distance_au,
                                    MoonCalibration calibration) {
  const double p = clamp_phase(phase_rad);
  const bool measured = calibration == MoonCalibration::kMagnitudeLaw;
  const double sun_albedo = measured ? moon_calibrated_albedo(p) : kJensenMoonAlbedo;
  const double earth_albedo = measured ? moon_calibrated_albedo(0.0) : kJensenMoonAlbedo;
  const double sun = sun_at(sun_distance_au);
  const double d_ratio = kMoonMeanDistanceM / std::max(observer_distance_m, 2.0 * kMoonRadiusM);
  MoonDiscLighting l;
  l.phase_rad = p;
  l.sun_albedo_lux = sun_albedo * sun;
  l.earthshine_albedo_lux = earth_albedo * earthshine_fraction(p) * sun * d_ratio * d_ratio;
  l.sun_bs = hapke_retrodirective(p) * hapke_scattering(p);
  l.earthshine_bs = hapke_retrodirective(0.0) * hapke_scattering(0.0);
  l.color_rgb = moon_color_rgb();
  return l;
}

glm::dvec3 moon_disc_normal(const glm::dvec2& disc_xy, const glm::dvec3& to_observer, const glm::dvec3& disc_right,
                            const glm::dvec3& disc_up) {
  glm::dvec2 xy = disc_xy;
  const double r2 = glm::dot(xy, xy);
  if (r2 > 1.0) xy /= std::sqrt(r2);
  const double z = std::sqrt(std::max(0.0, 1.0 - glm::dot(xy, xy)));
  return xy.x * disc_right + xy.y * disc_up + z * to_observer;
}

double moon_disc_luminance(const MoonDiscLighting& l, const glm::dvec3& normal, const glm::dvec3& to_sun,
                           const glm::dvec3& to_observer) {
  const double mu = glm::dot(normal, to_observer);
  if (!(mu > 0.0)) return 0.0;  // far side (also catches NaN input)
  const double mu0 = glm::dot(normal, to_sun);
  constexpr double k = 2.0 / (3.0 * kPi);
  double sunlit = 0.0;
  if (mu0 > 0.0) sunlit = l.sun_albedo_lux * l.sun_bs * mu0 / (mu0 + mu);
  const double earthlit = l.earthshine_albedo_lux * l.earthshine_bs * 0.5;  // mu0 = mu for light from the observer
  return k * (sunlit + earthlit);
}

glm::dvec3 moon_disc_radiance_rgb(const MoonDiscLighting& l, const glm::dvec3& normal, const glm::dvec3& to_sun,
                                  const glm::dvec3& to_observer) {
  return moon_disc_luminance(l, normal, to_sun, to_observer) * l.color_rgb;
}

glm::dvec3 moon_disc_radiance_toward(const MoonDiscLighting& lighting, const glm::dvec3& centre_in,
                                     double angular_radius_rad, const glm::dvec3& to_sun_in, const glm::dvec3& dir_in) {
  const glm::dvec3 c = glm::normalize(centre_in), d = glm::normalize(dir_in), to_sun = glm::normalize(to_sun_in);
  const double cos_t = glm::dot(d, c);
  if (!(cos_t > 0.0) || !(angular_radius_rad > 0.0)) return glm::dvec3(0.0);
  const glm::dvec3 lateral = d - cos_t * c;
  if (std::atan2(glm::length(lateral), cos_t) > angular_radius_rad) return glm::dvec3(0.0);
  // Disc axes: any pair perpendicular to the line of sight.
  const glm::dvec3 a = std::abs(c.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 right = glm::normalize(glm::cross(c, a)), up = glm::cross(c, right);
  const double s = std::sin(angular_radius_rad);
  const glm::dvec2 xy(glm::dot(lateral, right) / s, glm::dot(lateral, up) / s);
  return moon_disc_radiance_rgb(lighting, moon_disc_normal(xy, -c, right, up), to_sun, -c);
}

}  // namespace atmo::core::night
