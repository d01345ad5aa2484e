// sphere_fit.h — a set of spheres that bounds a closed mesh, for soft sky
// shadows from occluders made of spheres (Ren et al. 2006; Guerrero's thesis).
//
// The fit is Wang et al. 2006, "Variational sphere set approximation for
// solid objects": the object is sampled by points (the centres of a regular
// grid's cells that are inside the mesh, surface points, the mesh's vertices);
// each sphere owns a cluster of points and is the smallest sphere about its
// centre that holds them. The fit minimises the outside volume
//   E = sum_i V(S_i \ O)
// by alternating (1) a flood-fill assignment: the spheres grow over the
// points' neighbour graph from their deepest points, a point going to the
// sphere that reaches it with the smallest signed distance |q - c| - r (so
// clusters stay connected, and where spheres overlap a point goes to the
// sphere it is deepest in, which lets the others shrink), and (2) moving each
// centre to minimise its sphere's outside volume (a compass search). Spheres
// are made by splitting the sphere of largest outside volume, from one sphere
// up to K. Teleportation escapes local minima: delete the most-overlapped
// sphere, split the one of largest outside volume, a few rounds, and keep the
// result only if E went down.
//
// V(S \ O) is integrated along rows parallel to x on a lattice of half the
// grid step in y and z, exactly along each row (the mesh's inside intervals
// against the sphere's chord).
//
// Coverage: every sample point is in its sphere by construction. A denser set
// of check points (all vertices, points every quarter grid step along every
// edge, 4x the surface points, the inside of a grid twice as fine) is checked
// after the splits, every 10 iterations and up to 3 times at the end: the
// points left out join the samples, so the fit takes them in where that costs
// least. Any still left out at the very end are taken in by growing the sphere
// nearest to holding them. What can stay uncovered is slivers between check
// points (measure_fit's uncovered_volume_m3: under 0.05 % of the mesh volume
// for the shipped objects; the tests allow 0.5 %).
//
// Deterministic: the same mesh, options and seed give the same spheres.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "mesh.h"

namespace atmo::spheres {

struct Sphere {
  glm::dvec3 centre_m{0.0};
  double radius_m = 0.0;
};

struct FitOptions {
  int spheres = 32;
  int grid = 48;  // interior samples along the longest side
  int surface_points = 4000;
  int iterations = 30;  // rounds of assignment + centre optimisation, each followed by one teleport attempt
  uint64_t seed = 1;    // the surface samples
  std::function<void(const std::string&)> progress;  // one line at a time, no newline
};

struct FitError {
  double mesh_volume_m3 = 0.0;
  double outside_volume_m3 = 0.0;    // in the spheres, not in the mesh (the union's, not E's sum)
  double uncovered_volume_m3 = 0.0;  // in the mesh, not in any sphere: must be ~0
  double surface_distance_mean_m = 0.0;  // from mesh surface samples to the union-of-spheres surface
  double surface_distance_max_m = 0.0;
};

// Throws std::invalid_argument for options out of range (spheres < 1,
// grid < 4, ...) and std::runtime_error for a mesh with no inside.
std::vector<Sphere> fit_spheres(const TriangleMesh& mesh, const FitOptions& options);

// Volumes on rows parallel to x on a (y, z) lattice of step (the mesh's
// longest side / grid_samples), exact along each row; the surface distance
// at 8192 area-weighted surface points, exact to the union of the spheres'
// surfaces (the nearest of: each sphere's radial point, the nearest point
// of each circle where two spheres meet, the points where three meet; each
// only where no other sphere covers it).
FitError measure_fit(const TriangleMesh& mesh, const std::vector<Sphere>& spheres, int grid_samples);

// The distance from p to the surface of the union of the spheres, as
// measure_fit finds it (for p inside or outside the union).
double union_surface_distance_m(const std::vector<Sphere>& spheres, const glm::dvec3& p_m);

}  // namespace atmo::spheres
