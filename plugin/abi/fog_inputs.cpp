#include "abi/fog_inputs.h"

#include <cmath>
#include <cstring>
#include <string>

#include "abi/struct_io.h"
#include "abi/world_frame.h"

namespace atmo::abi {

namespace {

Verdict bad(AtmoResult code, const std::string& message) { return {code, message}; }

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.6g", v);
  return b;
}

}  // namespace

Verdict set_fog_state(const AtmoFogState& s, fog::FogMedium* fog) {
  const double fields[] = {s.visibility_m, s.extinction_per_m, s.top_height_m, s.phase_asymmetry,
                           s.single_scattering_albedo};
  const char* names[] = {"visibility_m", "extinction_per_m", "top_height_m", "phase_asymmetry",
                         "single_scattering_albedo"};
  for (int i = 0; i < 5; ++i)
    if (!std::isfinite(fields[i]))
      return bad(ATMO_ERROR_NON_FINITE_VALUE, std::string("AtmoFogState.") + names[i] + " is " + num(fields[i]));
  if (s.visibility_m != 0.0 && (s.visibility_m < 10.0 || s.visibility_m > 100000.0))
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoFogState.visibility_m = " + num(s.visibility_m) + " is outside [10, 100000] m");
  if (s.extinction_per_m < 0.0 || s.extinction_per_m > 1.0)
    return bad(ATMO_ERROR_OUT_OF_RANGE,
               "AtmoFogState.extinction_per_m = " + num(s.extinction_per_m) + " is outside [0, 1] 1/m");
  if (s.top_height_m < -500.0 || s.top_height_m > 20000.0)
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoFogState.top_height_m = " + num(s.top_height_m) + " is outside [-500, 20000] m");
  if (std::abs(s.phase_asymmetry) > 0.95)
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoFogState.phase_asymmetry = " + num(s.phase_asymmetry) + " is outside [-0.95, 0.95]");
  if (s.single_scattering_albedo < 0.0 || s.single_scattering_albedo > 1.0)
    return bad(ATMO_ERROR_OUT_OF_RANGE,
               "AtmoFogState.single_scattering_albedo = " + num(s.single_scattering_albedo) + " is outside (0, 1]");
  if (s.scattering >= ATMO_FOG_SCATTERING_COUNT)
    return bad(ATMO_ERROR_INVALID_ARGUMENT, "AtmoFogState.scattering = " + std::to_string(s.scattering) +
                                                " is not an AtmoFogScattering");
  if (s.airlight_table_size != 0 && (s.airlight_table_size < 8 || s.airlight_table_size > 512))
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoFogState.airlight_table_size = " + std::to_string(s.airlight_table_size) +
                                            " is outside [8, 512]");
  fog::FogOptics o;
  o.extinction_per_m = s.visibility_m > 0.0 ? fog::extinction_from_visibility(s.visibility_m) : s.extinction_per_m;
  o.albedo = s.single_scattering_albedo > 0.0 ? s.single_scattering_albedo : fog::kFogAlbedo;
  o.phase_g = s.phase_asymmetry != 0.0 ? s.phase_asymmetry : fog::kFogPhaseG;
  o.top_height_m = s.top_height_m != 0.0 ? s.top_height_m : INFINITY;
  o.multiple_scattering = s.scattering == ATMO_FOG_SCATTERING_AUTO;
  const int size = s.airlight_table_size ? static_cast<int>(s.airlight_table_size) : 64;
  fog->apply(o, size);
  return {};
}

