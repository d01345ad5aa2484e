#include "core/clouds/cloud_volume.h"

#include <algorithm>
#include <cmath>

namespace atmo::clouds {

float DenseGrid::sample(const glm::vec3& index_point) const {
  // Shift to voxel-centre coordinates, then blend the 8 neighbours.
  const glm::vec3 p = index_point - 0.5f;
  const int x0 = static_cast<int>(std::floor(p.x));
  const int y0 = static_cast<int>(std::floor(p.y));
  const int z0 = static_cast<int>(std::floor(p.z));
  const float fx = p.x - x0;
  const float fy = p.y - y0;
  const float fz = p.z - z0;
  auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
  const float c00 = lerp(at_or_zero(x0, y0, z0), at_or_zero(x0 + 1, y0, z0), fx);
  const float c10 = lerp(at_or_zero(x0, y0 + 1, z0), at_or_zero(x0 + 1, y0 + 1, z0), fx);
  const float c01 = lerp(at_or_zero(x0, y0, z0 + 1), at_or_zero(x0 + 1, y0, z0 + 1), fx);
  const float c11 = lerp(at_or_zero(x0, y0 + 1, z0 + 1), at_or_zero(x0 + 1, y0 + 1, z0 + 1), fx);
  return lerp(lerp(c00, c10, fy), lerp(c01, c11, fy), fz);
}

float max_density(const DenseGrid& grid) {
  float m = 0.0f;
  for (float v : grid.values) m = std::max(m, v);
  return m;
}

}  // namespace atmo::clouds
