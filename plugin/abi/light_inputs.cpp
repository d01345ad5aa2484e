#include "abi/light_inputs.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "abi/struct_io.h"
#include "abi/validation.h"
#include "abi/world_frame.h"

namespace atmo::abi {

namespace {

Verdict bad(AtmoResult code, const std::string& message) { return {code, message}; }

// One light of the host's array as the plugin keeps it. `where` names the
// array ("AtmoLightsState.lights"); messages add "[i].field". The string is
// built only on error: 65 536 lights are read in a few milliseconds.
Verdict read_light(const unsigned char* element, uint32_t stride, const char* where, uint32_t i, lights::Light* out) {
  AtmoLightPoint p;
  std::memset(&p, 0, sizeof(p));
  std::memcpy(&p, element, stride < sizeof(p) ? stride : sizeof(p));  // a 96-byte light reads no flags
  const auto field = [&](const std::string& f) { return std::string(where) + "[" + std::to_string(i) + "]." + f; };
  const double* all = &p.position_m[0];
  for (size_t k = 0; k < 12; ++k)  // the twelve doubles
    if (!std::isfinite(all[k]))
      return bad(ATMO_ERROR_NON_FINITE_VALUE, std::string(where) + "[" + std::to_string(i) +
                                                  "] has a NaN or Inf field (double " + std::to_string(k) + ")");
  for (int k = 0; k < 3; ++k)
    if (std::abs(p.position_m[k]) > 1e9)  // a light beyond the Moon's orbit: a units mistake
      return bad(ATMO_ERROR_OUT_OF_RANGE, field("position_m[" + std::to_string(k) + "]") + " = " +
                                              number(p.position_m[k]) + " is outside [-1e9, 1e9] m");
  if (p.intensity_cd < 0.0 || p.intensity_cd > 1e8)
    return bad(ATMO_ERROR_OUT_OF_RANGE, field("intensity_cd") + " = " + number(p.intensity_cd) + " is outside [0, 1e8]");
  for (int c = 0; c < 3; ++c)
    if (p.color[c] < 0.0 || p.color[c] > 16.0)
      return bad(ATMO_ERROR_OUT_OF_RANGE,
                 field("color[" + std::to_string(c) + "]") + " = " + number(p.color[c]) + " is outside [0, 16]");
  if (p.flags & ~uint32_t(ATMO_LIGHT_BIDIRECTIONAL))
    return bad(ATMO_ERROR_INVALID_ARGUMENT, field("flags") + " = " + std::to_string(p.flags) +
                                                " holds bits that are not AtmoLightFlags");
  lights::Light l;
  l.position_m = glm::dvec3(p.position_m[0], p.position_m[1], p.position_m[2]);
  l.intensity_cd = p.intensity_cd * glm::dvec3(p.color[0], p.color[1], p.color[2]);
  if (p.cone_outer_rad != 0.0) {
    const glm::dvec3 axis(p.direction[0], p.direction[1], p.direction[2]);
    if (!(p.cone_inner_rad >= 0.0 && p.cone_inner_rad < p.cone_outer_rad && p.cone_outer_rad <= M_PI))
      return bad(ATMO_ERROR_OUT_OF_RANGE, field("cone_*_rad") + ": inner " + number(p.cone_inner_rad) + ", outer " +
                                              number(p.cone_outer_rad) + " rad; needs 0 <= inner < outer <= pi");
    const double length = glm::length(axis);
    if (!(length > 0.0) || !std::isfinite(length))
      return bad(ATMO_ERROR_INVALID_ARGUMENT, field("direction") + " is the zero vector (a cone needs an axis)");
    l.lobes = (p.flags & ATMO_LIGHT_BIDIRECTIONAL) ? 2.0f : 1.0f;
    if (l.lobes > 1.0f && p.cone_outer_rad > 0.5 * M_PI)
      return bad(ATMO_ERROR_OUT_OF_RANGE, field("cone_outer_rad") + " = " + number(p.cone_outer_rad) +
                                              ": a bidirectional light's cones may not overlap (at most pi/2)");
    l.axis = axis / length;
    l.cos_inner = std::cos(p.cone_inner_rad);
    l.cos_outer = std::cos(p.cone_outer_rad);
  } else if (p.flags & ATMO_LIGHT_BIDIRECTIONAL) {
    return bad(ATMO_ERROR_INVALID_ARGUMENT,
               field("flags") + " asks for a bidirectional light with no cone (cone_outer_rad 0: omnidirectional)");
  }
  l.mean_profile = lights::mean_cone_profile(l.cos_inner, l.cos_outer, l.lobes);
  *out = l;
  return {};
}

// Reads `count` lights `stride` bytes apart into out[0, count).
Verdict read_lights(const AtmoLightPoint* lights, uint32_t count, uint32_t light_size, const char* struct_name,
                    lights::Light* out) {
  if (count == 0) return {};
  const std::string array = std::string(struct_name) + ".lights";
  if (!lights)
    return bad(ATMO_ERROR_INVALID_ARGUMENT, array + " is NULL with light_count " + std::to_string(count));
  uint32_t stride = 0;
  const ReadError e = array_stride<AtmoLightPoint>(light_size, (std::string(struct_name) + ".light_size").c_str(),
                                                   &stride);
  if (e.code) return bad(e.code, e.message);
  const auto* bytes = reinterpret_cast<const unsigned char*>(lights);
  for (uint32_t i = 0; i < count; ++i) {
    Verdict v = read_light(bytes + static_cast<size_t>(i) * stride, stride, array.c_str(), i, &out[i]);
    if (!v.ok()) return v;
  }
  return {};
}

}  // namespace

Verdict set_lights_state(const AtmoLightsState& s, lights::LightSet* set) {
  if (s.world_frame > ATMO_WORLD_ENU)
    return bad(ATMO_ERROR_INVALID_ARGUMENT, "AtmoLightsState.world_frame = " + std::to_string(s.world_frame) +
                                                " is not an AtmoWorldFrame");
  if (s.group >= lights::kMaxGroups)
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoLightsState.group = " + std::to_string(s.group) + " is outside [0, " +
                                            std::to_string(lights::kMaxGroups) + ")");
  if (!std::isfinite(s.glow_threshold_cd_m2) || s.glow_threshold_cd_m2 < 0.0)
    return bad(std::isfinite(s.glow_threshold_cd_m2) ? ATMO_ERROR_OUT_OF_RANGE : ATMO_ERROR_NON_FINITE_VALUE,
               "AtmoLightsState.glow_threshold_cd_m2 = " + number(s.glow_threshold_cd_m2) + " must be >= 0");
  if (!std::isfinite(s.visual_threshold_lux) || s.visual_threshold_lux < 0.0 || s.visual_threshold_lux > 1.0)
    return bad(std::isfinite(s.visual_threshold_lux) ? ATMO_ERROR_OUT_OF_RANGE : ATMO_ERROR_NON_FINITE_VALUE,
               "AtmoLightsState.visual_threshold_lux = " + number(s.visual_threshold_lux) + " is outside [0, 1] lux");
  if (s.world_frame == ATMO_WORLD_ENU) {
    const double* g = s.world_origin_geodetic;
    if (!std::isfinite(g[0]) || !std::isfinite(g[1]) || !std::isfinite(g[2]) || std::abs(g[0]) > 90.0)
      return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoLightsState.world_origin_geodetic is not a geodetic position");
  }
  const auto old = set->groups.find(s.group);
  const size_t others = set->size() - (old == set->groups.end() ? 0 : old->second.lights.size());
  if (s.light_count > lights::kMaxLights - others)
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoLightsState.light_count = " + std::to_string(s.light_count) +
                                            ": with the other groups' " + std::to_string(others) +
                                            " lights the context would hold more than " +
                                            std::to_string(lights::kMaxLights));
  std::vector<lights::Light> read(s.light_count);
  Verdict v = read_lights(s.lights, s.light_count, s.light_size, "AtmoLightsState", read.data());
  if (!v.ok()) return v;
  // Valid: apply.
  set->glow_threshold_cd_m2 = s.glow_threshold_cd_m2;
  set->visual_threshold_lux = s.visual_threshold_lux;
  ++set->version;
  if (read.empty()) {
    set->groups.erase(s.group);
    return {};
  }
  lights::LightGroup& g = set->groups[s.group];
  g.lights = std::move(read);
  g.ecef_from_world = ecef_from_world_frame(s.world_frame, s.world_origin_geodetic);
  g.set_pose(g.world_from_group);  // a group keeps its pose when its lights are replaced
  return {};
}

