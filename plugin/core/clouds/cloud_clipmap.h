// cloud_clipmap.h — the whole cloud field resampled around the eye, for the
// layer march (shaders/clouds/cloud_layer_march.glsl): nested levels of one
// lattice each, voxels doubling from level to level, so one march per pixel
// through every layer costs steps, not clouds. Each level voxel holds what the
// per-cloud march fetches, over the instances that cover it:
//   a = (sigma_t, tau_light, tau_up, tau_down)
//   b = (tau_back, sigma_t droplet_um)
// sigma_t (1/m) summed; the depths of overlapping instances (a deck's tiles)
// their density-weighted mean at the voxel (the plain mean where all are
// empty), and interpolated between voxels as they are, as the per-cloud march
// interpolates its grids (premultiplying them by the density, as before,
// weighted the interpolation towards the dense voxel and lit the edges of
// thin clouds too brightly: docs/CLOUDS.md); tau_back (the depth behind the
// point away from the light) taken per prototype voxel, as the march computes
// it. Coarse levels sample mips of the prototypes: the mean density, the
// depths weighted by density.
// Pure CPU, no GL; deterministic: a level's content is a function of the
// field, its light grids and the eye's lattice cell (never of the history).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/clouds/cloud_field.h"
#include "core/clouds/cloud_lighting.h"
#include "core/clouds/cloud_transmittance.h"

namespace atmo::clouds {

struct ClipmapSpec {
  int size = 192;             // voxels across each level (even), x and y
  int max_levels = 9;         // levels stop at this count or when one covers the field
  float base_voxel_m = 0.0f;  // level 0's voxel; 0: the finest prototype voxel
};

struct ClipmapLevel {
  double voxel_m = 0.0;         // voxel edge, m (cubes)
  glm::dvec3 origin_m{0.0};     // the clouds' frame: corner of voxel (0, 0, 0)
  int nx = 0, ny = 0, nz = 0;   // nz includes one empty voxel below and above the field
  std::vector<glm::vec4> a;     // see above, x fastest then y then z
  std::vector<glm::vec2> b;
  // Empty-space skipping: bricks of 2x2x2 voxels (bx = ceil(nx / 2), ...),
  // each the Chebyshev distance, in bricks, to the nearest brick with a
  // voxel of cloud (0 in one; at most 255); the grid's sides count as cloud
  // (what lies past them is another level's), above and below it is clear.
  // The march skips max(2 clear - 2.5, 0) voxels from any point in the
  // brick: the trilinear fetch reaches less than a voxel past a cloud
  // voxel's centre (tested: CloudClipmap.ClearBricksAreConservative).
  int bx = 0, by = 0, bz = 0;
  std::vector<uint8_t> clear;
  size_t index(int x, int y, int z) const { return (static_cast<size_t>(z) * ny + y) * nx + x; }
  size_t brick_index(int x, int y, int z) const { return (static_cast<size_t>(z) * by + y) * bx + x; }
};

// A prototype's mips of (density, tau_light, tau_up, tau_down) and tau_back
// (above), level 0 the prototype itself: built per light direction.
struct PrototypeMips {
  struct Mip {
    int nx = 0, ny = 0, nz = 0;
    std::vector<glm::vec4> terms;  // density, tau_light, tau_up, tau_down
    std::vector<float> tau_back;
  };
  std::vector<Mip> mips;
};

// What the levels' placement takes from the field, once per field: its
// boxes' bounds, level 0's voxel (the finest prototype's, coarsened until all
// levels fit the voxel budget) and the cell the levels are centred on.
struct ClipmapGeometry {
  glm::dvec3 lo{0.0}, hi{0.0};  // the instances' boxes, the clouds' frame
  double base_voxel_m = 0.0;
  double cell_m = 0.0;          // a quarter of level 0's width
};

struct CloudClipmap {
  std::vector<ClipmapLevel> levels;
  double bottom_m = 0.0, top_m = 0.0;   // the field's boxes' lowest and highest height
  glm::ivec2 cell{0};                    // the eye's lattice cell the levels were centred for
  // The field's droplet diameters (um, ascending, at most CLOUD_LAYER_PHASES)
  // and its lowest single-scattering albedo: the march's phase table.
  std::vector<float> droplet_um;
  float albedo = 1.0f;
  size_t memory_bytes() const;
};

// Mips per prototype for the current light grids (depths[p] per prototype).
std::vector<PrototypeMips> build_prototype_mips(const CloudField& field, const std::vector<LightDepths>& depths,
                                                const glm::dvec3& light_dir_enu);

// O(instances): compute it when the field changes, not per frame.
ClipmapGeometry clipmap_geometry(const CloudField& field, const ClipmapSpec& spec);

// The lattice cell the eye is in: the levels are centred on it, so the
// clipmap changes only when the eye crosses into another cell (a quarter of
// level 0's width), and two views whose eyes share a cell share it.
glm::ivec2 clipmap_cell(const ClipmapGeometry& geometry, const glm::dvec3& eye_m);

// Builds every level centred on `cell`; `index` (build_cloud_ray_index) finds
// the instances over a column, `geometry` is clipmap_geometry(field, spec).
// O(levels x size^2 x nz x instances per bucket). Stops early (an unfinished
// clipmap, to be thrown away) once *cancel is true (a worker's build).
// `threads` share each level's rows (the caller's thread is one of them):
// the result is the same for any count.
CloudClipmap build_clipmap(const CloudField& field, const std::vector<PrototypeMips>& mips,
                           const CloudRayIndex& index, const ClipmapSpec& spec, const ClipmapGeometry& geometry,
                           const glm::ivec2& cell, const std::atomic<bool>* cancel = nullptr, int threads = 1);

// The march's volume on the CPU (cloud_layer_march.glsl's CLOUD_LAYER).
struct CpuCloudLayer {
  const CloudClipmap* clipmap = nullptr;
};

// The layer march's inputs for an eye (the clouds' frame, m): the levels
// relative to the eye, the field's droplet phases, the light.
twin::CloudLayerMarch make_layer_march(const CloudClipmap& clipmap, const glm::dvec3& eye_m, const CloudLight& light,
                                       float step_voxels, int max_steps);

// The C++ twin of the GLSL layer march (no air): a ray from the eye along unit dir to t_max_m.
twin::CloudLayerSample march_layer_ray(const CloudClipmap& clipmap, const twin::CloudLayerMarch& march,
                                       const twin::CloudOctaves& octaves, const glm::dvec3& dir, double t_max_m);

}  // namespace atmo::clouds
