#include "core/night_sky/background.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/atmosphere/atmosphere_model.h"
#include "core/night_sky/star_photometry.h"
#include "core/spectral/colorimetry.h"
#include "core/spectral/spectral_atmosphere.h"

namespace atmo::core::night {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Leinert et al. 1998: 1 S10 (solar spectrum, V) = 1.28e-8 W m^-2 sr^-1 um^-1 at 500 nm.
constexpr double kZodiacalTableUnitsPerS10 = 1.28;

// Length of the part of the ray p(t) = r0 z + t d, t in [0, t_max], inside the
// sphere of radius rho (mu: cosine between d and z).
double length_inside(double r0, double mu, double t_max, double rho) {
  const double disc = r0 * r0 * (mu * mu - 1.0) + rho * rho;
  if (disc <= 0.0) return 0.0;
  const double s = std::sqrt(disc);
  const double t0 = std::max(-r0 * mu - s, 0.0);
  const double t1 = std::min(-r0 * mu + s, t_max);
  return std::max(t1 - t0, 0.0);
}

glm::dvec3 safe_normalize(const glm::dvec3& v) {
  const double l = glm::length(v);
  return l > 0.0 && std::isfinite(l) ? v / l : glm::dvec3(0.0, 0.0, 1.0);
}
}  // namespace

glm::dvec3 ecliptic_pole_icrs() {
  return glm::dvec3(0.0, -std::sin(kObliquityJ2000Rad), std::cos(kObliquityJ2000Rad));
}

glm::dmat3 galactic_from_icrs() {
  // Rows of A_G' (Hipparcos, ESA 1997); glm is column-major, so build the transpose and transpose it.
  const glm::dmat3 columns_are_rows(-0.0548755604162154, -0.8734370902348850, -0.4838350155487132,
                                    +0.4941094278755837, -0.4448296299600112, +0.7469822444972189,
                                    -0.8676661490190047, -0.1980763734312015, +0.4559837761750669);
  return glm::transpose(columns_are_rows);
}

glm::dvec2 galactic_lon_lat(const glm::dvec3& dir_icrs) {
  const glm::dvec3 g = galactic_from_icrs() * safe_normalize(dir_icrs);
  double l = std::atan2(g.y, g.x);
  if (l < 0.0) l += 2.0 * kPi;
  return {l, std::asin(std::clamp(g.z, -1.0, 1.0))};
}

double airglow_slant_factor(double cos_zenith, double eye_altitude_m, double planet_radius_m,
                            const BackgroundSettings& s) {
  const double radius = std::max(planet_radius_m, 1.0);
  const double thickness = std::max(s.airglow_layer_thickness_m, 1.0);
  const double r0 = radius + std::max(eye_altitude_m, 0.0);
  const double mu = std::clamp(cos_zenith, -1.0, 1.0);
  if (!std::isfinite(r0) || std::isnan(mu)) return 0.0;
  // The ray ends at the ground if it meets it.
  double t_max = kInf;
  const double ground_disc = r0 * r0 * (mu * mu - 1.0) + radius * radius;
  if (mu < 0.0 && ground_disc >= 0.0) t_max = std::max(-r0 * mu - std::sqrt(ground_disc), 0.0);
  const double inner = radius + s.airglow_layer_altitude_m - 0.5 * thickness;
  const double outer = radius + s.airglow_layer_altitude_m + 0.5 * thickness;
  const double path = length_inside(r0, mu, t_max, outer) - length_inside(r0, mu, t_max, inner);
  return std::max(path, 0.0) / thickness;
}

double airglow_luminance(double cos_zenith, double eye_altitude_m, double planet_radius_m,
                         const BackgroundSettings& s) {
  return luminance_from_s10(s.airglow_zenith_s10) * airglow_slant_factor(cos_zenith, eye_altitude_m, planet_radius_m, s);
}

double zodiacal_s10(double elongation_rad, double ecliptic_latitude_rad) {
  const double eps = std::clamp(std::abs(elongation_rad), 2.0 * kDeg, kPi) / (90.0 * kDeg);
  // |beta| <= eps for every real direction; the clamp keeps impossible pairs finite too.
  const double sin_beta = std::min(std::abs(std::sin(ecliptic_latitude_rad)), std::sin(std::min(eps, 1.0) * 0.5 * kPi));
  const double ecliptic = 149.85 * std::pow(eps, -2.459) + 171.0;
  const double width = 1.0635 * eps;
  const double gegenschein = (kPi - eps * 90.0 * kDeg) / (36.28 * kDeg);
  const double table_units = -44.76 + ecliptic * std::exp(-std::pow(sin_beta / width, 0.7259)) +
                             67.28 * std::exp(-gegenschein * gegenschein);
  return std::max(table_units, 0.0) / kZodiacalTableUnitsPerS10;
}