Verdict set_lights_state(const AtmoLightsState& s, fog::FogLights* out) {
  if (s.world_frame > ATMO_WORLD_ENU)
    return bad(ATMO_ERROR_INVALID_ARGUMENT, "AtmoLightsState.world_frame = " + std::to_string(s.world_frame) +
                                                " is not an AtmoWorldFrame");
  if (s.light_count > 16384)
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoLightsState.light_count = " + std::to_string(s.light_count) +
                                            " is above 16384");
  if (s.light_count > 0 && !s.lights)
    return bad(ATMO_ERROR_INVALID_ARGUMENT, "AtmoLightsState.lights is NULL with light_count " + std::to_string(s.light_count));
  uint32_t stride = 0;
  if (s.light_count > 0) {
    const ReadError e = array_stride<AtmoLightPoint>(s.light_size, "AtmoLightsState.light_size", &stride);
    if (e.code) return bad(e.code, e.message);
  }
  if (!std::isfinite(s.glow_threshold_cd_m2) || s.glow_threshold_cd_m2 < 0.0)
    return bad(std::isfinite(s.glow_threshold_cd_m2) ? ATMO_ERROR_OUT_OF_RANGE : ATMO_ERROR_NON_FINITE_VALUE,
               "AtmoLightsState.glow_threshold_cd_m2 = " + num(s.glow_threshold_cd_m2) + " must be >= 0");
  if (s.world_frame == ATMO_WORLD_ENU) {
    const double* g = s.world_origin_geodetic;
    if (!std::isfinite(g[0]) || !std::isfinite(g[1]) || !std::isfinite(g[2]) || std::abs(g[0]) > 90.0)
      return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoLightsState.world_origin_geodetic is not a geodetic position");
  }
  const glm::dmat4 ecef_from_world_m = ecef_from_world_frame(s.world_frame, s.world_origin_geodetic);
  const glm::dmat3 ecef_from_world(ecef_from_world_m);
  const glm::dvec3 origin(ecef_from_world_m[3]);
  std::vector<fog::FogLight> lights(s.light_count);
  const auto* bytes = reinterpret_cast<const unsigned char*>(s.lights);
  for (uint32_t i = 0; i < s.light_count; ++i) {
    AtmoLightPoint p;
    std::memcpy(&p, bytes + static_cast<size_t>(i) * stride, sizeof(p));
    const std::string where = "AtmoLightsState.lights[" + std::to_string(i) + "].";
    const double* all = &p.position_m[0];
    for (size_t k = 0; k < sizeof(p) / sizeof(double); ++k)
      if (!std::isfinite(all[k])) return bad(ATMO_ERROR_NON_FINITE_VALUE, where + " has a NaN or Inf field");
    for (int k = 0; k < 3; ++k)
      if (std::abs(p.position_m[k]) > 1e9)  // a light beyond the Moon's orbit: a units mistake
        return bad(ATMO_ERROR_OUT_OF_RANGE, where + "position_m[" + std::to_string(k) + "] = " + num(p.position_m[k]) +
                                                " is outside [-1e9, 1e9] m");
    if (p.intensity_cd < 0.0 || p.intensity_cd > 1e8)
      return bad(ATMO_ERROR_OUT_OF_RANGE, where + "intensity_cd = " + num(p.intensity_cd) + " is outside [0, 1e8]");
    for (int c = 0; c < 3; ++c)
      if (p.color[c] < 0.0 || p.color[c] > 16.0)
        return bad(ATMO_ERROR_OUT_OF_RANGE, where + "color[" + std::to_string(c) + "] = " + num(p.color[c]) +
                                                " is outside [0, 16]");
    fog::FogLight& l = lights[i];
    l.position_ecef_m = origin + ecef_from_world * glm::dvec3(p.position_m[0], p.position_m[1], p.position_m[2]);
    l.intensity_cd = p.intensity_cd * glm::dvec3(p.color[0], p.color[1], p.color[2]);
    if (p.cone_outer_rad != 0.0) {
      const glm::dvec3 axis(p.direction[0], p.direction[1], p.direction[2]);
      if (!(p.cone_inner_rad >= 0.0 && p.cone_inner_rad < p.cone_outer_rad && p.cone_outer_rad <= M_PI))
        return bad(ATMO_ERROR_OUT_OF_RANGE, where + "cone (inner " + num(p.cone_inner_rad) + ", outer " +
                                                num(p.cone_outer_rad) + " rad) needs 0 <= inner < outer <= pi");
      if (glm::length(axis) <= 0.0) return bad(ATMO_ERROR_INVALID_ARGUMENT, where + "direction is the zero vector");
      l.axis_ecef = glm::normalize(ecef_from_world * axis);
      l.cos_inner = std::cos(p.cone_inner_rad);
      l.cos_outer = std::cos(p.cone_outer_rad);
      l.mean_profile = fog::mean_cone_profile(l.cos_inner, l.cos_outer);
    }
  }
  out->lights = std::move(lights);
  out->glow_threshold_cd_m2 = s.glow_threshold_cd_m2;
  return {};
}

}  // namespace atmo::abi
