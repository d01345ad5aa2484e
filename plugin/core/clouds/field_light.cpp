#include "core/clouds/field_light.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace atmo::clouds {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Light components below this (grid axes) leave through no face of that axis.
constexpr double kAxisEps = 1e-6;

// Clips the ray q + d t, t in [*t0, *t1], to the box [lo, hi]; false when
// nothing (or a single point) is left.
bool clip_to_box(const glm::dvec3& q, const glm::dvec3& d, const glm::dvec3& lo, const glm::dvec3& hi, double* t0,
                 double* t1) {
  for (int a = 0; a < 3; ++a) {
    if (std::abs(d[a]) < 1e-12) {
      if (q[a] < lo[a] || q[a] > hi[a]) return false;
      continue;
    }
    const double inv = 1.0 / d[a];
    double ta = (lo[a] - q[a]) * inv, tb = (hi[a] - q[a]) * inv;
    if (ta > tb) std::swap(ta, tb);
    *t0 = std::max(*t0, ta);
    *t1 = std::min(*t1, tb);
    if (!(*t0 < *t1)) return false;
  }
  return true;
}

glm::dvec3 grid_size(const DenseGrid& g) { return glm::dvec3(g.nx, g.ny, g.nz); }

// DenseGrid::sample (trilinear, zero outside) with the bounds checks only
// where the eight voxels are not all inside: most samples of a long ray.
inline float sample_density(const DenseGrid& g, const glm::vec3& index_point) {
  const glm::vec3 p = index_point - 0.5f;
  const float fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy), z0 = static_cast<int>(fz);
  if (x0 < 0 || y0 < 0 || z0 < 0 || x0 + 1 >= g.nx || y0 + 1 >= g.ny || z0 + 1 >= g.nz) return g.sample(index_point);
  const float ax = p.x - fx, ay = p.y - fy, az = p.z - fz;
  const size_t sy = static_cast<size_t>(g.nx), sz = sy * static_cast<size_t>(g.ny);
  const float* v = &g.values[g.index(x0, y0, z0)];
  const float c00 = v[0] + ax * (v[1] - v[0]);
  const float c10 = v[sy] + ax * (v[sy + 1] - v[sy]);
  const float c01 = v[sz] + ax * (v[sz + 1] - v[sz]);
  const float c11 = v[sz + sy] + ax * (v[sz + sy + 1] - v[sz + sy]);
  const float c0 = c00 + ay * (c10 - c00), c1 = c01 + ay * (c11 - c01);
  return c0 + az * (c1 - c0);
}

// Optical depth of the other grid along p + dir_grid t, t in [t0, t1]
// (this prototype's index units), midpoint steps of at most o.step.
double integrate_other(const CloudField& field, const FieldLightPlan::Other& o, const glm::dvec3& p, double t0,
                       double t1) {
  const DenseGrid& g = field.prototypes[o.prototype].density;
  const glm::dvec3 q = o.m * p + o.b;
  if (!clip_to_box(q, o.d, glm::dvec3(0.0), grid_size(g), &t0, &t1)) return 0.0;
  const int steps = std::max(1, static_cast<int>(std::ceil((t1 - t0) / o.step)));
  const double dt = (t1 - t0) / steps;
  // Single precision along the segment: index coordinates of a few hundred
  // voxels at most, so ~1e-5 voxel.
  const glm::vec3 start(q + o.d * (t0 + 0.5 * dt));
  const glm::vec3 stride(o.d * dt);
  float sum = 0.0f;
  for (int i = 0; i < steps; ++i) sum += sample_density(g, start + stride * static_cast<float>(i));
  return static_cast<double>(sum) * dt * o.tau_per_unit;
}

double integrate_all(const CloudField& field, const std::vector<FieldLightPlan::Other>& others, const glm::dvec3& p,
                     double t0, double t1) {
  double sum = 0.0;
  for (const FieldLightPlan::Other& o : others) sum += integrate_other(field, o, p, t0, t1);
  return sum;
}

void other_axes(int axis, int* u, int* w) {
  *u = axis == 0 ? 1 : 0;
  *w = axis == 2 ? 1 : 2;
}

// Breakpoints along an axis of n voxels: 0, 0.5, 0.5 + L, 0.5 + 2L, ..., n - 0.5, n.
std::vector<double> breakpoints(double n, double interval) {
  std::vector<double> b{0.0};
  if (n <= 1.0) {
    b.push_back(n);
    return b;
  }
  // On voxel centres; a last piece shorter than a quarter interval joins the one before.
  for (int k = 0; 0.5 + k * interval < n - 0.5 - 0.25 * interval; ++k) b.push_back(0.5 + k * interval);
  b.push_back(n - 0.5);
  b.push_back(n);
  return b;
}

