// cloud_lighting.h — what the march needs besides density: at every voxel
// centre, the optical depth to the light (tau_light), from the voxel to where
// the ray leaves the grid, and the optical depths towards the upper and lower
// hemispheres (tau_up, tau_down): each the depth whose escape conductance
// 1 / (1 + tau / kAmbientEscapeDepth) is the mean of the conductances along
// kAmbientDirections directions spread evenly over the hemisphere (so a voxel
// near a cloud's side, where slanted rays leave quickly, sees less depth than
// straight up or down would say). tau_up / tau_down depend on the cloud only
// (computed once); tau_light follows the Sun or Moon and is recomputed when it
// moves, a slab of z-slices at a time so the work can be spread over frames or
// run on a worker thread. Pure CPU, no GL.
#pragma once

#include <vector>

#include "core/clouds/cloud_twin.h"
#include "core/clouds/cloud_volume.h"

namespace atmo::clouds {

// The side faces of a grid (its x and y axes: west -x, east +x, south -y,
// north +y) across which the cloud goes on in another grid (a deck's tiles,
// continuing_sides in field_light.h). Slanted rays that leave there are taken
// as going on through the edge voxels, so a tile's border voxels see the deck
// beyond it rather than clear air (without this, tau_up and tau_down fall to
// ~60 % within a few voxels of a tile's border: a seam along every border),
// and the march's depth behind a point (cloud_march.glsl) goes on past them.
struct ContinuingSides {
  bool west = false, east = false, south = false, north = false;
  bool any() const { return west || east || south || north; }
};

struct LightDepths {
  int nx = 0, ny = 0, nz = 0;
  std::vector<glm::vec3> tau;  // (tau_light, tau_up, tau_down) per voxel, same order as DenseGrid
  ContinuingSides sides;       // what compute_ambient_depths was given (the march needs it too)
  size_t index(int x, int y, int z) const { return (static_cast<size_t>(z) * ny + y) * nx + x; }
};

// Default march step for the optical depths, voxels: half a voxel keeps the
// trilinear density's optical depth within ~1 % (tests/clouds).
constexpr float kDepthStepVoxels = 0.5f;

// The hemispherical depths: directions per hemisphere, and the optical depth
// at which a direction's escape conductance halves.
constexpr int kAmbientDirections = 16;
constexpr float kAmbientEscapeDepth = 2.0f;

// CloudMarch::continuing_sides from the flags: 1 per continuing face (west, east, south, north).
glm::vec4 continuing_sides_vector(const ContinuingSides& s);

// A scene (ENU) direction in the grid's axes.
glm::vec3 grid_direction(const CloudVolume& cloud, const glm::dvec3& dir_enu);

// Optical depth from an index-space point along a unit grid direction to the
// grid's boundary (trilinear density, midpoint steps of step_voxels).
float optical_depth_to_exit(const CloudVolume& cloud, const glm::vec3& index_point, const glm::vec3& dir_grid,
                            float step_voxels = kDepthStepVoxels);

// Sizes *out to the cloud and fills tau_up and tau_down (hemispherical, above;
// one sweep of the grid per direction, `directions` per hemisphere); records
// `sides` in out->sides.
void compute_ambient_depths(const CloudVolume& cloud, LightDepths* out, const ContinuingSides& sides = {},
                            int directions = kAmbientDirections);
// Fills tau_light for z-slices [z_begin, z_end) (out already sized).
void compute_light_depth_slices(const CloudVolume& cloud, const glm::dvec3& light_dir_enu, int z_begin, int z_end,
                                LightDepths* out);
// All of it at once.
LightDepths compute_light_depths(const CloudVolume& cloud, const glm::dvec3& light_dir_enu);
// tau_light of every voxel in one sweep (as the ambient depths: exact along
// an axis, blurred by up to a voxel elsewhere; across out->sides the cloud
// goes on to the top or bottom), O(voxels) where the march is O(voxels^4/3):
// the streamed layer march's draft. out already sized (compute_ambient_depths).
void sweep_light_depths(const CloudVolume& cloud, const glm::dvec3& light_dir_enu, LightDepths* out);

// The march's volume on the CPU (declared in cloud_twin.h).
struct CpuCloudVolume {
  const DenseGrid* density = nullptr;
  const LightDepths* depths = nullptr;
};

// Interleaves density and depths as the GL texture holds them (RGBA, x fastest).
std::vector<float> pack_cloud_texels(const DenseGrid& density, const LightDepths& depths);

// Inputs of one march for a cloud (CloudMarch) from the physical scene.
struct CloudLight {
  glm::dvec3 direction_enu{0.0, 0.0, 1.0};  // unit, towards the light
  glm::dvec3 illuminance_lux{0.0};          // at the cloud
  glm::dvec3 sky_radiance{0.0};             // cd/m^2
  glm::dvec3 ground_radiance{0.0};          // cd/m^2
};
twin::CloudMarch make_cloud_march(const CloudVolume& cloud, const CloudLight& light, float step_voxels = 1.0f,
                                  int max_steps = 512);

// The C++ twin of the GLSL march (cloud_march.glsl) for a ray in the scene
// frame: eye position (ENU m), unit direction, stop distance (m). The march's
// continuing_sides are taken from depths.sides.
twin::CloudSample march_cloud_ray(const CloudVolume& cloud, const LightDepths& depths, const twin::CloudMarch& march,
                                  const twin::CloudPhase& phase, const twin::CloudOctaves& octaves,
                                  const glm::dvec3& eye_enu_m, const glm::dvec3& dir_enu, double t_max_m);

}  // namespace atmo::clouds
