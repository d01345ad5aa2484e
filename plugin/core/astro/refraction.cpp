#include "core/astro/refraction.h"

#include <erfa.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace atmo::core::astro {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kArcmin = kDeg / 60.0;
constexpr double kBlendLowDeg = 5.0;
constexpr double kBlendHighDeg = 15.0;
constexpr double kLowestDeg = -1.0;
constexpr double kFadeDeg = 2.0;

// US Standard Atmosphere 1976 layers: base geopotential height (m) and lapse
// rate (K/m); base temperature 288.15 K and pressure 101325 Pa at 0 m.
struct Layer {
  double base_m;
  double lapse_k_per_m;
};
constexpr Layer kLayers[] = {{0.0, -0.0065},    {11000.0, 0.0},     {20000.0, 0.001}, {32000.0, 0.0028},
                             {47000.0, 0.0},    {51000.0, -0.0028}, {71000.0, -0.002}, {84852.0, 0.0}};
constexpr double kG0MOverR = 0.034163195;  // g0 M / R*, K/m
constexpr double kEarthRadiusM = 6356766.0;  // for geopotential height

}  // namespace

RefractionConditions standard_refraction_conditions(double height_m) {
  const double h = kEarthRadiusM * height_m / (kEarthRadiusM + height_m);  // geopotential
  double t = 288.15, p = 101325.0;
  const int n = static_cast<int>(sizeof kLayers / sizeof kLayers[0]);
  for (int i = 0; i < n; ++i) {
    const double top = i + 1 < n ? kLayers[i + 1].base_m : 1e30;
    const double base = kLayers[i].base_m;
    const double lapse = kLayers[i].lapse_k_per_m;
    // The first layer also serves below sea level.
    const double dh = (i + 1 < n && h > top ? top : h) - base;
    if (lapse != 0.0) {
      const double t1 = t + lapse * dh;
      p *= std::pow(t / t1, kG0MOverR / lapse);
      t = t1;
    } else {
      p *= std::exp(-kG0MOverR * dh / t);
    }
    if (h <= top) break;
  }
  RefractionConditions c;
  c.pressure_hpa = p / 100.0;
  c.temperature_c = t - 273.15;
  c.relative_humidity = 0.5;
  c.wavelength_um = 0.55;
  return c;
}

std::optional<std::string> validate(const RefractionConditions& c) {
  char buf[160];
  if (!std::isfinite(c.pressure_hpa) || c.pressure_hpa < 0.0 || c.pressure_hpa > 1200.0) {
    std::snprintf(buf, sizeof buf, "pressure %g hPa is not in [0, 1200]", c.pressure_hpa);
    return std::string(buf);
  }
  if (!std::isfinite(c.temperature_c) || c.temperature_c < -150.0 || c.temperature_c > 100.0) {
    std::snprintf(buf, sizeof buf, "temperature %g °C is not in [-150, 100]", c.temperature_c);
    return std::string(buf);
  }
  if (!std::isfinite(c.relative_humidity) || c.relative_humidity < 0.0 || c.relative_humidity > 1.0) {
    std::snprintf(buf, sizeof buf, "relative humidity %g is not in [0, 1]", c.relative_humidity);
    return std::string(buf);
  }
  if (!std::isfinite(c.wavelength_um) || c.wavelength_um < 0.3 || c.wavelength_um > 30.0) {
    std::snprintf(buf, sizeof buf, "wavelength %g µm is not in [0.3, 30]", c.wavelength_um);
    return std::string(buf);
  }
  return std::nullopt;
}

RefractionModel make_refraction_model(const RefractionConditions& c, double observer_height_m) {
  RefractionModel m;
  constexpr double kMeanEarthRadiusM = 6371000.0;
  const double h = std::max(observer_height_m, 0.0);
  m.hold_until_rad = kLowestDeg * kDeg - std::acos(kMeanEarthRadiusM / (kMeanEarthRadiusM + h));
  eraRefco(c.pressure_hpa, c.temperature_c, c.relative_humidity, c.wavelength_um, &m.refa, &m.refb);
  m.saemundsson_scale = (c.pressure_hpa / 1010.0) * (283.0 / (273.0 + c.temperature_c));
  return m;
}

double refraction_erfa_rad(const RefractionModel& m, double e) {
  // dz = A tan z + B tan^3 z holds for the observed zenith distance z; one
  // Newton step from the unrefracted one, as eraAtioq.
  const double sin_e = std::max(std::sin(e), 0.05);  // eraAtioq's floor (2.9°)
  const double cos_e = std::max(std::cos(e), 1e-6);
  const double tz = cos_e / sin_e;
  const double w = m.refb * tz * tz;
  return (m.refa + w) * tz / (1.0 + (m.refa + 3.0 * w) / (sin_e * sin_e));
}

double refraction_saemundsson_rad(const RefractionModel& m, double e) {
  const double h = std::max(e / kDeg, kLowestDeg);
  return m.saemundsson_scale * 1.02 * kArcmin / std::tan((h + 10.3 / (h + 5.11)) * kDeg);
}

double refraction_rad(const RefractionModel& m, double e) {
  if (!std::isfinite(e)) return 0.0;
  const double deg = e / kDeg;
  if (deg >= kBlendHighDeg) return refraction_erfa_rad(m, e);
  if (e < m.hold_until_rad) {
    const double x = std::clamp((e - (m.hold_until_rad - kFadeDeg * kDeg)) / (kFadeDeg * kDeg), 0.0, 1.0);
    return x * x * (3.0 - 2.0 * x) * refraction_saemundsson_rad(m, kLowestDeg * kDeg);
  }
  if (deg <= kBlendLowDeg) return refraction_saemundsson_rad(m, e);
  const double x = (deg - kBlendLowDeg) / (kBlendHighDeg - kBlendLowDeg);
  const double w = x * x * (3.0 - 2.0 * x);
  return (1.0 - w) * refraction_saemundsson_rad(m, e) + w * refraction_erfa_rad(m, e);
}

}  // namespace atmo::core::astro
