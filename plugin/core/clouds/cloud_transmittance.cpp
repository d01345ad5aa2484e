#include "core/clouds/cloud_transmittance.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace atmo::clouds {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kOpaqueTau = 50.0;

using Box = InstanceBox;

// [t0, t1] of origin + t dir inside [lo, hi] on the axes in `axes` (t1 < t0: a
// miss).
glm::dvec2 clip_to_box(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo, const glm::dvec3& hi, int axes,
                       glm::dvec2 t) {
  for (int a = 0; a < axes; ++a) {
    if (std::abs(d[a]) < 1e-15) {
      if (o[a] < lo[a] || o[a] > hi[a]) return {1.0, 0.0};
      continue;
    }
    double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t.x = std::max(t.x, ta);
    t.y = std::min(t.y, tb);
  }
  return t;
}

// Optical depth of one instance's grid along the ray over [t.x, t.y] (ENU
// metres).
double instance_tau(const CloudField& field, const CloudInstance& inst, const glm::dvec3& o_enu,
                    const glm::dvec3& d_enu, glm::dvec2 t, double step_voxels) {
  const CloudVolume& v = field.prototypes[static_cast<size_t>(inst.prototype)];
  const glm::dquat to_grid = glm::conjugate(v.rotation);
  const double vox = v.voxel_size_m;
  const glm::dvec3 o = (to_grid * (o_enu - inst.origin_enu_m)) / vox;  // index space
  const glm::dvec3 d = to_grid * d_enu;                                // unit: index space differs by vox only
  const glm::dvec3 size(v.density.nx, v.density.ny, v.density.nz);
  t = clip_to_box(o, d, glm::dvec3(0.0), size, 3, t / vox);
  if (!(t.x < t.y)) return 0.0;
  const int steps = std::max(1, static_cast<int>(std::ceil((t.y - t.x) / step_voxels)));
  const double dt = (t.y - t.x) / steps;
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) sum += v.density.sample(glm::vec3(o + d * (t.x + (i + 0.5) * dt)));
  return sum * dt * vox * v.optics.extinction_per_m;
}

}  // namespace

CloudRayIndex build_cloud_ray_index(const CloudField& field, int max_cells_per_side) {
  CloudRayIndex ix;
  if (field.instances.empty()) return ix;
  std::vector<Box> boxes;
  boxes.reserve(field.instances.size());
  glm::dvec3 lo(kInf), hi(-kInf);
  double widest = 0.0;
  for (const CloudInstance& inst : field.instances) {
    boxes.push_back(instance_box(field, inst));
    lo = glm::min(lo, boxes.back().lo);
    hi = glm::max(hi, boxes.back().hi);
    widest = std::max({widest, boxes.back().hi.x - boxes.back().lo.x, boxes.back().hi.y - boxes.back().lo.y});
  }
  const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
  const int side = std::max(1, max_cells_per_side);
  ix.cell_m = std::max({widest, extent / side, 1.0});
  ix.nx = std::clamp(static_cast<int>(std::ceil((hi.x - lo.x) / ix.cell_m)), 1, side);
  ix.ny = std::clamp(static_cast<int>(std::ceil((hi.y - lo.y) / ix.cell_m)), 1, side);
  ix.corner_enu_m = glm::dvec2(lo);
  ix.z_lo_m = lo.z;
  ix.z_hi_m = hi.z;
  auto cell_range = [&](const Box& b, int* x0, int* x1, int* y0, int* y1) {
    *x0 = std::clamp(static_cast<int>(std::floor((b.lo.x - lo.x) / ix.cell_m)), 0, ix.nx - 1);
    *x1 = std::clamp(static_cast<int>(std::floor((b.hi.x - lo.x) / ix.cell_m)), 0, ix.nx - 1);
    *y0 = std::clamp(static_cast<int>(std::floor((b.lo.y - lo.y) / ix.cell_m)), 0, ix.ny - 1);
    *y1 = std::clamp(static_cast<int>(std::floor((b.hi.y - lo.y) / ix.cell_m)), 0, ix.ny - 1);
  };
  // Two passes (count, then fill): one flat array, no per-bucket vectors.
  ix.start.assign(static_cast<size_t>(ix.nx) * ix.ny + 1, 0);
  int x0, x1, y0, y1;
  for (const Box& b : boxes) {
    cell_range(b, &x0, &x1, &y0, &y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) ++ix.start[static_cast<size_t>(y) * ix.nx + x + 1];
  }
  for (size_t c = 1; c < ix.start.size(); ++c) ix.start[c] += ix.start[c - 1];
  ix.items.resize(ix.start.back());
  std::vector<uint32_t> fill(ix.start.begin(), ix.start.end() - 1);
  for (size_t i = 0; i < boxes.size(); ++i) {
    cell_range(boxes[i], &x0, &x1, &y0, &y1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) ix.items[fill[static_cast<size_t>(y) * ix.nx + x]++] = static_cast<uint32_t>(i);
  }
  return ix;
}

