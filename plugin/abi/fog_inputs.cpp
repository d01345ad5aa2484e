#include "abi/fog_inputs.h"

#include <cmath>
#include <cstring>
#include <string>

#include "abi/struct_io.h"
#include "core/fog/fog_twin.h"
#include "core/geodesy.h"

namespace atmo::abi {

namespace {

Verdict bad(AtmoResult code, const std::string& message) { return {code, message}; }

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.6g", v);
  return b;
}

// Mean over the sphere of a cone light's profile (atmo_fog_cone): d(omega) = 2 pi d(cos).
double mean_cone_profile(double cos_inner, double cos_outer) {
  const int n = 512;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const float c = static_cast<float>(-1.0 + 2.0 * (i + 0.5) / n);
    sum += fog::twin::atmo_fog_cone(glm::vec3(0.0f, 0.0f, 1.0f), static_cast<float>(cos_inner),
                                    static_cast<float>(cos_outer), glm::vec3(std::sqrt(1.0f - c * c), 0.0f, c));
  }
  return sum / n;
}

}  // namespace

Verdict set_fog_state(const AtmoFogState& s, ContextFog* fog) {
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
  if (o.extinction_per_m > 0.0 && (o.phase_g != fog->tables_phase_g || size != fog->tables_airlight_size)) {
    fog->airlight = fog::build_airlight_table(size, o.phase_g);
    fog->surface = fog::build_surface_table(32, 32, o.phase_g);
    fog->bound = std::make_unique<fog::GlowBound>(o.phase_g);
    fog->tables_phase_g = o.phase_g;
    fog->tables_airlight_size = size;
    ++fog->version;
  }
  fog->optics = o;
  fog->airlight_table_size = size;
  return {};
}

Verdict set_lights_state(const AtmoLightsState& s, ContextLights* out) {
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
  glm::dmat3 ecef_from_world(1.0);
  glm::dvec3 origin(0.0);
  if (s.world_frame == ATMO_WORLD_ENU) {
    const double* g = s.world_origin_geodetic;
    if (!std::isfinite(g[0]) || !std::isfinite(g[1]) || !std::isfinite(g[2]) || std::abs(g[0]) > 90.0)
      return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoLightsState.world_origin_geodetic is not a geodetic position");
    ecef_from_world = core::ecef_from_enu(g[0], g[1]);
    origin = core::ecef_from_geodetic({g[0], g[1], g[2]});
  }
  std::vector<FogLight> lights(s.light_count);
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
    FogLight& l = lights[i];
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
      l.mean_profile = mean_cone_profile(l.cos_inner, l.cos_outer);
    }
  }
  out->lights = std::move(lights);
  out->glow_threshold_cd_m2 = s.glow_threshold_cd_m2;
  return {};
}

FogFrame make_fog_frame(const ContextFog& fog, const ContextLights& lights, const core::EyeFrame& eye,
                        double threshold_cd_m2) {
  FogFrame f;
  const fog::FogOptics& o = fog.optics;
  const double top = std::isfinite(o.top_height_m) ? o.top_height_m - eye.eye.height_m : INFINITY;
  f.top_above_eye_m = std::isfinite(top) ? static_cast<float>(top) : fog::kNoTop;
  const glm::dmat3 enu_from_ecef = glm::transpose(eye.ecef_from_enu);
  // The diffusion term's layer: from the ground, taken as the lowest of the eye and the lights (lights stand
  // on the ground), to the top (docs/FOG.md).
  double floor_above_eye = 0.0;
  for (const FogLight& l : lights.lights)
    floor_above_eye = std::min(floor_above_eye, (enu_from_ecef * (l.position_ecef_m - eye.eye_ecef_m)).z);
  const double depth = std::isfinite(top) ? std::max(top - floor_above_eye, 1.0) : INFINITY;
  const double tr = o.transport_per_m(), mu = o.diffusion_decay_per_m(depth);
  const double cap = !o.multiple_scattering ? 0.0 : std::isfinite(depth) ? o.extinction_per_m * depth : 1e30;
  f.diffusion = glm::vec4(float(tr), float(mu), float(fog::kHandoverRate), float(cap));
  f.lights.resize(lights.lights.size());
  glm::dvec3 fluence(0.0);
  glm::dmat3 flux(0.0);
  for (size_t i = 0; i < lights.lights.size(); ++i) {
    const FogLight& l = lights.lights[i];
    FrameLight& fl = f.lights[i];
    const glm::dvec3 rel = enu_from_ecef * (l.position_ecef_m - eye.eye_ecef_m);
    fl.position_enu_m = glm::vec3(rel);
    fl.intensity_cd = glm::vec3(l.intensity_cd);
    fl.axis_enu = glm::vec3(enu_from_ecef * l.axis_ecef);
    fl.cos_inner = static_cast<float>(l.cos_inner);
    fl.cos_outer = static_cast<float>(l.cos_outer);
    // The part of the eye-light segment inside the layer (heights in the tangent plane at the eye).
    const double beta =
        o.extinction_per_m * fog::twin::atmo_fog_inside_fraction(0.0f, fl.position_enu_m.z, f.top_above_eye_m);
    fl.beta_per_m = static_cast<float>(beta);
    const double d = glm::length(rel);
    const double peak = std::max({l.intensity_cd.x, l.intensity_cd.y, l.intensity_cd.z});
    fl.glow_radius_rad = fog.bound ? static_cast<float>(fog.bound->radius_rad(beta, o.albedo, std::max(d, 1e-3), peak,
                                                                              threshold_cd_m2))
                                   : 0.0f;
    if (o.multiple_scattering && d > 0.0) {
      const glm::vec2 p1 = fog::twin::atmo_fog_diffusion_light(f.diffusion, static_cast<float>(d),
                                                                static_cast<float>(beta * d), false);
      const double phi = p1.x, flux_magnitude = p1.y;
      const glm::dvec3 towards = rel / d;
      const glm::dvec3 power = l.intensity_cd * l.mean_profile;
      fluence += phi * power;
      for (int c = 0; c < 3; ++c) flux[c] += flux_magnitude * power[c] * towards;
    }
  }
  f.fluence = glm::vec3(fluence);
  f.flux_towards_lights = glm::mat3(flux);
  return f;
}

std::vector<float> surface_light_ranges(const ContextFog& fog, const FogFrame& frame,
                                        double threshold_cd_m2) {
  std::vector<float> range(frame.lights.size(), 0.0f);
  const glm::vec2 size(static_cast<float>(fog.surface.width),
                       static_cast<float>(fog.surface.height / fog::kSurfaceLayers));
  for (size_t i = 0; i < frame.lights.size(); ++i) {
    const FrameLight& l = frame.lights[i];
    const double peak = std::max({l.intensity_cd.x, l.intensity_cd.y, l.intensity_cd.z});
    if (!(peak > 0.0)) continue;
    // Distances 1 m .. 1000 km, 8 per octave; the range is the step past the last one above the threshold.
    for (int k = 0; k <= 160; ++k) {
      const float r = std::exp2(static_cast<float>(k) / 8.0f);
      const float beta = l.beta_per_m;
      const glm::vec2 t = fog::twin::atmo_fog_surface_terms(fog.surface, size, beta, static_cast<float>(fog.optics.albedo),
                                                            frame.diffusion, r, beta * r, 1.0f, 1.0f, 1.0f);
      if (peak * t.x / M_PI >= threshold_cd_m2) range[i] = std::exp2(static_cast<float>(k + 1) / 8.0f);
    }
  }
  return range;
}

}  // namespace atmo::abi