double zodiacal_luminance(const glm::dvec3& dir_icrs, const glm::dvec3& sun_icrs, const BackgroundSettings& s) {
  const glm::dvec3 d = safe_normalize(dir_icrs);
  const double eps = std::acos(std::clamp(glm::dot(d, safe_normalize(sun_icrs)), -1.0, 1.0));
  const double beta = std::asin(std::clamp(glm::dot(d, ecliptic_pole_icrs()), -1.0, 1.0));
  return s.zodiacal_scale * luminance_from_s10(zodiacal_s10(eps, beta));
}

double starlight_s10(double l, double b, const BackgroundSettings& s) {
  const double width = std::max(s.starlight_width_sin_b, 1e-3);
  // cos b cos l is the galactic x component: the longitude term fades toward the poles, where l is undefined.
  return s.starlight_pole_s10 +
         s.starlight_plane_excess_s10 * (1.0 + s.starlight_longitude_contrast * std::cos(b) * std::cos(l)) *
             std::exp(-std::abs(std::sin(b)) / width);
}

double starlight_luminance(const glm::dvec3& dir_icrs, const BackgroundSettings& s) {
  const glm::dvec2 lb = galactic_lon_lat(dir_icrs);
  return luminance_from_s10(starlight_s10(lb.x, lb.y, s));
}

glm::dvec3 airglow_color_rgb() {
  static const glm::dvec3 rgb = [] {
    constexpr double h = 6.62607015e-34, c = 299792458.0;
    constexpr double kPhotonsPerRayleigh = 1e10 / (4.0 * kPi);  // m^-2 s^-1 sr^-1
    struct Line {
      double nm, rayleigh;
    };
    const Line lines[] = {{557.7, 250.0}, {589.3, 50.0}, {630.0, 100.0}};
    const glm::dmat3 to_rgb = spectral::linear_srgb_from_xyz();
    glm::dvec3 line_xyz(0.0);  // photometric: 683 lm/W times the CMFs, per W m^-2 sr^-1
    for (const Line& l : lines) {
      const double watts = l.rayleigh * kPhotonsPerRayleigh * h * c / (l.nm * 1e-9);
      line_xyz += spectral::kMaxLuminousEfficacy * watts * spectral::cie1931_2deg(l.nm);
    }
    // The continuum (flat in energy per nm) makes up the rest of the default zenith luminance.
    const std::vector<double> grid = spectral::wavelength_grid(360.0, 830.0, 5.0);
    const spectral::SpectrumToColor conv(grid);
    const std::vector<double> unit(grid.size(), 1.0);  // 1 W m^-2 sr^-1 nm^-1
    const double zenith = luminance_from_s10(BackgroundSettings{}.airglow_zenith_s10);
    const double continuum_level = std::max(zenith - line_xyz.y, 0.0) / conv.luminance(unit);
    const glm::dvec3 rgb_total = to_rgb * line_xyz + continuum_level * conv.linear_srgb(unit);
    const glm::dvec3 clamped = glm::max(rgb_total, glm::dvec3(0.0));
    return clamped / rgb_luminance(clamped);
  }();
  return rgb;
}

glm::dvec3 zodiacal_color_rgb() {
  static const glm::dvec3 rgb = [] {
    const glm::dvec3 sun = core::sun_rgb_illuminance_at_1au_lux();
    return sun / rgb_luminance(sun);
  }();
  return rgb;
}

glm::dvec3 starlight_color_rgb() {
  static const glm::dvec3 rgb = star_rgb_from_bv(kStarlightBV);
  return rgb;
}

glm::dvec3 BackgroundLuminance::rgb() const {
  return airglow * airglow_color_rgb() + zodiacal * zodiacal_color_rgb() +
         (starlight + diffuse_galactic + cosmic) * starlight_color_rgb();
}

BackgroundLuminance night_background(const glm::dvec3& dir_icrs, const glm::dvec3& sun_icrs,
                                     const glm::dvec3& zenith_icrs, double eye_altitude_m, double planet_radius_m,
                                     const BackgroundSettings& s) {
  const glm::dvec3 d = safe_normalize(dir_icrs);
  BackgroundLuminance b;
  b.airglow = airglow_luminance(glm::dot(d, safe_normalize(zenith_icrs)), eye_altitude_m, planet_radius_m, s);
  b.zodiacal = zodiacal_luminance(d, sun_icrs, s);
  b.starlight = starlight_luminance(d, s);
  b.diffuse_galactic = s.diffuse_galactic_fraction * b.starlight;
  b.cosmic = luminance_from_s10(s.cosmic_s10);
  return b;
}

}  // namespace atmo::core::night