double node_position(const std::vector<double>& b, int node) {
  const int i = node / 2;
  return (node & 1) ? 0.5 * (b[i] + b[i + 1]) : b[i];
}

// The interval holding c and the quadratic weights of its three nodes.
int quadratic_weights(const std::vector<double>& b, double c, float w[3]) {
  const int last = static_cast<int>(b.size()) - 2;
  int i = static_cast<int>(std::upper_bound(b.begin(), b.end(), c) - b.begin()) - 1;
  i = std::clamp(i, 0, last);
  const double t = std::clamp((c - b[i]) / (b[i + 1] - b[i]), 0.0, 1.0);
  w[0] = static_cast<float>(2.0 * (t - 0.5) * (t - 1.0));
  w[1] = static_cast<float>(-4.0 * t * (t - 1.0));
  w[2] = static_cast<float>(2.0 * t * (t - 0.5));
  return 2 * i;
}

// The map at (cu, cw); false where the cell is rough (march instead).
bool interpolate_face(const FieldLightPlan::FaceMap& f, double cu, double cw, float* tau) {
  float wu[3], ww[3];
  const int iu = quadratic_weights(f.bu, cu, wu), iw = quadratic_weights(f.bw, cw, ww);
  if (f.rough[static_cast<size_t>(iw / 2) * (f.nu / 2) + iu / 2]) return false;
  float sum = 0.0f, lo = 3e38f, hi = 0.0f;
  for (int j = 0; j < 3; ++j) {
    const float* row = &f.tau[static_cast<size_t>(iw + j) * f.nu + iu];
    sum += ww[j] * (wu[0] * row[0] + wu[1] * row[1] + wu[2] * row[2]);
    lo = std::min({lo, row[0], row[1], row[2]});
    hi = std::max({hi, row[0], row[1], row[2]});
  }
  // The quadratic overshoots next to a kink (a cloud's edge): no further than its nodes.
  *tau = std::clamp(sum, lo, hi);
  return true;
}

// Where the ray from p leaves the box, as the exit axis (-1: none) and *t.
struct ExitFaces {
  glm::dvec3 face{0.0}, inv{0.0};  // per axis: coordinate of the face the light leaves through, 1/dir (0: none)
  ExitFaces(const glm::dvec3& size, const glm::dvec3& dir) {
    for (int a = 0; a < 3; ++a) {
      if (std::abs(dir[a]) < kAxisEps) continue;
      face[a] = dir[a] > 0.0 ? size[a] : 0.0;
      inv[a] = 1.0 / dir[a];
    }
  }
  int exit(const glm::dvec3& p, double* t_exit) const {
    int axis = -1;
    *t_exit = kInf;
    for (int a = 0; a < 3; ++a) {
      if (inv[a] == 0.0) continue;
      const double t = (face[a] - p[a]) * inv[a];
      if (t < *t_exit) *t_exit = t, axis = a;
    }
    *t_exit = std::max(*t_exit, 0.0);
    return axis;
  }
};

}  // namespace

int sole_instance(const CloudField& field, int prototype) {
  int found = -1;
  for (size_t i = 0; i < field.instances.size(); ++i) {
    if (field.instances[i].prototype != prototype) continue;
    if (found >= 0) return -1;
    found = static_cast<int>(i);
  }
  return found;
}

FieldNeighbours field_neighbours(const CloudField& field, const CloudRayIndex& index) {
  FieldNeighbours n;
  n.index = &index;
  n.sole.assign(field.prototypes.size(), -1);
  std::vector<int> count(field.prototypes.size(), 0);
  for (size_t i = 0; i < field.instances.size(); ++i) {
    const int p = field.instances[i].prototype;
    if (p < 0 || p >= static_cast<int>(count.size())) continue;
    if (++count[static_cast<size_t>(p)] == 1) n.sole[static_cast<size_t>(p)] = static_cast<int>(i);
  }
  for (size_t p = 0; p < count.size(); ++p)
    if (count[p] != 1) n.sole[p] = -1;
  return n;
}

