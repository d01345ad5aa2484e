// occluder_inputs.h — set_occluders and set_occluder_poses: validation of the
// host's objects (spheres, albedo, poses) into the context's occluders
// (core/shadows). Each call is checked whole before anything changes; an
// error names the struct, the object's and the sphere's index and the field.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "abi/validation.h"
#include "atmo/atmo.h"
#include "core/shadows/occlusion_frame.h"

namespace atmo::abi {

struct ContextOccluders {
  std::vector<shadows::OccluderObject> objects;  // in their own frames
  std::vector<glm::dmat4> world_from_object;     // their poses in the host's world frame
  glm::dmat4 ecef_from_world{1.0};
  uint32_t flags = 0;                            // AtmoOcclusionFlags
  uint64_t version = 0;                          // bumps on every change
};

Verdict set_occluders_state(const AtmoOccludersState& s, ContextOccluders* out);
Verdict set_occluder_poses_state(const AtmoOccluderPoses& p, ContextOccluders* out);

}  // namespace atmo::abi
