#include "core/clouds/cloud_shadow.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/clouds/cloud_lighting.h"
#include "core/clouds/parallel_bands.h"

namespace atmo::clouds {

namespace {

constexpr double kMinLightZ = 0.02;  // ~1.1 degrees

// A ray's entry and exit parameters in a box [0, size] (index space); empty when t0 >= t1.
glm::dvec2 box_hit(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& size) {
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-12) {
      if (o[a] < 0.0 || o[a] > size[a]) return {1.0, 0.0};
      continue;
    }
    double ta = (0.0 - o[a]) / d[a], tb = (size[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return {t0, t1};
}

}  // namespace

CloudShadowMap compute_cloud_shadow_map(const CloudField& field, const glm::dvec3& light, int size,
                                        double max_extent_m, float step_voxels, int threads) {
  CloudShadowMap map;
  map.light_direction_enu = light;
  if (field.instances.empty() || size <= 0) return map;
  const bool low = !(light.z > kMinLightZ);
  // The shadows' footprint: each box's corners slid along the light onto z = 0.
  const glm::dvec3 slide = low ? glm::dvec3(0.0) : light / light.z;
  glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const CloudInstance& inst : field.instances) {
    const CloudVolume& v = field.prototypes[static_cast<size_t>(inst.prototype)];
    const glm::dvec3 e = v.extent_m();
    for (int c = 0; c < 8; ++c) {
      const glm::dvec3 corner = inst.origin_enu_m + v.rotation * (e * glm::dvec3(c & 1, (c >> 1) & 1, (c >> 2) & 1));
      const glm::dvec3 g = corner - slide * corner.z;
      lo = glm::min(lo, glm::dvec2(g));
      hi = glm::max(hi, glm::dvec2(g));
    }
  }
  const glm::dvec2 centre = 0.5 * (lo + hi);
  const double extent = std::min(max_extent_m, std::max(hi.x - lo.x, hi.y - lo.y) * 1.02 + 1.0);
  map.size = size;
  map.texel_m = extent / size;
  map.corner_enu_m = centre - 0.5 * extent;
  map.transmittance.assign(static_cast<size_t>(size) * size, 1.0f);
  if (low) return map;  // the light grazes: shadows longer than any map; left unshadowed
  std::vector<double> tau(map.transmittance.size(), 0.0);
  // Bands of rows, one per thread: each texel sums its instances in one
  // order, so the map does not depend on the thread count.
  for_bands(size, threads, [&](int band_lo, int band_hi) {
    for (const CloudInstance& inst : field.instances) {
      const CloudVolume& v = field.prototypes[static_cast<size_t>(inst.prototype)];
      const glm::dvec3 e = v.extent_m();
      // The texels this box shades.
      glm::dvec2 blo(std::numeric_limits<double>::infinity()), bhi(-std::numeric_limits<double>::infinity());
      for (int c = 0; c < 8; ++c) {
        const glm::dvec3 corner = inst.origin_enu_m + v.rotation * (e * glm::dvec3(c & 1, (c >> 1) & 1, (c >> 2) & 1));
        const glm::dvec2 g(corner - slide * corner.z);
        blo = glm::min(blo, g);
        bhi = glm::max(bhi, g);
      }
      const int x0 = std::max(0, static_cast<int>(std::floor((blo.x - map.corner_enu_m.x) / map.texel_m)));
      const int x1 = std::min(size - 1, static_cast<int>(std::floor((bhi.x - map.corner_enu_m.x) / map.texel_m)));
      const int y0 = std::max(band_lo, static_cast<int>(std::floor((blo.y - map.corner_enu_m.y) / map.texel_m)));
      const int y1 = std::min(band_hi - 1, static_cast<int>(std::floor((bhi.y - map.corner_enu_m.y) / map.texel_m)));
      if (y0 > y1 || x0 > x1) continue;
      const glm::dquat to_grid = glm::conjugate(v.rotation);
      const glm::dvec3 d = to_grid * light;  // unit, index space differs by the voxel size only
      const glm::dvec3 grid_size(v.density.nx, v.density.ny, v.density.nz);
      const double vox = v.voxel_size_m;
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const glm::dvec3 g(map.corner_enu_m.x + (x + 0.5) * map.texel_m,
                             map.corner_enu_m.y + (y + 0.5) * map.texel_m, 0.0);
          const glm::dvec3 o = (to_grid * (g - inst.origin_enu_m)) / vox;
          const glm::dvec2 t = box_hit(o, d, grid_size);
          if (!(t.x < t.y)) continue;
          const int steps = std::max(1, static_cast<int>(std::ceil((t.y - t.x) / step_voxels)));
          const double dt = (t.y - t.x) / steps;
          double sum = 0.0;
          for (int i = 0; i < steps; ++i) sum += v.density.sample(glm::vec3(o + d * (t.x + (i + 0.5) * dt)));
          tau[static_cast<size_t>(y) * size + x] += sum * dt * vox * v.optics.extinction_per_m;
        }
    }
  });
  for (size_t i = 0; i < tau.size(); ++i) map.transmittance[i] = static_cast<float>(std::exp(-tau[i]));
  return map;
}

glm::dmat4 cloud_shadow_uvz_from(const CloudShadowMap& map, const glm::dmat4& clouds_from_frame) {
  glm::dmat4 m = cloud_shadow_uv_from_enu(map) * clouds_from_frame;
  for (int col = 0; col < 4; ++col) m[col][2] = clouds_from_frame[col][2];
  return m;
}

glm::dmat4 cloud_shadow_uv_from_enu(const CloudShadowMap& map) {
  glm::dmat4 m(0.0);
  m[3][3] = 1.0;
  if (map.size <= 0) return m;
  const double extent = map.texel_m * map.size;
  const glm::dvec3 l = map.light_direction_enu;
  const double sx = l.z > kMinLightZ ? l.x / l.z : 0.0, sy = l.z > kMinLightZ ? l.y / l.z : 0.0;
  // u = (p.x - sx p.z - corner.x) / extent, v likewise (glm: m[column][row]).
  m[0][0] = 1.0 / extent;
  m[2][0] = -sx / extent;
  m[3][0] = -map.corner_enu_m.x / extent;
  m[1][1] = 1.0 / extent;
  m[2][1] = -sy / extent;
  m[3][1] = -map.corner_enu_m.y / extent;
  return m;
}

double sample_cloud_shadow(const CloudShadowMap& map, const glm::dvec3& p) {
  if (map.size <= 0) return 1.0;
  const glm::dvec4 uv = cloud_shadow_uv_from_enu(map) * glm::dvec4(p, 1.0);
  if (uv.x < 0.0 || uv.y < 0.0 || uv.x > 1.0 || uv.y > 1.0) return 1.0;
  const double fx = uv.x * map.size - 0.5, fy = uv.y * map.size - 0.5;
  const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
  const double ax = fx - x0, ay = fy - y0;
  auto at = [&](int x, int y) {
    x = std::clamp(x, 0, map.size - 1);
    y = std::clamp(y, 0, map.size - 1);
    return static_cast<double>(map.transmittance[static_cast<size_t>(y) * map.size + x]);
  };
  return (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x0 + 1, y0)) + ay * ((1 - ax) * at(x0, y0 + 1) + ax * at(x0 + 1, y0 + 1));
}

}  // namespace atmo::clouds