Verdict update_lights_state(const AtmoLightsUpdate& u, lights::LightSet* set) {
  const auto it = set->groups.find(u.group);
  if (it == set->groups.end())
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoLightsUpdate.group = " + std::to_string(u.group) +
                                            " holds no lights (set_lights fills a group first)");
  std::vector<lights::Light>& group = it->second.lights;
  if (u.first > group.size() || u.light_count > group.size() - u.first)
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoLightsUpdate: lights [" + std::to_string(u.first) + ", " +
                                            std::to_string(uint64_t(u.first) + u.light_count) + ") are not within group " +
                                            std::to_string(u.group) + "'s " + std::to_string(group.size()));
  std::vector<lights::Light> read(u.light_count);
  Verdict v = read_lights(u.lights, u.light_count, u.light_size, "AtmoLightsUpdate", read.data());
  if (!v.ok()) return v;
  std::copy(read.begin(), read.end(), group.begin() + u.first);
  ++set->version;
  return {};
}

Verdict set_light_group_pose_state(const AtmoLightGroupPose& p, lights::LightSet* set) {
  const auto it = set->groups.find(p.group);
  if (it == set->groups.end())
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoLightGroupPose.group = " + std::to_string(p.group) +
                                            " holds no lights (set_lights fills a group first)");
  for (int k = 0; k < 16; ++k)
    if (!std::isfinite(p.world_from_group[k]))
      return bad(ATMO_ERROR_NON_FINITE_VALUE, "AtmoLightGroupPose.world_from_group[" + std::to_string(k) +
                                                  "] = " + number(p.world_from_group[k]));
  const glm::dmat4 m = matrix(p.world_from_group);
  Verdict v;
  if (!rigid_transform(&v, m, "AtmoLightGroupPose.world_from_group")) return v;
  for (int k = 0; k < 3; ++k)
    if (std::abs(m[3][k]) > 1e9)
      return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoLightGroupPose.world_from_group[" + std::to_string(12 + k) + "] = " +
                                              number(m[3][k]) + " is outside [-1e9, 1e9] m");
  it->second.set_pose(m);
  ++set->version;
  return {};
}

}  // namespace atmo::abi
