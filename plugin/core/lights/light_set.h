// light_set.h — the host's lights as the plugin keeps them: groups (the
// host's unit of change: set_lights replaces one, set_light_group_pose moves
// one, update_lights replaces some of one), each light in its group's frame,
// in double. Pure; the ABI layer validates the host's structs into these, and
// each view's frame (fog glows, light points, surface lists) reads them
// through for_each_light (docs/FOG.md).
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include <glm/glm.hpp>

namespace atmo::lights {

// All groups together; ATMO_LIGHTS_MAX.
constexpr uint32_t kMaxLights = 65536;
// Group numbers are [0, kMaxGroups): ATMO_LIGHT_GROUPS_MAX.
constexpr uint32_t kMaxGroups = 4096;

// cos_outer below this: an omnidirectional light.
constexpr double kOmni = -1.5;

struct Light {
  glm::dvec3 position_m{0.0};           // in the group's frame
  glm::dvec3 axis{0.0, 0.0, 1.0};       // unit, the group's frame
  glm::dvec3 intensity_cd{0.0};         // on the axis, per channel (intensity times colour)
  double cos_inner = -2.0, cos_outer = -2.0;  // cos_outer < kOmni: omnidirectional
  float lobes = 1.0f;                   // 2: the cone shines both ways along its axis
  double mean_profile = 1.0;            // the profile's mean over the sphere (the diffusion term's power)
};

// The mean over the sphere of a cone's profile smoothstep(cos_outer, cos_inner, cos angle)
// (atmo_fog_cone), `lobes` cones (2 needs cos_outer >= 0): the integral of a smoothstep over its ramp is
// half the ramp, so one cone's mean is (2 - cos_inner - cos_outer) / 4. Exact.
double mean_cone_profile(double cos_inner, double cos_outer, double lobes = 1.0);

struct LightGroup {
  std::vector<Light> lights;
  glm::dmat4 ecef_from_world{1.0};   // the group's world frame (AtmoLightsState.world_frame)
  glm::dmat4 world_from_group{1.0};  // its pose (set_light_group_pose)
  glm::dmat4 ecef_from_group{1.0};   // the two together
  void set_pose(const glm::dmat4& pose) {
    world_from_group = pose;
    ecef_from_group = ecef_from_world * pose;
  }
};

struct LightSet {
  std::map<uint32_t, LightGroup> groups;  // ordered: every walk over the lights is in one order
  double glow_threshold_cd_m2 = 0.0;      // 0: from the view's exposure
  double visual_threshold_lux = 0.0;      // 0: from the background (allard_threshold_lux)
  uint64_t version = 0;                   // bumps on every change (the views' frames follow)

  size_t size() const;
  bool empty() const { return size() == 0; }
  // f(ecef_position, ecef_axis, light) for every light, groups in ascending order.
  template <typename F>
  void for_each_light(F&& f) const {
    for (const auto& [id, g] : groups) {
      const glm::dmat3 r(g.ecef_from_group);
      const glm::dvec3 t(g.ecef_from_group[3]);
      for (const Light& l : g.lights) f(r * l.position_m + t, r * l.axis, l);
    }
  }
};

}  // namespace atmo::lights
