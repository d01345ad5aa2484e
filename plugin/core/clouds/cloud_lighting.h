// cloud_lighting.h — what the march needs besides density: at every voxel
// centre, the optical depth to the light (tau_light), to the sky straight up
// (tau_up) and to the ground straight down (tau_down), each from the voxel to
// where the ray leaves the grid. tau_up / tau_down depend on the cloud only
// (computed once); tau_light follows the Sun or Moon and is recomputed when it
// moves, a slab of z-slices at a time so the work can be spread over frames or
// run on a worker thread. Pure CPU, no GL.
#pragma once

#include <vector>

#include "core/clouds/cloud_twin.h"
#include "core/clouds/cloud_volume.h"

namespace atmo::clouds {

struct LightDepths {
  int nx = 0, ny = 0, nz = 0;
  std::vector<glm::vec3> tau;  // (tau_light, tau_up, tau_down) per voxel, same order as DenseGrid
  size_t index(int x, int y, int z) const { return (static_cast<size_t>(z) * ny + y) * nx + x; }
};

// Default march step for the optical depths, voxels: half a voxel keeps the
// trilinear density's optical depth within ~1 % (tests/clouds).
constexpr float kDepthStepVoxels = 0.5f;

// A scene (ENU) direction in the grid's axes.
glm::vec3 grid_direction(const CloudVolume& cloud, const glm::dvec3& dir_enu);

// Optical depth from an index-space point along a unit grid direction to the
// grid's boundary (trilinear density, midpoint steps of step_voxels).
float optical_depth_to_exit(const CloudVolume& cloud, const glm::vec3& index_point, const glm::vec3& dir_grid,
                            float step_voxels = kDepthStepVoxels);

// Sizes *out to the cloud and fills tau_up and tau_down.
void compute_ambient_depths(const CloudVolume& cloud, LightDepths* out);
// Fills tau_light for z-slices [z_begin, z_end) (out already sized).
void compute_light_depth_slices(const CloudVolume& cloud, const glm::dvec3& light_dir_enu, int z_begin, int z_end,
                                LightDepths* out);
// All of it at once.
LightDepths compute_light_depths(const CloudVolume& cloud, const glm::dvec3& light_dir_enu);

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
// frame: eye position (ENU m), unit direction, stop distance (m).
twin::CloudSample march_cloud_ray(const CloudVolume& cloud, const LightDepths& depths, const twin::CloudMarch& march,
                                  const twin::CloudPhase& phase, const twin::CloudOctaves& octaves,
                                  const glm::dvec3& eye_enu_m, const glm::dvec3& dir_enu, double t_max_m);

}  // namespace atmo::clouds
