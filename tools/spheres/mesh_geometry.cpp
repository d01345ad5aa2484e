#include "mesh_geometry.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <utility>

namespace atmo::spheres {

double Bounds::longest_side_m() const {
  const glm::dvec3 s = size_m();
  return std::max(s.x, std::max(s.y, s.z));
}

Bounds mesh_bounds(const TriangleMesh& mesh) {
  Bounds b;
  if (mesh.vertices.empty()) return b;
  b.min_m = b.max_m = mesh.vertices[0];
  for (const glm::dvec3& v : mesh.vertices) {
    b.min_m = glm::min(b.min_m, v);
    b.max_m = glm::max(b.max_m, v);
  }
  return b;
}

namespace {

// Signed volumes about a point near the mesh keep the sum's rounding small.
double tetra_volume(const glm::dvec3& o, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  return glm::dot(a - o, glm::cross(b - o, c - o)) / 6.0;
}

std::vector<double> shell_volumes(const TriangleMesh& mesh, const std::vector<int>& shells, int shell_count) {
  const Bounds b = mesh_bounds(mesh);
  const glm::dvec3 o = 0.5 * (b.min_m + b.max_m);
  std::vector<double> volume(static_cast<size_t>(shell_count), 0.0);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    volume[static_cast<size_t>(shells[t])] +=
        tetra_volume(o, mesh.vertices[tri.x], mesh.vertices[tri.y], mesh.vertices[tri.z]);
  }
  return volume;
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[static_cast<size_t>(i)] != i) {
    parent[static_cast<size_t>(i)] = parent[static_cast<size_t>(parent[static_cast<size_t>(i)])];
    i = parent[static_cast<size_t>(i)];
  }
  return i;
}

// 2D edge function of (u, v) at p in the (y, z) plane. edge(u, v, p) is
// exactly -edge(v, u, p) in IEEE arithmetic (no FMA contraction in ISO C++
// mode), so two triangles sharing an edge always agree on p's side of it.
double edge_function(const glm::dvec3& u, const glm::dvec3& v, double py, double pz) {
  return (u.y - py) * (v.z - pz) - (u.z - pz) * (v.y - py);
}

// The side of p when edge_function is exactly zero: p shifted by (eps, eps^2)
// in (y, z) with eps -> 0+. Antisymmetric in (u, v), and zero only for an
// edge that is a point in projection.
int zero_edge_sign(const glm::dvec3& u, const glm::dvec3& v) {
  const double dz = u.z - v.z, dy = u.y - v.y;
  if (dz != 0.0) return dz > 0.0 ? 1 : -1;
  if (dy != 0.0) return dy < 0.0 ? 1 : -1;
  return 0;
}

int side(double e, const glm::dvec3& u, const glm::dvec3& v) { return e > 0.0 ? 1 : e < 0.0 ? -1 : zero_edge_sign(u, v); }

struct Crossing {
  double x_m;
  int shell;
  int delta;  // +1 entering the shell (ray going +x), -1 leaving
};

}  // namespace

double signed_volume_m3(const TriangleMesh& mesh) {
  const std::vector<int> shells(mesh.triangles.size(), 0);
  return mesh.triangles.empty() ? 0.0 : shell_volumes(mesh, shells, 1)[0];
}

