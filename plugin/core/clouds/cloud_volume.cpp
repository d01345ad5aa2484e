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

CloudVolume half_resolution(const CloudVolume& v) {
  const DenseGrid& f = v.density;
  CloudVolume h;
  h.name = v.name + " (half resolution)";
  h.density = DenseGrid((f.nx + 1) / 2, (f.ny + 1) / 2, (f.nz + 1) / 2);
  h.voxel_size_m = 2.0f * v.voxel_size_m;
  h.origin_enu_m = v.origin_enu_m;
  h.rotation = v.rotation;
  h.optics = v.optics;
  for (int z = 0; z < h.density.nz; ++z)
    for (int y = 0; y < h.density.ny; ++y)
      for (int x = 0; x < h.density.nx; ++x) {
        float sum = 0.0f;
        for (int c = 0; c < 8; ++c) sum += f.at_or_zero(2 * x + (c & 1), 2 * y + ((c >> 1) & 1), 2 * z + (c >> 2));
        h.density.at(x, y, z) = 0.125f * sum;
      }
  return h;
}

}  // namespace atmo::clouds
