#include "core/night_sky/night_plan.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/night_sky/night_sky_twin.h"
#include "core/night_sky/point_sources.h"
#include "core/night_sky/star_photometry.h"

namespace atmo::core::night {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// Margin of the horizon cut, as PointSourceCut's.
constexpr double kHorizonMarginRad = 0.5 * kDeg;
// A linear HDR target's host tone-maps it; 0.5 % of the background is half the ~1 % contrast the eye
// resolves in daylight (Weber; Blackwell 1946), so an increase smaller than that is invisible under any
// global tone curve (a local operator that boosts contrast more is the host's to account for).
constexpr double kHdrWeberFraction = 0.005;
constexpr double kZodiacalGlareElongationRad = 30.0 * kDeg;

double luminance(const glm::vec3& rgb) { return rgb_luminance(glm::dvec3(rgb)); }

// Zenith radiance of the sky lit by `atm`'s light from `light_enu`, cd/m^2 (CPU twin march).
double zenith_sky_luminance(const twin::AtmosphereParameters& atm, const twin::Lut2D& t, const twin::Lut2D& ms,
                            double eye_altitude_m, const glm::dvec3& light_enu) {
  const glm::vec3 rgb = twin::sky_radiance(atm, t, glm::vec2(t.width, t.height), ms, glm::vec2(ms.width, ms.height),
                                           static_cast<float>(std::max(eye_altitude_m, 1.0)), glm::vec3(0, 0, 1),
                                           glm::vec3(light_enu), 16);
  const double l = luminance(rgb);
  return std::isfinite(l) ? std::max(l, 0.0) : 0.0;
}
}  // namespace

double visible_increase_cd_m2(double background_cd_m2, double exposure, bool display_encoded) {
  const double l = std::max(background_cd_m2, 0.0);
  if (!(exposure > 0.0) || !std::isfinite(exposure)) return std::numeric_limits<double>::infinity();
  if (!display_encoded) return std::max(visible_step_linear(false) / exposure, kHdrWeberFraction * l);
  // Half a display step above the background's encoded value; none if the display is saturated there.
  const float base = twin::encode_display_srgb(glm::vec3(static_cast<float>(exposure * l))).x;
  const float target = base + 0.5f / 255.0f;
  if (target >= 1.0f) return std::numeric_limits<double>::infinity();
  double lo = 0.0, hi = std::max(1.0, 4.0 * exposure * l);
  while (twin::encode_display_srgb(glm::vec3(static_cast<float>(exposure * l + hi))).x < target) hi *= 2.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (twin::encode_display_srgb(glm::vec3(static_cast<float>(exposure * l + mid))).x >= target) hi = mid;
    else lo = mid;
  }
  return hi / exposure;
}

double visible_step_linear(bool display_encoded) {
  if (!display_encoded) return 1e-4;
  // Half an 8-bit step of the encoded output, on black: bisect encode_display_srgb.
  const float target = 0.5f / 255.0f;
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (twin::encode_display_srgb(glm::vec3(static_cast<float>(mid))).x >= target) hi = mid;
    else lo = mid;
  }
  return hi;
}

double point_limiting_magnitude(double background_cd_m2, const NightPlanInputs& in) {
  if (!(in.exposure > 0.0) || !std::isfinite(in.exposure)) return -std::numeric_limits<double>::infinity();
  DisplayThreshold threshold;
  if (in.display_encoded) {
    threshold.kind = DisplayThreshold::Kind::kEncodedSdr;
    threshold.step = 1.0 / 255.0;  // one display step: an 8-bit pixel changes by at least one code value
  } else {
    threshold.kind = DisplayThreshold::Kind::kLinear;
    threshold.step = in.exposure * visible_increase_cd_m2(background_cd_m2, in.exposure, false);
  }
  return display_limiting_magnitude(std::max(background_cd_m2, 0.0), in.exposure,
                                    std::max(in.pixel_solid_angle_sr, 1e-12), threshold);
}

twin::AtmosphereParameters moonlit_atmosphere(const twin::AtmosphereParameters& atmosphere, const SkyBodies& bodies) {
  twin::AtmosphereParameters a = atmosphere;
  a.sun_illuminance_lux = glm::vec3(bodies.moon_illuminance_rgb_lux);
  a.sun_angular_radius = static_cast<float>(std::max(bodies.moon_angular_radius_rad, 1e-6));
  return a;
}