std::vector<int> triangle_shells(const TriangleMesh& mesh, int* shell_count) {
  // Weld equal positions, so a mesh written without shared vertices still has its shells.
  const size_t nv = mesh.vertices.size();
  std::vector<int> order(nv);
  std::iota(order.begin(), order.end(), 0);
  auto less = [&](int a, int b) {
    const glm::dvec3 &p = mesh.vertices[static_cast<size_t>(a)], &q = mesh.vertices[static_cast<size_t>(b)];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    if (p.z != q.z) return p.z < q.z;
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<int> canonical(nv);
  for (size_t i = 0; i < nv; ++i) {
    const bool same = i > 0 && mesh.vertices[static_cast<size_t>(order[i])] == mesh.vertices[static_cast<size_t>(order[i - 1])];
    canonical[static_cast<size_t>(order[i])] = same ? canonical[static_cast<size_t>(order[i - 1])] : order[i];
  }
  std::vector<int> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  for (const glm::uvec3& t : mesh.triangles) {
    const int a = find_root(parent, canonical[t.x]);
    for (int k = 1; k < 3; ++k) {
      const int b = find_root(parent, canonical[t[k]]);
      if (a != b) parent[static_cast<size_t>(b)] = a;
    }
  }
  std::map<int, int> shell_of_root;
  std::vector<int> shells(mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const int root = find_root(parent, canonical[mesh.triangles[t].x]);
    auto it = shell_of_root.emplace(root, static_cast<int>(shell_of_root.size())).first;
    shells[t] = it->second;
  }
  if (shell_count) *shell_count = static_cast<int>(shell_of_root.size());
  return shells;
}

std::string closed_mesh_problem(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) return "no triangles";
  std::map<std::pair<unsigned, unsigned>, size_t> directed;  // edge -> triangle that runs it
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k)
      if (tri[k] >= mesh.vertices.size())
        return "triangle " + std::to_string(t) + ": vertex index " + std::to_string(tri[k]) + " out of range (" +
               std::to_string(mesh.vertices.size()) + " vertices)";
    if (tri.x == tri.y || tri.y == tri.z || tri.z == tri.x)
      return "triangle " + std::to_string(t) + " is degenerate (repeats a vertex)";
    for (int k = 0; k < 3; ++k) {
      const std::pair<unsigned, unsigned> e(tri[k], tri[(k + 1) % 3]);
      auto [it, fresh] = directed.emplace(e, t);
      if (!fresh)
        return "edge " + std::to_string(e.first) + "-" + std::to_string(e.second) + " is run in the same direction by triangles " +
               std::to_string(it->second) + " and " + std::to_string(t) + " (inconsistent orientation or a non-manifold edge)";
    }
  }
  for (const auto& [e, t] : directed)
    if (!directed.count({e.second, e.first}))
      return "edge " + std::to_string(e.first) + "-" + std::to_string(e.second) + " of triangle " + std::to_string(t) +
             " has no triangle on its other side (a hole)";
  int shell_count = 0;
  const std::vector<int> shells = triangle_shells(mesh, &shell_count);
  const std::vector<double> volumes = shell_volumes(mesh, shells, shell_count);
  for (int s = 0; s < shell_count; ++s)
    if (!(volumes[static_cast<size_t>(s)] > 0.0))
      return "shell " + std::to_string(s) + " has signed volume " + std::to_string(volumes[static_cast<size_t>(s)]) +
             " m^3 (its triangles face inward)";
  return "";
}

InsideRows inside_rows(const TriangleMesh& mesh, double y0_m, double z0_m, double step_m, int ny, int nz) {
  InsideRows out;
  out.y0_m = y0_m;
  out.z0_m = z0_m;
  out.step_m = step_m;
  out.ny = std::max(ny, 0);
  out.nz = std::max(nz, 0);
  out.rows.assign(static_cast<size_t>(out.ny) * static_cast<size_t>(out.nz), {});
  if (out.rows.empty()) return out;
  int shell_count = 0;
  const std::vector<int> shells = triangle_shells(mesh, &shell_count);

  std::vector<std::vector<Crossing>> crossings(out.rows.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    const glm::dvec3 &a = mesh.vertices[tri.x], &b = mesh.vertices[tri.y], &c = mesh.vertices[tri.z];
    const double ymin = std::min({a.y, b.y, c.y}), ymax = std::max({a.y, b.y, c.y});
    const double zmin = std::min({a.z, b.z, c.z}), zmax = std::max({a.z, b.z, c.z});
    // One row of margin each side: the exact test below decides, not this range.
    const int j0 = std::max(0, static_cast<int>(std::ceil((ymin - y0_m) / step_m)) - 1);
    const int j1 = std::min(out.ny - 1, static_cast<int>(std::floor((ymax - y0_m) / step_m)) + 1);
    const int k0 = std::max(0, static_cast<int>(std::ceil((zmin - z0_m) / step_m)) - 1);
    const int k1 = std::min(out.nz - 1, static_cast<int>(std::floor((zmax - z0_m) / step_m)) + 1);
    for (int k = k0; k <= k1; ++k) {
      const double pz = z0_m + k * step_m;
      for (int j = j0; j <= j1; ++j) {
        const double py = y0_m + j * step_m;
        const double e0 = edge_function(b, c, py, pz), e1 = edge_function(c, a, py, pz), e2 = edge_function(a, b, py, pz);
        const int s0 = side(e0, b, c), s1 = side(e1, c, a), s2 = side(e2, a, b);
        if (s0 == 0 || s0 != s1 || s1 != s2) continue;
        const double sum = e0 + e1 + e2;
        const double x = sum != 0.0 ? (e0 * a.x + e1 * b.x + e2 * c.x) / sum : a.x;
        // All sides positive: the triangle's normal points to +x, so the ray leaves the shell here.
        crossings[static_cast<size_t>(j) + static_cast<size_t>(out.ny) * k].push_back({x, shells[t], s0 > 0 ? -1 : 1});
      }
    }
  }

  std::vector<int> winding(static_cast<size_t>(shell_count), 0);
  for (size_t r = 0; r < crossings.size(); ++r) {
    std::vector<Crossing>& row = crossings[r];
    if (row.empty()) continue;
    std::sort(row.begin(), row.end(), [](const Crossing& p, const Crossing& q) {
      if (p.x_m != q.x_m) return p.x_m < q.x_m;
      if (p.shell != q.shell) return p.shell < q.shell;
      return p.delta > q.delta;
    });
    int active = 0;  // shells with a non-zero winding number
    double start = 0.0;
    std::vector<Interval>& intervals = out.rows[r];
    for (const Crossing& c : row) {
      int& w = winding[static_cast<size_t>(c.shell)];
      const int before = active;
      if (w != 0) --active;
      w += c.delta;
      if (w != 0) ++active;
      if (before == 0 && active > 0) start = c.x_m;
      if (before > 0 && active == 0 && c.x_m > start) {
        if (!intervals.empty() && intervals.back().x1_m >= start) intervals.back().x1_m = c.x_m;
        else intervals.push_back({start, c.x_m});
      }
    }
    for (const Crossing& c : row) winding[static_cast<size_t>(c.shell)] = 0;
  }
  return out;
}