void instances_near(const CloudRayIndex& ix, const glm::dvec2& lo, const glm::dvec2& hi, std::vector<uint32_t>* out) {
  out->clear();
  if (ix.nx == 0 || ix.ny == 0 || !(lo.x <= hi.x) || !(lo.y <= hi.y)) return;
  auto cell = [&](double v, double corner, int n) {
    return std::clamp(static_cast<int>(std::floor(std::clamp((v - corner) / ix.cell_m, -1.0, double(n)))), 0, n - 1);
  };
  const int x0 = cell(lo.x, ix.corner_enu_m.x, ix.nx), x1 = cell(hi.x, ix.corner_enu_m.x, ix.nx);
  const int y0 = cell(lo.y, ix.corner_enu_m.y, ix.ny), y1 = cell(hi.y, ix.corner_enu_m.y, ix.ny);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const size_t b = static_cast<size_t>(y) * ix.nx + x;
      out->insert(out->end(), ix.items.begin() + ix.start[b], ix.items.begin() + ix.start[b + 1]);
    }
  std::sort(out->begin(), out->end());
  out->erase(std::unique(out->begin(), out->end()), out->end());
}

double transmittance_along_ray(const CloudField& field, const CloudRayIndex& ix, const glm::dvec3& o,
                               const glm::dvec3& d, double max_distance_m, double step_voxels) {
  if (ix.nx <= 0 || field.instances.empty()) return 1.0;
  // The part of the ray inside the clouds' height range and over the buckets.
  const glm::dvec3 lo(ix.corner_enu_m, ix.z_lo_m);
  const glm::dvec3 hi(ix.corner_enu_m + ix.cell_m * glm::dvec2(ix.nx, ix.ny), ix.z_hi_m);
  const glm::dvec2 t = clip_to_box(o, d, lo, hi, 3, glm::dvec2(0.0, max_distance_m));
  if (!(t.x < t.y)) return 1.0;
  // The buckets the ray's (east, north) track crosses over [t.x, t.y] (a 2D
  // DDA).
  std::vector<uint32_t> candidates;
  const glm::dvec3 p = o + d * t.x;
  int cx = std::clamp(static_cast<int>(std::floor((p.x - lo.x) / ix.cell_m)), 0, ix.nx - 1);
  int cy = std::clamp(static_cast<int>(std::floor((p.y - lo.y) / ix.cell_m)), 0, ix.ny - 1);
  const int sx = d.x > 0.0 ? 1 : -1, sy = d.y > 0.0 ? 1 : -1;
  auto next_edge = [&](int c, int s, double from, double dir, double corner) {
    if (std::abs(dir) < 1e-15) return kInf;
    return (corner + (c + (s > 0 ? 1 : 0)) * ix.cell_m - from) / dir;  // t from the ray's origin
  };
  double tx = next_edge(cx, sx, o.x, d.x, lo.x), ty = next_edge(cy, sy, o.y, d.y, lo.y);
  const double dtx = std::abs(d.x) < 1e-15 ? kInf : ix.cell_m / std::abs(d.x);
  const double dty = std::abs(d.y) < 1e-15 ? kInf : ix.cell_m / std::abs(d.y);
  for (;;) {
    const size_t c = static_cast<size_t>(cy) * ix.nx + cx;
    candidates.insert(candidates.end(), ix.items.begin() + ix.start[c], ix.items.begin() + ix.start[c + 1]);
    if (std::min(tx, ty) >= t.y) break;
    if (tx < ty) {
      cx += sx;
      tx += dtx;
    } else {
      cy += sy;
      ty += dty;
    }
    if (cx < 0 || cy < 0 || cx >= ix.nx || cy >= ix.ny) break;
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  double tau = 0.0;
  for (uint32_t i : candidates) {
    tau += instance_tau(field, field.instances[i], o, d, t, step_voxels);
    if (tau > kOpaqueTau) return 0.0;
  }
  return std::exp(-tau);
}

}  // namespace atmo::clouds