namespace {

// The prototype's sole instance (-1: none or several), from the neighbours when given.
int sole_of(const CloudField& field, int prototype, const FieldNeighbours* neighbours) {
  if (neighbours && prototype >= 0 && prototype < static_cast<int>(neighbours->sole.size()))
    return neighbours->sole[static_cast<size_t>(prototype)];
  return sole_instance(field, prototype);
}

// The instances a search over the ENU rectangle [lo, hi] must look at: those
// near it (with neighbours), else every one.
void candidates(const CloudField& field, const FieldNeighbours* neighbours, const glm::dvec2& lo, const glm::dvec2& hi,
                std::vector<uint32_t>* out) {
  if (neighbours && neighbours->index) {
    instances_near(*neighbours->index, lo, hi, out);
    return;
  }
  out->resize(field.instances.size());
  for (size_t i = 0; i < out->size(); ++i) (*out)[i] = static_cast<uint32_t>(i);
}

}  // namespace

ContinuingSides continuing_sides(const CloudField& field, int prototype, const FieldNeighbours* neighbours) {
  ContinuingSides sides;
  const int self = sole_of(field, prototype, neighbours);
  if (self < 0) return sides;
  const CloudVolume& vol = field.prototypes[static_cast<size_t>(prototype)];
  if (vol.density.empty()) return sides;
  const glm::dvec3 size = grid_size(vol.density);
  const glm::dmat3 to_enu = glm::mat3_cast(vol.rotation) * static_cast<double>(vol.voxel_size_m);
  const glm::dvec3 origin = field.instances[static_cast<size_t>(self)].origin_enu_m;
  std::vector<uint32_t> near;
  auto in_another_grid = [&](const glm::dvec3& p_index) {
    const glm::dvec3 p = origin + to_enu * p_index;
    candidates(field, neighbours, glm::dvec2(p), glm::dvec2(p), &near);
    for (const uint32_t i : near) {
      if (static_cast<int>(i) == self) continue;
      const CloudInstance& other = field.instances[i];
      const CloudVolume& v = field.prototypes[static_cast<size_t>(other.prototype)];
      const glm::dvec3 q = glm::inverse(v.rotation) * (p - other.origin_enu_m) / static_cast<double>(v.voxel_size_m);
      const glm::dvec3 n = grid_size(v.density);
      if (q.x >= 0.0 && q.y >= 0.0 && q.z >= 0.0 && q.x < n.x && q.y < n.y && q.z < n.z) return true;
    }
    return false;
  };
  // Face `axis` (0: x, 1: y) at index `at` (-1 or n + 1): two of three points beyond it in another grid.
  auto goes_on = [&](int axis, double at) {
    int hits = 0;
    for (double f : {0.25, 0.5, 0.75}) {
      glm::dvec3 p(0.0, 0.0, 0.5 * size.z);
      p[axis] = at;
      p[1 - axis] = f * size[1 - axis];
      hits += in_another_grid(p) ? 1 : 0;
    }
    return hits >= 2;
  };
  sides.west = goes_on(0, -1.0);
  sides.east = goes_on(0, size.x + 1.0);
  sides.south = goes_on(1, -1.0);
  sides.north = goes_on(1, size.y + 1.0);
  return sides;
}

