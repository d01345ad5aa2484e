// cloud_field.h — a scene's clouds: a few volumes (prototypes) and where each
// copy stands. Copies are translated only, never rotated or scaled, so every
// copy of a prototype shares its density and its light grid (the sun's
// direction in the grid's axes is the same for all of them): hundreds of
// clouds cost the memory and the lighting of a few dozen. Shadows cast from
// one cloud onto another are not modelled (docs/CLOUDS.md).
#pragma once

#include <vector>

#include "core/clouds/cloud_volume.h"

namespace atmo::clouds {

struct CloudInstance {
  int prototype = 0;              // index into CloudField::prototypes
  glm::dvec3 origin_enu_m{0.0};   // replaces the prototype's origin_enu_m
};

// The scene-frame (ENU) bounding box of an instance's grid (turned by its prototype's rotation).
struct InstanceBox {
  glm::dvec3 lo, hi;
};

struct CloudField;
InstanceBox instance_box(const CloudField& field, const CloudInstance& inst);

struct CloudField {
  std::vector<CloudVolume> prototypes;
  std::vector<CloudInstance> instances;

  size_t memory_bytes() const {
    size_t b = 0;
    for (const CloudVolume& v : prototypes) b += v.memory_bytes();
    return b;
  }
};

inline InstanceBox instance_box(const CloudField& field, const CloudInstance& inst) {
  const CloudVolume& v = field.prototypes[static_cast<size_t>(inst.prototype)];
  const glm::dvec3 e = v.extent_m();
  InstanceBox b{glm::dvec3(1e300), glm::dvec3(-1e300)};
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 corner = inst.origin_enu_m + v.rotation * (e * glm::dvec3(c & 1, (c >> 1) & 1, (c >> 2) & 1));
    b.lo = glm::min(b.lo, corner);
    b.hi = glm::max(b.hi, corner);
  }
  return b;
}

}  // namespace atmo::clouds
