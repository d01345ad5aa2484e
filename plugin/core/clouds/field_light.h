// field_light.h — light grids that see the neighbouring grids. Each
// prototype's tau_light (cloud_lighting.h) stops where the light ray leaves
// its own grid; a deck cut into tiles (procedural_clouds.cpp) then shows
// bright seams at low sun, where a tile's sunward voxels see a short path
// while the deck goes on for kilometres. This ADDS, to the tau_light of every
// prototype placed exactly once, the optical depth its light rays gather in
// the OTHER instances' grids (their density times their extinction, placed
// as the field places them). A prototype with several instances is left as
// it is: its one light grid serves every copy, and the copies stand in
// different neighbourhoods, so it cannot hold a per-copy shadow.
//
// Method (docs/CLOUDS.md, "Light across deck tiles"): the optical depth
// beyond a grid is a smooth function of where the ray leaves it, so it is
// marched once per node of a map on each face the light leaves through, and
// each voxel interpolates the map (quadratic) at its exit point. The part of
// the ray still inside the own grid that crosses an overlapping grid (deck
// tiles overlap by two voxels) is marched per voxel, clipped to that grid.
// Voxels leaving through a map cell whose nodes show a kink (a cloud's edge),
// or through a face with fewer exits than map nodes (high sun), march their
// whole ray instead. Pure CPU, no GL; reads the field only.
//
// Use: per prototype p, after compute_light_depth_slices has filled its own
// tau_light for the same direction:
//   const FieldLightPlan plan = plan_field_light(field, p, light_dir_enu);
//   add_field_light_slices(field, plan, z_begin, z_end, &depths[p]);   // in any pieces
// or add_field_light_depths(field, light_dir_enu, &depths) for all of it.
#pragma once

#include <vector>

#include "core/clouds/cloud_field.h"
#include "core/clouds/cloud_lighting.h"
#include "core/clouds/cloud_transmittance.h"

namespace atmo::clouds {

struct FieldLightOptions {
  // March step through the other grids, in their voxels (as compute_light_depth_slices).
  float step_voxels = kDepthStepVoxels;
  // Exit maps, per axis of the prototype's grid, in its voxels: breakpoints
  // at the faces, at the outermost voxel centres (0.5 and n - 0.5) and every
  // `interval` voxels between them (voxel centres are where the trilinear
  // density has its kinks), each interval with a node at both ends and one in
  // the middle. Fine along z: at low sun the optical depth beyond a side face
  // changes by ~ extinction * voxel / tan(elevation) per voxel of height.
  // At least 0.25.
  glm::vec3 map_interval_voxels{2.0f, 2.0f, 0.25f};
  // A map cell is rough, and the voxels leaving through it march, where a
  // midpoint node differs from the mean of its interval's ends by more than
  // rough_abs + rough_rel * tau.
  float rough_abs = 0.05f, rough_rel = 0.005f;
  // No maps: every voxel marches its whole ray (the reference).
  bool exact = false;
};

// The instance that places `prototype`, if exactly one does; -1 otherwise.
int sole_instance(const CloudField& field, int prototype);

// What the neighbour searches below take from the field once: every
// prototype's sole instance and the field's buckets, so that a tile's
// neighbours cost the instances near it rather than all of them (a 400 km
// deck is 10 000 tiles). Without it (nullptr) they scan every instance.
struct FieldNeighbours {
  std::vector<int> sole;                 // per prototype, as sole_instance
  const CloudRayIndex* index = nullptr;  // build_cloud_ray_index(field); must outlive this
};
FieldNeighbours field_neighbours(const CloudField& field, const CloudRayIndex& index);

// The side faces of a prototype placed exactly once across which another
// instance's grid goes on (a deck's neighbouring tiles: points one voxel
// beyond the face, at a quarter, half and three quarters of its width, mid
// height, lie in another grid, at least two of the three). For
// compute_ambient_depths. None for a prototype with several copies.
ContinuingSides continuing_sides(const CloudField& field, int prototype, const FieldNeighbours* neighbours = nullptr);

// What one prototype's light rays meet outside its grid, for one light
// direction: the grids in the way and the exit maps. Refers to the field's
// prototypes by index (no pointers): pass the same, unchanged field to
// add_field_light_slices.
struct FieldLightPlan {
  // Another instance seen from this prototype's index space: q = m * p + b
  // maps an index point of this prototype into the other's index space.
  struct Other {
    int prototype = 0;          // the other instance's prototype
    glm::dmat3 m{1.0};
    glm::dvec3 b{0.0};
    glm::dvec3 d{0.0};          // the light direction there, m * dir_grid
    double tau_per_unit = 0.0;  // optical depth per unit of this prototype's index length at density 1
    double step = 0.5;          // march step in this prototype's index units
  };
  // Optical depth beyond the grid at the nodes of one exit face (normal
  // along `axis`); u and w are the two other axes in increasing order. Along
  // each, intervals between breakpoints with a node at both ends and one in
  // the middle.
  struct FaceMap {
    int axis = -1;                    // -1: the light does not leave through this axis
    std::vector<double> bu, bw;       // breakpoints, index units, 0 .. the grid's size
    int nu = 0, nw = 0;               // nodes: 2 * intervals + 1
    std::vector<float> tau;           // nu * nw, u fastest; empty: the voxels leaving here march
    std::vector<unsigned char> rough; // per cell (u fastest): 1 where its voxels march
  };

  int prototype = -1;                  // -1: nothing to add (shared or unplaced prototype, or nothing in the way)
  glm::dvec3 dir_grid{0.0, 0.0, 1.0};  // unit light direction in this prototype's grid axes
  bool exact = false;                  // FieldLightOptions::exact
  std::vector<Other> overlapping;      // grids that overlap this one (deck tiles: the 8 neighbours)
  std::vector<Other> ahead;            // grids a light ray from inside this one can reach (overlapping included)
  FaceMap faces[3];
};

// Builds the plan for `prototype`: one ray through the field per map node
// (a 3 km overcast tile at 2 degrees: ~15 ms). plan.prototype = -1 when
// there is nothing to add.
FieldLightPlan plan_field_light(const CloudField& field, int prototype, const glm::dvec3& light_dir_enu,
                                const FieldLightOptions& options = {}, const FieldNeighbours* neighbours = nullptr);

// ADDS the optical depth beyond the grid to tau_light (.x) of z-slices
// [z_begin, z_end) of `depths`, the plan's prototype's light depths, which
// must already hold the grid's own tau_light (compute_light_depth_slices)
// for the same direction: calling it twice adds twice. Does nothing when the
// plan is empty or depths is not sized to the prototype. Reads the field and
// the plan only: slices and prototypes can run on separate threads.
void add_field_light_slices(const CloudField& field, const FieldLightPlan& plan, int z_begin, int z_end,
                            LightDepths* depths);

// All of it: for every prototype with exactly one instance, plan and add over
// all its slices. depths: one per prototype (as set_clouds keeps them), each
// holding its own tau_light for light_dir_enu; shared prototypes are left
// untouched. Does nothing when depths->size() != field.prototypes.size().
void add_field_light_depths(const CloudField& field, const glm::dvec3& light_dir_enu,
                            std::vector<LightDepths>* depths, const FieldLightOptions& options = {});

}  // namespace atmo::clouds
