// cloud_transmittance.h — the clouds' direct transmittance exp(-tau) along one
// ray (the Sun or Moon seen from the eye: get_lighting). A field's instances
// go into a coarse 2D grid of buckets over their boxes' (east, north)
// footprints, built once per field, so a ray visits only the instances whose
// buckets its horizontal track crosses, inside the clouds' height range: the
// cost is bounded by the buckets crossed and the instances in them, not by the
// field's size. Pure CPU, no GL.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "core/clouds/cloud_field.h"

namespace atmo::clouds {

struct CloudRayIndex {
  glm::dvec2 corner_enu_m{0.0};       // (east, north) of the grid's south-west corner
  double cell_m = 1.0;                // bucket edge, m
  int nx = 0, ny = 0;                 // buckets (0: an empty field)
  double z_lo_m = 0.0, z_hi_m = 0.0;  // the boxes' height range
  std::vector<uint32_t> start;        // nx * ny + 1 offsets into `items`, east fastest
  std::vector<uint32_t> items;        // instance indices, bucket by bucket

  size_t memory_bytes() const { return (start.size() + items.size()) * sizeof(uint32_t); }
};

// Buckets of at least the widest box's footprint (so a box lies in at most
// 4 buckets when boxes are alike), at most max_cells_per_side per side.
CloudRayIndex build_cloud_ray_index(const CloudField& field, int max_cells_per_side = 512);

// The instances whose boxes reach into the (east, north) rectangle [lo, hi]
// through the buckets it touches (a superset: boxes near it may come too),
// ascending, each once, into *out.
void instances_near(const CloudRayIndex& index, const glm::dvec2& lo, const glm::dvec2& hi,
                    std::vector<uint32_t>* out);

// exp(-tau) of every instance box the ray origin + t dir (t in [0,
// max_distance_m], dir unit, ENU of the field) crosses: the trilinear density
// times the box's extinction, midpoint steps of step_voxels voxels per box
// (overlapping boxes add, as field_density_at sums). Stops once tau > 50
// (exp(-50) = 2e-22) and returns 0 then.
double transmittance_along_ray(const CloudField& field, const CloudRayIndex& index, const glm::dvec3& origin_enu_m,
                               const glm::dvec3& dir_enu, double max_distance_m = 1e300, double step_voxels = 0.5);

}  // namespace atmo::clouds
