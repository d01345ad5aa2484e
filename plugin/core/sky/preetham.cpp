#include "core/sky/preetham.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/spectral/spectral_atmosphere.h"

namespace atmo::core {

namespace {
constexpr double kPi = 3.14159265358979323846;

// Preetham et al. 1999, Appendix A: each coefficient is linear in T,
// value = slope * T + offset, for Y, x, y.
struct Linear {
  double slope, offset;
  double at(double t) const { return slope * t + offset; }
};
//                                  Y                    x                    y
constexpr Linear kA[3] = {{0.1787, -1.4630}, {-0.0193, -0.2592}, {-0.0167, -0.2608}};
constexpr Linear kB[3] = {{-0.3554, 0.4275}, {-0.0665, 0.0008}, {-0.0950, 0.0092}};
constexpr Linear kC[3] = {{-0.0227, 5.3251}, {-0.0004, 0.2125}, {-0.0079, 0.2102}};
constexpr Linear kD[3] = {{0.1206, -2.5771}, {-0.0641, -0.8989}, {-0.0441, -1.6537}};
constexpr Linear kE[3] = {{-0.0670, 0.3703}, {-0.0033, 0.0452}, {-0.0109, 0.0529}};

// Zenith chromaticity: [T^2 T 1] M [theta^3 theta^2 theta 1]^T.
constexpr double kXz[3][4] = {{0.00166, -0.00375, 0.00209, 0.0},
                              {-0.02903, 0.06377, -0.03202, 0.00394},
                              {0.11693, -0.21196, 0.06052, 0.25886}};
constexpr double kYz[3][4] = {{0.00275, -0.00610, 0.00317, 0.0},
                              {-0.04214, 0.08970, -0.04153, 0.00516},
                              {0.15346, -0.26756, 0.06670, 0.26688}};

double chromaticity_polynomial(const double (&m)[3][4], double t, double theta) {
  const double tv[3] = {t * t, t, 1.0};
  const double th[4] = {theta * theta * theta, theta * theta, theta, 1.0};
  double sum = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) sum += tv[i] * m[i][j] * th[j];
  return sum;
}

glm::vec3 linear3(const Linear (&k)[3], double t) {
  return glm::vec3(static_cast<float>(k[0].at(t)), static_cast<float>(k[1].at(t)), static_cast<float>(k[2].at(t)));
}

double smoothstep(double edge0, double edge1, double x) {
  double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

std::string format(const char* fmt, double a, double b) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), fmt, a, b);
  return buf;
}
}  // namespace

double preetham_zenith_luminance_kcd(double turbidity, double sun_zenith_rad) {
  const double chi = (4.0 / 9.0 - turbidity / 120.0) * (kPi - 2.0 * sun_zenith_rad);
  return (4.0453 * turbidity - 4.9710) * std::tan(chi) - 0.2155 * turbidity + 2.4192;
}

void preetham_zenith_chromaticity(double turbidity, double sun_zenith_rad, double& x_z, double& y_z) {
  x_z = chromaticity_polynomial(kXz, turbidity, sun_zenith_rad);
  y_z = chromaticity_polynomial(kYz, turbidity, sun_zenith_rad);
}

twin::PreethamCoefficients preetham_coefficients(double turbidity, double sun_zenith_rad) {
  const double theta_s = std::clamp(sun_zenith_rad, 0.0, kPi);
  twin::PreethamCoefficients c{};
  c.A = linear3(kA, turbidity);
  c.B = linear3(kB, turbidity);
  c.C = linear3(kC, turbidity);
  c.D = linear3(kD, turbidity);
  c.E = linear3(kE, turbidity);
  // chi stays below pi/2 for T >= 0 and theta_s >= 0, so tan() is finite.
  const double y_kcd = std::max(preetham_zenith_luminance_kcd(turbidity, theta_s), 0.0);
  double x_z = 0.0, y_z = 0.0;
  preetham_zenith_chromaticity(turbidity, std::min(theta_s, 0.5 * kPi), x_z, y_z);
  c.zenith_Yxy = glm::vec3(static_cast<float>(y_kcd * 1000.0), static_cast<float>(x_z), static_cast<float>(y_z));
  return c;
}