NightPlan plan_night_sky(const Scene& scene, const twin::Lut2D& transmittance, const twin::Lut2D& multiple_scattering,
                         const NightPlanInputs& in) {
  NightPlan plan;
  plan.inputs = in;
  const double exposure = std::isfinite(in.exposure) && in.exposure > 0.0 ? in.exposure : 0.0;
  plan.visible_step_linear = visible_step_linear(in.display_encoded);
  if (exposure <= 0.0 || transmittance.width == 0 || multiple_scattering.width == 0) {
    plan.limiting_magnitude = -std::numeric_limits<double>::infinity();
    return plan;
  }
  const SkyBodies& b = scene.bodies;
  const double radius = static_cast<double>(scene.atmosphere.bottom_radius_m);
  const double horizon_cut = -(horizon_dip_rad(scene.eye_altitude_m, radius) + kHorizonMarginRad);
  plan.moon_up = std::asin(std::clamp(b.moon_enu.z, -1.0, 1.0)) > horizon_cut;
  const double moon_lux = std::max(rgb_luminance(b.moon_illuminance_rgb_lux), 0.0);

  // The darkest sky the Sun leaves in view, erring dark, and the smallest increase visible on it: a term
  // that cannot add that much anywhere is left out (the background's millicandelas vanish in a day sky).
  plan.sun_zenith_cd_m2 = zenith_sky_luminance(scene.atmosphere, transmittance, multiple_scattering,
                                               scene.eye_altitude_m, scene.sun_direction_enu);
  const double sun_darkest = 0.3 * plan.sun_zenith_cd_m2 + kBackgroundMinLuminance;
  const double step_cd_m2 = visible_increase_cd_m2(sun_darkest, exposure, in.display_encoded);
  plan.visible_increase_cd_m2 = step_cd_m2;

  // The Moon's disc: its mean luminance (illuminance over its solid angle) x 2 bounds the Hapke peak.
  const double moon_solid_angle = kPi * std::max(b.moon_angular_radius_rad, 1e-6) * std::max(b.moon_angular_radius_rad, 1e-6);
  plan.moon_disc = plan.moon_up && 2.0 * moon_lux / moon_solid_angle >= step_cd_m2;
  // The moonlit sky: only with a table to draw it from; the Moon a little below the horizon still lights the air.
  const bool moon_lights_air = b.moon_enu.z > std::sin(horizon_cut - 6.0 * kDeg);
  plan.moonlit_sky = in.method_has_sky_view && moon_lights_air &&
                     kMoonlitSkyMaxRadiancePerLux * moon_lux >= step_cd_m2;
  // The background's bound depends on the geometry only through the Sun's depression: ENU axes will do. Its
  // zodiacal term is taken no nearer the Sun than kZodiacalGlareElongationRad: nearer, the zodiacal light is
  // seen only once the Sun is that far down (the "false dawn" cone after astronomical twilight); while the Sun
  // is higher the twilight there outshines it by orders of magnitude, and the whole-sky bound would switch the
  // background on at sunset against a sky it cannot change.
  glm::dvec3 sun_for_bound = b.sun_enu_unrefracted;
  const double horizontal = std::hypot(sun_for_bound.x, sun_for_bound.y);
  const double depression = std::max(-std::asin(std::clamp(sun_for_bound.z, -1.0, 1.0)), kZodiacalGlareElongationRad);
  const glm::dvec2 azimuth = horizontal > 1e-12 ? glm::dvec2(sun_for_bound.x, sun_for_bound.y) / horizontal
                                                : glm::dvec2(0.0, 1.0);
  sun_for_bound = glm::dvec3(azimuth * std::cos(depression), -std::sin(depression));
  plan.background = night_background_max_luminance(glm::dmat3(1.0), sun_for_bound, scene.eye_altitude_m, radius) >=
                    step_cd_m2;

  // The stars' limit against the darkest sky with the Moon's light too.
  if (plan.moonlit_sky) {
    plan.moon_zenith_cd_m2 = zenith_sky_luminance(moonlit_atmosphere(scene.atmosphere, b), transmittance,
                                                  multiple_scattering, scene.eye_altitude_m, b.moon_enu);
  }
  plan.darkest_sky_cd_m2 = sun_darkest + 0.3 * plan.moon_zenith_cd_m2;
  NightPlanInputs clamped = in;
  clamped.exposure = exposure;
  plan.limiting_magnitude = point_limiting_magnitude(plan.darkest_sky_cd_m2, clamped);
  if (!std::isfinite(plan.limiting_magnitude) && plan.limiting_magnitude > 0.0) plan.limiting_magnitude = 30.0;
  plan.points = plan.limiting_magnitude >= kBrightestPointSourceMagnitude;
  return plan;
}

}  // namespace atmo::core::night
