// procedural_clouds.h — cloud layers generated from a seed: cumulus as a few
// dozen prototype clouds copied (translated) over the area, stratus, overcast
// and cirrus as decks cut into square tiles (one prototype and one instance
// each). Deterministic: the same spec gives bit-identical output (own integer
// hash and PRNG, core/clouds/noise.h). Pure CPU, no GL.
//
// Frames and units: SI, scene ENU metres; heights are ENU z above the scene
// origin. Every grid leaves at least one voxel of zero density on each face.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/clouds/cloud_field.h"

namespace atmo::clouds {

enum class CloudLayerType { Cumulus, Stratus, Overcast, Cirrus };

struct CloudLayerSpec {
  CloudLayerType type = CloudLayerType::Cumulus;
  // 0..8: the fraction oktas/8 of the area's ground covered by the vertical
  // projection of cloud (a column counts when its optical depth exceeds 0.1).
  // Overcast is always 8 (except 0: no cloud).
  int coverage_oktas = 4;
  double base_m = 1200, top_m = 2500;  // heights above the scene origin (ENU z), top > base
  double area_size_m = 20000;          // side of the square area that holds the layer
  glm::dvec2 area_centre_enu_m{0.0};   // its centre (east, north)
  uint64_t seed = 0;
  // Upper bound on the voxel edge, m; 0: the type's default (cumulus 20-40 m
  // so the largest cloud spans ~96 voxels; stratus/overcast 40-80 m with at
  // least 4 (6 by default) voxels through the deck; cirrus 40-80 m).
  float max_voxel_size_m = 0;
  // Budget over all prototypes (32 Mi voxels = 128 MiB of float): voxels are
  // coarsened until the layer fits, and a note says so.
  size_t max_total_voxels = 32u << 20;
};

struct GeneratedLayer {
  CloudField field;  // prototypes + instances, in the scene's ENU frame
  // Achieved ground coverage: the fraction of the area's ground cells whose
  // vertical optical depth exceeds 0.1, measured on the generated grids;
  // compare with oktas/8.
  double coverage_fraction = 0.0;
  std::vector<std::string> notes;  // what differs from the spec, and why (coarsened voxels, coverage not reached)
  bool cancelled = false;          // stopped by the cancel flag: nothing else is set
};

// Throws std::invalid_argument naming the bad field (coverage_oktas out of
// 0..8, top_m <= base_m, a non-finite number, area_size_m <= 0, ...).
// `cancel` (decks only: cumulus is cheap) is polled between rows of tiles
// and bisection steps; when it is raised the result is empty and `cancelled`.
// `threads` (the caller's is one) share the prototypes or the deck's rows of
// tiles; the layer is the same for any count.
GeneratedLayer generate_cloud_layer(const CloudLayerSpec& spec, const std::atomic<bool>* cancel = nullptr,
                                    int threads = 1);

// Stratus, overcast and cirrus (tiles of a deck), not cumulus.
bool is_deck(CloudLayerType type);

// The spec of the same deck with `factor` times fewer voxels along each axis
// (its budget cut to 1/factor^3 of what the spec plans; the generator then
// takes fewer, thicker layers): the streamed set-up's quick first field.
// Cumulus (whose generation is cheap) and factor <= 1: the spec unchanged.
CloudLayerSpec coarser_layer_spec(const CloudLayerSpec& spec, int factor);

const char* cloud_layer_type_name(CloudLayerType t);  // "cumulus", "stratus", "overcast", "cirrus"

// Scene density at an ENU point: the SUM of the trilinear densities of every
// instance whose grid contains it. Where volumes overlap their extinctions add
// (optical depth is additive); the deck tiles rely on it to join without a
// seam (procedural_clouds.cpp). O(instances): for tests and tools.
float field_density_at(const CloudField& field, const glm::dvec3& p_enu_m);

}  // namespace atmo::clouds