bool point_inside(const TriangleMesh& mesh, const glm::dvec3& p_m) {
  const InsideRows rows = inside_rows(mesh, p_m.y, p_m.z, 1.0, 1, 1);
  for (const Interval& i : rows.rows[0])
    if (p_m.x >= i.x0_m && p_m.x < i.x1_m) return true;
  return false;
}

double overlap_length_m(const std::vector<Interval>& intervals, double x0_m, double x1_m) {
  double total = 0.0;
  for (const Interval& i : intervals) {
    if (i.x0_m >= x1_m) break;
    const double lo = std::max(i.x0_m, x0_m), hi = std::min(i.x1_m, x1_m);
    if (hi > lo) total += hi - lo;
  }
  return total;
}

uint64_t SplitMix64::next() {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double SplitMix64::uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

std::vector<glm::dvec3> sample_surface(const TriangleMesh& mesh, int count, uint64_t seed) {
  std::vector<glm::dvec3> points;
  if (count <= 0 || mesh.triangles.empty()) return points;
  std::vector<double> cumulative(mesh.triangles.size());
  double total = 0.0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    const glm::dvec3 &a = mesh.vertices[tri.x], &b = mesh.vertices[tri.y], &c = mesh.vertices[tri.z];
    total += 0.5 * glm::length(glm::cross(b - a, c - a));
    cumulative[t] = total;
  }
  SplitMix64 rng(seed);
  points.reserve(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    const double u = rng.uniform() * total;
    size_t t = static_cast<size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin());
    t = std::min(t, cumulative.size() - 1);
    const glm::uvec3& tri = mesh.triangles[t];
    const double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
    points.push_back((1.0 - r1) * mesh.vertices[tri.x] + r1 * (1.0 - r2) * mesh.vertices[tri.y] +
                     r1 * r2 * mesh.vertices[tri.z]);
  }
  return points;
}

std::vector<glm::dvec3> sample_edges(const TriangleMesh& mesh, double spacing_m) {
  std::vector<glm::dvec3> points(mesh.vertices.begin(), mesh.vertices.end());
  std::vector<std::pair<unsigned, unsigned>> edges;
  for (const glm::uvec3& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) edges.emplace_back(std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const auto& [i, j] : edges) {
    const glm::dvec3 &a = mesh.vertices[i], &b = mesh.vertices[j];
    const int n = std::max(1, static_cast<int>(std::ceil(glm::length(b - a) / spacing_m)));
    for (int s = 1; s < n; ++s) points.push_back(glm::mix(a, b, static_cast<double>(s) / n));
  }
  return points;
}

}  // namespace atmo::spheres
