#include "core/lights/light_points.h"

#include <algorithm>
#include <cmath>

#include "core/fog/fog_twin.h"

namespace atmo::lights {

double allard_threshold_lux(double background_cd_m2) {
  // (log10 B, log10 E_t) anchors; constant outside.
  static const double kAnchors[][2] = {
      {1.69897, -6.09691}, {3.0, -5.0}, {4.07918, -4.0}, {4.60206, -3.0}};
  const double b = std::log10(std::max(background_cd_m2, 1e-12));
  if (b <= kAnchors[0][0]) return std::pow(10.0, kAnchors[0][1]);
  for (int i = 1; i < 4; ++i)
    if (b <= kAnchors[i][0]) {
      const double t = (b - kAnchors[i - 1][0]) / (kAnchors[i][0] - kAnchors[i - 1][0]);
      return std::pow(10.0, kAnchors[i - 1][1] + t * (kAnchors[i][1] - kAnchors[i - 1][1]));
    }
  return std::pow(10.0, kAnchors[3][1]);
}

glm::dvec3 air_transmittance(const twin::AtmosphereParameters& atm, double eye_altitude_m,
                             const glm::dvec3& to_point_enu_m) {
  // 8-point Gauss-Legendre on [0, 1].
  static const double kX[8] = {0.0198550717512319, 0.1016667612931866, 0.2372337950418355, 0.4082826787521751,
                               0.5917173212478249, 0.7627662049581645, 0.8983332387068134, 0.9801449282487681};
  static const double kW[8] = {0.0506142681451881, 0.1111905172266872, 0.1568533229389436, 0.1813418916891810,
                               0.1813418916891810, 0.1568533229389436, 0.1111905172266872, 0.0506142681451881};
  const double length = glm::length(to_point_enu_m);
  if (!(length > 0.0)) return glm::dvec3(1.0);
  const double radius = static_cast<double>(atm.bottom_radius_m);
  const glm::dvec3 centre_to_eye(0.0, 0.0, radius + eye_altitude_m);
  const glm::dvec3 dir = to_point_enu_m / length;
  const auto altitude = [&](double t) { return glm::length(centre_to_eye + t * dir) - radius; };
  // Pieces over which the altitude is monotonic (split at the lowest point of a grazing path), each cut into
  // parts spanning at most kPartHeightM of altitude (a third of the aerosols' scale height: the extinction
  // changes by < 40 % across a part, which 8 points integrate to ~1e-10) and 100 km.
  constexpr double kPartHeightM = 400.0, kPartLengthM = 100000.0;
  const double lowest = std::clamp(-glm::dot(centre_to_eye, dir), 0.0, length);
  const double cuts[3] = {0.0, lowest, length};
  glm::dvec3 depth(0.0);
  for (int piece = 0; piece < 2; ++piece) {
    const double a = cuts[piece], b = cuts[piece + 1];
    if (!(b > a)) continue;
    const double rise = std::abs(altitude(b) - altitude(a));
    const int parts = static_cast<int>(
        std::clamp(std::ceil(std::max(rise / kPartHeightM, (b - a) / kPartLengthM)), 1.0, 256.0));
    const double step = (b - a) / parts;
    for (int k = 0; k < parts; ++k)
      for (int i = 0; i < 8; ++i)
        depth += kW[i] * step *
                 glm::dvec3(twin::extinction_at(atm, static_cast<float>(altitude(a + (k + kX[i]) * step))));
  }
  return glm::exp(-depth);
}

std::vector<LightPoint> visible_light_points(const fog::FogFrame& frame, const twin::AtmosphereParameters& atm,
                                             double eye_altitude_m, const PointCamera& camera, double threshold_lux,
                                             LightPointStats* stats) {
  std::vector<LightPoint> out;
  LightPointStats st;
  st.lights = static_cast<uint32_t>(frame.lights.size());
  const double half_w = 0.5 * camera.viewport_width, half_h = 0.5 * camera.viewport_height;
  const double reach_x = 1.0 + camera.margin_px / half_w, reach_y = 1.0 + camera.margin_px / half_h;
  // The air's transmittance is at most 1 and the fog's is known: a light whose
  // E is under the threshold without the air is not integrated.
  for (const fog::FrameLight& l : frame.lights) {
    const glm::dvec3 p(l.position_enu_m);
    const glm::dvec4 clip = camera.clip_from_enu * glm::dvec4(p, 1.0);
    if (!(clip.w > 0.0) || std::abs(clip.x) > reach_x * clip.w || std::abs(clip.y) > reach_y * clip.w) {
      ++st.off_screen;
      continue;
    }
    const double d2 = glm::dot(p, p);
    const double d = std::sqrt(d2);
    // The light's intensity towards the eye: its cone at the direction light -> eye.
    const glm::vec3 to_eye = d > 0.0 ? glm::vec3(-p / d) : glm::vec3(0.0f, 0.0f, 1.0f);
    const double cone = fog::twin::atmo_fog_cone(l.axis_enu, l.cos_inner, l.cos_outer, l.lobes, to_eye);
    const double fog_t = std::exp(-static_cast<double>(l.beta_per_m) * d);
    const glm::dvec3 upper = glm::dvec3(l.intensity_cd) * (cone * fog_t / std::max(d2, 1e-6));
    if (!(luminance(upper) >= threshold_lux)) {
      ++st.below_threshold;
      continue;
    }
    const glm::dvec3 e = upper * air_transmittance(atm, eye_altitude_m, p);
    if (!(luminance(e) >= threshold_lux)) {
      ++st.below_threshold;
      continue;
    }
    out.push_back({l.position_enu_m, glm::vec3(e)});
  }
  st.drawn = static_cast<uint32_t>(out.size());
  if (stats) *stats = st;
  return out;
}

}  // namespace atmo::lights
