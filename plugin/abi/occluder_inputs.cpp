#include "abi/occluder_inputs.h"

#include <cmath>
#include <cstring>
#include <string>

#include "abi/struct_io.h"
#include "abi/world_frame.h"

namespace atmo::abi {

namespace {

Verdict bad(AtmoResult code, const std::string& message) { return {code, message}; }

// A pose: finite, rigid, within [-1e9, 1e9] m.
Verdict read_pose(const double m16[16], const std::string& name, glm::dmat4* out) {
  for (int k = 0; k < 16; ++k)
    if (!std::isfinite(m16[k]))
      return bad(ATMO_ERROR_NON_FINITE_VALUE, name + "[" + std::to_string(k) + "] = " + number(m16[k]));
  const glm::dmat4 m = matrix(m16);
  Verdict v;
  if (!rigid_transform(&v, m, name)) return v;
  for (int k = 0; k < 3; ++k)
    if (std::abs(m[3][k]) > 1e9)
      return bad(ATMO_ERROR_OUT_OF_RANGE,
                 name + "[" + std::to_string(12 + k) + "] = " + number(m[3][k]) + " is outside [-1e9, 1e9] m");
  *out = m;
  return {};
}

}  // namespace

Verdict set_occluders_state(const AtmoOccludersState& s, ContextOccluders* out) {
  if (s.world_frame > ATMO_WORLD_ENU)
    return bad(ATMO_ERROR_INVALID_ARGUMENT, "AtmoOccludersState.world_frame = " + std::to_string(s.world_frame) +
                                                " is not an AtmoWorldFrame");
  if (s.world_frame == ATMO_WORLD_ENU) {
    const double* g = s.world_origin_geodetic;
    if (!std::isfinite(g[0]) || !std::isfinite(g[1]) || !std::isfinite(g[2]) || std::abs(g[0]) > 90.0)
      return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoOccludersState.world_origin_geodetic is not a geodetic position");
  }
  if (s.flags & ~uint32_t(ATMO_OCCLUSION_NO_BOUNCE | ATMO_OCCLUSION_OPTIMAL_LINEAR))
    return bad(ATMO_ERROR_INVALID_ARGUMENT, "AtmoOccludersState.flags = " + std::to_string(s.flags) +
                                                " holds bits that are not AtmoOcclusionFlags");
  if (s.object_count > ATMO_OCCLUDER_OBJECTS_MAX)
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoOccludersState.object_count = " + std::to_string(s.object_count) +
                                            " is more than " + std::to_string(ATMO_OCCLUDER_OBJECTS_MAX));
  if (s.object_count && !s.objects)
    return bad(ATMO_ERROR_INVALID_ARGUMENT,
               "AtmoOccludersState.objects is NULL with object_count " + std::to_string(s.object_count));
  uint32_t object_stride = 0;
  ReadError e = array_stride<AtmoOccluderObject>(s.object_size, "AtmoOccludersState.object_size", &object_stride);
  if (e.code) return bad(e.code, e.message);
  std::vector<std::vector<glm::dvec4>> spheres(s.object_count);
  std::vector<glm::dvec3> albedo(s.object_count);
  std::vector<glm::dmat4> poses(s.object_count);
  size_t total = 0;
  const auto* objects = reinterpret_cast<const unsigned char*>(s.objects);
  for (uint32_t i = 0; i < s.object_count; ++i) {
    AtmoOccluderObject o;
    std::memcpy(&o, objects + static_cast<size_t>(i) * object_stride, sizeof(o));
    const std::string where = "AtmoOccludersState.objects[" + std::to_string(i) + "]";
    if (o.sphere_count > ATMO_OCCLUDER_SPHERES_MAX)
      return bad(ATMO_ERROR_OUT_OF_RANGE, where + ".sphere_count = " + std::to_string(o.sphere_count) +
                                              " is more than " + std::to_string(ATMO_OCCLUDER_SPHERES_MAX));
    total += o.sphere_count;
    if (total > ATMO_OCCLUDER_SPHERES_TOTAL_MAX)
      return bad(ATMO_ERROR_OUT_OF_RANGE, where + ": the objects up to it hold " + std::to_string(total) +
                                              " spheres, more than " + std::to_string(ATMO_OCCLUDER_SPHERES_TOTAL_MAX));
    if (o.sphere_count && !o.spheres)
      return bad(ATMO_ERROR_INVALID_ARGUMENT, where + ".spheres is NULL with sphere_count " +
                                                  std::to_string(o.sphere_count));
    uint32_t sphere_stride = 0;
    e = array_stride<AtmoOccluderSphere>(o.sphere_size, (where + ".sphere_size").c_str(), &sphere_stride);
    if (e.code) return bad(e.code, e.message);
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(o.albedo[c]) || o.albedo[c] < 0.0 || o.albedo[c] > 1.0)
        return bad(std::isfinite(o.albedo[c]) ? ATMO_ERROR_OUT_OF_RANGE : ATMO_ERROR_NON_FINITE_VALUE,
                   where + ".albedo[" + std::to_string(c) + "] = " + number(o.albedo[c]) + " is outside [0, 1]");
    albedo[i] = glm::dvec3(o.albedo[0], o.albedo[1], o.albedo[2]);
    Verdict v = read_pose(o.world_from_object, where + ".world_from_object", &poses[i]);
    if (!v.ok()) return v;
    const auto* bytes = reinterpret_cast<const unsigned char*>(o.spheres);
    for (uint32_t k = 0; k < o.sphere_count; ++k) {
      AtmoOccluderSphere sp;
      std::memcpy(&sp, bytes + static_cast<size_t>(k) * sphere_stride, sizeof(sp));
      const std::string at = where + ".spheres[" + std::to_string(k) + "]";
      for (int c = 0; c < 3; ++c)
        if (!std::isfinite(sp.centre_m[c]) || std::abs(sp.centre_m[c]) > 1e5)
          return bad(std::isfinite(sp.centre_m[c]) ? ATMO_ERROR_OUT_OF_RANGE : ATMO_ERROR_NON_FINITE_VALUE,
                     at + ".centre_m[" + std::to_string(c) + "] = " + number(sp.centre_m[c]) +
                         " is outside [-1e5, 1e5] m");
      if (!std::isfinite(sp.radius_m) || sp.radius_m < 0.0 || sp.radius_m > 1e5)
        return bad(std::isfinite(sp.radius_m) ? ATMO_ERROR_OUT_OF_RANGE : ATMO_ERROR_NON_FINITE_VALUE,
                   at + ".radius_m = " + number(sp.radius_m) + " is outside [0, 1e5] m");
      if (sp.radius_m > 0.0) spheres[i].emplace_back(sp.centre_m[0], sp.centre_m[1], sp.centre_m[2], sp.radius_m);
    }
  }
  // Valid: apply.
  out->objects.clear();
  for (uint32_t i = 0; i < s.object_count; ++i)
    out->objects.push_back(shadows::make_occluder_object(std::move(spheres[i]), albedo[i]));
  out->world_from_object = std::move(poses);
  out->ecef_from_world = ecef_from_world_frame(s.world_frame, s.world_origin_geodetic);
  out->flags = s.flags;
  ++out->version;
  return {};
}

Verdict set_occluder_poses_state(const AtmoOccluderPoses& p, ContextOccluders* out) {
  const size_t n = out->objects.size();
  if (p.first > n || p.count > n - p.first)
    return bad(ATMO_ERROR_OUT_OF_RANGE, "AtmoOccluderPoses: objects [" + std::to_string(p.first) + ", " +
                                            std::to_string(uint64_t(p.first) + p.count) +
                                            ") are not within the " + std::to_string(n) + " set_occluders gave");
  if (p.count && !p.world_from_object)
    return bad(ATMO_ERROR_INVALID_ARGUMENT,
               "AtmoOccluderPoses.world_from_object is NULL with count " + std::to_string(p.count));
  std::vector<glm::dmat4> poses(p.count);
  for (uint32_t i = 0; i < p.count; ++i) {
    Verdict v = read_pose(p.world_from_object + 16 * static_cast<size_t>(i),
                          "AtmoOccluderPoses.world_from_object[" + std::to_string(i) + "]", &poses[i]);
    if (!v.ok()) return v;
  }
  std::copy(poses.begin(), poses.end(), out->world_from_object.begin() + p.first);
  ++out->version;
  return {};
}

}  // namespace atmo::abi