// The air is the spectral model's (core/spectral/spectral_atmosphere.h), the
// one the LUT tier and the reference are built from.
double preetham_turbidity_from_visibility(double visibility_m, double aerosol_scale_height_m) {
  return spectral::turbidity_from_visibility(std::max(visibility_m, 1.0), std::max(aerosol_scale_height_m, 0.0));
}

double preetham_visibility_from_turbidity(double turbidity, double aerosol_scale_height_m) {
  return spectral::visibility_from_turbidity(turbidity, std::max(aerosol_scale_height_m, 1.0));
}

PreethamValidity preetham_validity(double turbidity, double sun_elevation_rad, double eye_altitude_m) {
  PreethamValidity v;
  if (!std::isfinite(turbidity) || !std::isfinite(sun_elevation_rad) || !std::isfinite(eye_altitude_m)) {
    v.reason = "non-finite input: hand over to the LUT tier";
    return v;
  }
  const double deg = 180.0 / kPi;
  std::string hard, soft;
  auto add = [](std::string& list, const std::string& item) { list += (list.empty() ? "" : "; ") + item; };

  if (turbidity < kPreethamMinTurbidity)
    add(hard, format("turbidity %.2f < %.2f: the zenith normalisation 1 + A_Y exp(B_Y) crosses 0 near T = 1.64 "
                     "(and B_Y > 0 below T = 1.20 blows up at the horizon)",
                     turbidity, kPreethamMinTurbidity));
  else if (turbidity > kPreethamMaxTurbidity)
    add(hard, format("turbidity %.2f > %.1f: beyond the hazy end of the fitted range (second-order scattering only)",
                     turbidity, kPreethamMaxTurbidity));
  else if (turbidity < kPreethamFullMinTurbidity || turbidity > kPreethamFullMaxTurbidity)
    add(soft, format("turbidity %.2f near the fitted range's edge [%.1f, 10]", turbidity, kPreethamMinTurbidity));

  if (sun_elevation_rad < kPreethamMinSunElevationRad)
    add(hard, format("sun elevation %.2f deg < %.1f deg: the fit has no twilight (Y_z stays ~2 kcd/m^2 at the "
                     "horizon and positive far below it)",
                     sun_elevation_rad * deg, kPreethamMinSunElevationRad * deg));
  else if (sun_elevation_rad < kPreethamFullSunElevationRad)
    add(soft, format("sun elevation %.2f deg near the %.0f deg cut-off", sun_elevation_rad * deg,
                     kPreethamMinSunElevationRad * deg));

  if (eye_altitude_m > kPreethamMaxEyeAltitudeM)
    add(hard, format("eye altitude %.0f m > %.0f m: the model is a ground-observer fit (sea-level US Standard "
                     "Atmosphere), no view from above the haze",
                     eye_altitude_m, kPreethamMaxEyeAltitudeM));
  else if (eye_altitude_m > kPreethamFullMaxEyeAltitudeM)
    add(soft, format("eye altitude %.0f m above the %.0f m ground-observer range", eye_altitude_m,
                     kPreethamFullMaxEyeAltitudeM));

  v.valid = hard.empty();
  if (v.valid) {
    v.confidence = smoothstep(kPreethamMinTurbidity, kPreethamFullMinTurbidity, turbidity) *
                   (1.0 - smoothstep(kPreethamFullMaxTurbidity, kPreethamMaxTurbidity, turbidity)) *
                   smoothstep(kPreethamMinSunElevationRad, kPreethamFullSunElevationRad, sun_elevation_rad) *
                   (1.0 - smoothstep(kPreethamFullMaxEyeAltitudeM, kPreethamMaxEyeAltitudeM, eye_altitude_m));
    v.reason = soft.empty() ? "inside the fitted range" : "valid, near a bound: " + soft;
  } else {
    v.confidence = 0.0;
    v.reason = "invalid, hand over to the LUT tier: " + hard;
  }
  return v;
}

}  // namespace atmo::core
