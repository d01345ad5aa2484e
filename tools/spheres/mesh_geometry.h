// mesh_geometry.h — what the sphere fit asks of a mesh: bounds, volume,
// closedness, shells, which points are inside, and surface samples.
//
// "Inside" is inside the union of the mesh's shells (connected pieces): a
// point is inside when the winding number of any one shell around it is not
// zero. Inside is found along rays parallel to x: each triangle is crossed by
// a ray or not by an exact rule (the 2D edge functions of a shared edge are
// exact negatives of each other, and a zero one is decided by a fixed
// infinitesimal shift of the ray, simulation of simplicity), so a ray through
// an edge or a vertex is counted once, never twice or not at all.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mesh.h"

namespace atmo::spheres {

struct Bounds {
  glm::dvec3 min_m{0.0};
  glm::dvec3 max_m{0.0};
  glm::dvec3 size_m() const { return max_m - min_m; }
  double longest_side_m() const;
};

Bounds mesh_bounds(const TriangleMesh& mesh);

// Sum of the shells' signed volumes (> 0 for outward-facing shells; overlaps
// of shells count twice).
double signed_volume_m3(const TriangleMesh& mesh);

// "" for a closed, consistently oriented mesh (every edge shared by exactly
// two triangles that run it in opposite directions, no degenerate triangle,
// no index out of range, signed volume > 0); else the first problem found.
std::string closed_mesh_problem(const TriangleMesh& mesh);

// The shell (connected piece, by shared vertex positions) of each triangle,
// numbered from 0; `shell_count` receives how many there are.
std::vector<int> triangle_shells(const TriangleMesh& mesh, int* shell_count = nullptr);

struct Interval {
  double x0_m, x1_m;
};

// The mesh's inside along rows parallel to x on a regular lattice in (y, z):
// row (j, k) lies at y = y0_m + j step_m, z = z0_m + k step_m.
struct InsideRows {
  double y0_m = 0.0, z0_m = 0.0, step_m = 1.0;
  int ny = 0, nz = 0;
  std::vector<std::vector<Interval>> rows;  // index j + ny k; sorted, disjoint
  const std::vector<Interval>* row(int j, int k) const {
    return j < 0 || k < 0 || j >= ny || k >= nz ? nullptr : &rows[static_cast<size_t>(j) + static_cast<size_t>(ny) * k];
  }
};

InsideRows inside_rows(const TriangleMesh& mesh, double y0_m, double z0_m, double step_m, int ny, int nz);

// One point (slow: every triangle; for tests and a few points).
bool point_inside(const TriangleMesh& mesh, const glm::dvec3& p_m);

// The length of [x0, x1] that lies in the sorted, disjoint intervals.
double overlap_length_m(const std::vector<Interval>& intervals, double x0_m, double x1_m);

// Area-weighted uniform random points on the surface (deterministic for a seed).
std::vector<glm::dvec3> sample_surface(const TriangleMesh& mesh, int count, uint64_t seed);

// Points along every edge, no farther apart than `spacing_m` (ends included).
std::vector<glm::dvec3> sample_edges(const TriangleMesh& mesh, double spacing_m);

// A small deterministic generator (splitmix64): the same numbers on every
// platform, unlike the standard library's distributions.
struct SplitMix64 {
  uint64_t state;
  explicit SplitMix64(uint64_t seed) : state(seed) {}
  uint64_t next();
  double uniform();  // [0, 1)
};

}  // namespace atmo::spheres
