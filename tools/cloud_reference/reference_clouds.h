// reference_clouds.h — clouds the lighting model is measured on against the
// path tracer, shared by tests/clouds/octaves_vs_path_tracer_test.cpp (whose
// stored references are of these very grids) and bench/clouds_error_cost.cpp.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

#include "core/clouds/cloud_volume.h"

namespace atmo::clouds::reference {

// A cumulus-like blob: a flattened sphere with a flat base and noisy edges,
// 600 m across at 20 m voxels, peak optical depth through the centre ~20.
inline CloudVolume blob_cloud() {
  CloudVolume c;
  c.name = "blob";
  c.voxel_size_m = 20.0f;
  const int n = 32;
  c.density = DenseGrid(n, n, n);
  for (int z = 1; z < n - 1; ++z)
    for (int y = 1; y < n - 1; ++y)
      for (int x = 1; x < n - 1; ++x) {
        const glm::vec3 p = (glm::vec3(x, y, z) + 0.5f - 0.5f * n) / (0.5f * n - 1.5f);
        const float r = glm::length(glm::vec3(p.x, p.y, p.z * 1.3f + 0.25f));
        const float wobble = 0.12f * std::sin(7.0f * p.x) * std::sin(5.0f * p.y + 1.0f) * std::cos(6.0f * p.z);
        const float d = std::clamp((1.0f - r + wobble) * 4.0f, 0.0f, 1.0f);
        c.density.at(x, y, z) = z > 4 ? d : 0.0f;
      }
  c.optics.extinction_per_m = 0.06f;
  return c;
}

}  // namespace atmo::clouds::reference
