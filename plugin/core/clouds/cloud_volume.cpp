#include "core/clouds/cloud_volume.h"

#include <algorithm>

namespace atmo::clouds {

float DenseGrid::sample(const glm::vec3& index_point) const {
  return trilinear_zero_border<float>(nx, ny, nz, index_point, [this](int x, int y, int z) { return at(x, y, z); });
}

float max_density(const DenseGrid& grid) {
  float m = 0.0f;
  for (float v : grid.values) m = std::max(m, v);
  return m;
}

}  // namespace atmo::clouds