FieldLightPlan plan_field_light(const CloudField& field, int prototype, const glm::dvec3& light_dir_enu,
                                const FieldLightOptions& options, const FieldNeighbours* neighbours) {
  FieldLightPlan plan;
  if (prototype < 0 || prototype >= static_cast<int>(field.prototypes.size())) return plan;
  // A shared grid serves copies in different neighbourhoods: it cannot hold
  // one copy's shadow, so shared prototypes keep their own tau_light only.
  const int self = sole_of(field, prototype, neighbours);
  if (self < 0) return plan;
  const CloudVolume& vol = field.prototypes[prototype];
  if (vol.density.empty()) return plan;
  const glm::dvec3 size = grid_size(vol.density);
  const glm::dvec3 dir = glm::normalize(glm::inverse(vol.rotation) * light_dir_enu);
  plan.dir_grid = dir;
  plan.exact = options.exact;
  const float step_voxels = options.step_voxels > 0.0f ? options.step_voxels : kDepthStepVoxels;

  // This prototype's index space -> ENU: origin + R * p * v.
  const glm::dmat3 to_enu = glm::mat3_cast(vol.rotation) * static_cast<double>(vol.voxel_size_m);
  const glm::dvec3 origin = field.instances[self].origin_enu_m;
  // Only grids the box swept along the light meets before it leaves the
  // field's heights can be in the way: those near that sweep's footprint.
  std::vector<uint32_t> near;
  {
    const InstanceBox box = instance_box(field, field.instances[static_cast<size_t>(self)]);
    const glm::dvec3 d = glm::normalize(light_dir_enu);
    double reach = kInf;
    if (neighbours && neighbours->index) {
      const CloudRayIndex& ix = *neighbours->index;
      if (d.z > 1e-9) reach = (ix.z_hi_m - box.lo.z) / d.z;
      if (d.z < -1e-9) reach = (ix.z_lo_m - box.hi.z) / d.z;
      reach = std::min(std::max(reach, 0.0), 2.0 * ix.cell_m * (ix.nx + ix.ny));  // beyond the field: the field
    }
    const glm::dvec2 far = glm::dvec2(d) * (std::isfinite(reach) ? reach : 0.0);
    candidates(field, neighbours, glm::min(glm::dvec2(box.lo), glm::dvec2(box.lo) + far),
               glm::max(glm::dvec2(box.hi), glm::dvec2(box.hi) + far), &near);
  }
  for (const uint32_t i : near) {
    if (static_cast<int>(i) == self) continue;
    const CloudInstance& inst = field.instances[i];
    if (inst.prototype < 0 || inst.prototype >= static_cast<int>(field.prototypes.size())) continue;
    const CloudVolume& other = field.prototypes[inst.prototype];
    if (other.density.empty() || other.optics.extinction_per_m <= 0.0f) continue;
    FieldLightPlan::Other o;
    o.prototype = inst.prototype;
    const glm::dmat3 from_enu = glm::mat3_cast(glm::inverse(other.rotation)) / static_cast<double>(other.voxel_size_m);
    o.m = from_enu * to_enu;
    o.b = from_enu * (origin - inst.origin_enu_m);
    o.d = o.m * dir;
    o.tau_per_unit = static_cast<double>(vol.voxel_size_m) * other.optics.extinction_per_m;
    o.step = step_voxels / std::max(glm::length(o.d), 1e-12);
    // The other box in this prototype's index space (its bounding box when turned).
    const glm::dmat3 back = glm::inverse(o.m);
    const glm::dvec3 n = grid_size(other.density);
    glm::dvec3 lo(kInf), hi(-kInf);
    for (int c = 0; c < 8; ++c) {
      const glm::dvec3 corner((c & 1) ? n.x : 0.0, (c & 2) ? n.y : 0.0, (c & 4) ? n.z : 0.0);
      const glm::dvec3 q = back * (corner - o.b);
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
    // Ahead: the box swept along the light meets the other box, i.e. the ray
    // from 0 along dir meets the Minkowski difference [lo - size, hi].
    double t0 = 0.0, t1 = kInf;
    if (!clip_to_box(glm::dvec3(0.0), dir, lo - size, hi, &t0, &t1)) continue;
    plan.ahead.push_back(o);
    const bool overlaps = lo.x < size.x && lo.y < size.y && lo.z < size.z && hi.x > 0.0 && hi.y > 0.0 && hi.z > 0.0;
    if (overlaps) plan.overlapping.push_back(o);
  }
  if (plan.ahead.empty()) return plan;  // nothing in the way: prototype stays -1
  plan.prototype = prototype;
  if (plan.exact) return plan;

  // Exit maps: the optical depth beyond the grid from nodes on each face the
  // light leaves through. The rays go outwards, so they never re-enter this
  // (convex) grid: only the other grids count. A face gets a map only when
  // it has fewer nodes than voxels whose rays leave through it (at high Sun
  // few rays leave through the sides); otherwise those voxels march.
  const DenseGrid& g = vol.density;
  const ExitFaces exits(size, dir);
  size_t leaving[3] = {0, 0, 0};
  for (int z = 0; z < g.nz; ++z)
    for (int y = 0; y < g.ny; ++y)
      for (int x = 0; x < g.nx; ++x) {
        double t;
        const int a = exits.exit(glm::dvec3(x + 0.5, y + 0.5, z + 0.5), &t);
        if (a >= 0) ++leaving[a];
      }
  for (int a = 0; a < 3; ++a) {
    if (exits.inv[a] == 0.0) continue;
    FieldLightPlan::FaceMap& f = plan.faces[a];
    int u, w;
    other_axes(a, &u, &w);
    f.axis = a;
    f.bu = breakpoints(size[u], std::max(0.25f, options.map_interval_voxels[u]));
    f.bw = breakpoints(size[w], std::max(0.25f, options.map_interval_voxels[w]));
    f.nu = 2 * static_cast<int>(f.bu.size() - 1) + 1;
    f.nw = 2 * static_cast<int>(f.bw.size() - 1) + 1;
    if (static_cast<size_t>(f.nu) * f.nw >= leaving[a]) {
      f.bu.clear(), f.bw.clear(), f.nu = f.nw = 0;  // marched per voxel
      continue;
    }
    f.tau.assign(static_cast<size_t>(f.nu) * f.nw, 0.0f);
    glm::dvec3 e(0.0);
    e[a] = exits.face[a];
    for (int iw = 0; iw < f.nw; ++iw)
      for (int iu = 0; iu < f.nu; ++iu) {
        e[u] = node_position(f.bu, iu);
        e[w] = node_position(f.bw, iw);
        f.tau[static_cast<size_t>(iw) * f.nu + iu] = static_cast<float>(integrate_all(field, plan.ahead, e, 0.0, kInf));
      }
    // Rough cells: a midpoint node off the mean of its interval's ends by
    // more than the tolerance (a kink inside the interval, which the
    // quadratic would smear) marks the cells that use it.
    const int cu = f.nu / 2, cw = f.nw / 2;
    f.rough.assign(static_cast<size_t>(cu) * cw, 0);
    auto at = [&](int iu, int iw) { return f.tau[static_cast<size_t>(iw) * f.nu + iu]; };
    auto mark = [&](int iu, int iw) {  // node (iu, iw): every cell it touches
      for (int jw = std::max(0, (iw - 1) / 2); jw <= std::min(cw - 1, iw / 2); ++jw)
        for (int ju = std::max(0, (iu - 1) / 2); ju <= std::min(cu - 1, iu / 2); ++ju)
          f.rough[static_cast<size_t>(jw) * cu + ju] = 1;
    };
    for (int iw = 0; iw < f.nw; ++iw)
      for (int iu = 0; iu < f.nu; ++iu) {
        const float c = at(iu, iw), tol = options.rough_abs + options.rough_rel * c;
        if ((iu & 1) && std::abs(c - 0.5f * (at(iu - 1, iw) + at(iu + 1, iw))) > tol) mark(iu, iw);
        if ((iw & 1) && std::abs(c - 0.5f * (at(iu, iw - 1) + at(iu, iw + 1))) > tol) mark(iu, iw);
      }
  }
  return plan;
}

void add_field_light_slices(const CloudField& field, const FieldLightPlan& plan, int z_begin, int z_end,
                            LightDepths* depths) {
  if (plan.prototype < 0 || plan.prototype >= static_cast<int>(field.prototypes.size()) || depths == nullptr) return;
  const DenseGrid& g = field.prototypes[plan.prototype].density;
  if (depths->nx != g.nx || depths->ny != g.ny || depths->nz != g.nz || depths->tau.size() != g.voxel_count()) return;
  const ExitFaces exits(grid_size(g), plan.dir_grid);
  for (int z = std::max(z_begin, 0); z < std::min(z_end, g.nz); ++z)
    for (int y = 0; y < g.ny; ++y)
      for (int x = 0; x < g.nx; ++x) {
        const glm::dvec3 p(x + 0.5, y + 0.5, z + 0.5);
        double t_exit;
        const int axis = exits.exit(p, &t_exit);
        if (axis < 0) continue;
        const FieldLightPlan::FaceMap& f = plan.faces[axis];
        // Inside this grid: the grids that overlap it (deck tiles: the two
        // voxels their border rings share); beyond it: the exit map.
        float beyond = 0.0f;
        bool mapped = !plan.exact && !f.tau.empty();
        if (mapped) {
          const glm::dvec3 e = p + plan.dir_grid * t_exit;
          int u, w;
          other_axes(axis, &u, &w);
          mapped = interpolate_face(f, e[u], e[w], &beyond);
        }
        const double add = mapped ? integrate_all(field, plan.overlapping, p, 0.0, t_exit) + beyond
                                  : integrate_all(field, plan.ahead, p, 0.0, kInf);
        depths->tau[depths->index(x, y, z)].x += static_cast<float>(add);
      }
}

void add_field_light_depths(const CloudField& field, const glm::dvec3& light_dir_enu,
                            std::vector<LightDepths>* depths, const FieldLightOptions& options) {
  if (depths == nullptr || depths->size() != field.prototypes.size()) return;
  for (size_t p = 0; p < field.prototypes.size(); ++p) {
    const FieldLightPlan plan = plan_field_light(field, static_cast<int>(p), light_dir_enu, options);
    add_field_light_slices(field, plan, 0, field.prototypes[p].density.nz, &(*depths)[p]);
  }
}

}  // namespace atmo::clouds
