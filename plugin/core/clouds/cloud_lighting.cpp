#include "core/clouds/cloud_lighting.h"

#include <algorithm>
#include <cmath>

namespace atmo::clouds {


glm::vec3 grid_direction(const CloudVolume& cloud, const glm::dvec3& dir_enu) {
  return glm::vec3(glm::normalize(glm::inverse(cloud.rotation) * dir_enu));
}

float optical_depth_to_exit(const CloudVolume& cloud, const glm::vec3& index_point, const glm::vec3& dir_grid,
                            float step_voxels) {
  const glm::vec3 size(cloud.density.nx, cloud.density.ny, cloud.density.nz);
  const glm::vec2 hit = twin::cloud_box_hit(index_point, dir_grid, size);
  if (!(hit.x < hit.y)) return 0.0f;
  const int steps = std::max(1, static_cast<int>(std::ceil((hit.y - hit.x) / step_voxels)));
  const float dt = (hit.y - hit.x) / static_cast<float>(steps);
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) {
    sum += cloud.density.sample(index_point + dir_grid * (hit.x + (static_cast<float>(i) + 0.5f) * dt));
  }
  return static_cast<float>(sum * dt * cloud.voxel_size_m * cloud.optics.extinction_per_m);
}

void compute_ambient_depths(const CloudVolume& cloud, LightDepths* out) {
  const DenseGrid& g = cloud.density;
  out->nx = g.nx;
  out->ny = g.ny;
  out->nz = g.nz;
  out->tau.assign(g.voxel_count(), glm::vec3(0.0f));
  const glm::vec3 up = grid_direction(cloud, glm::dvec3(0.0, 0.0, 1.0));
  for (int z = 0; z < g.nz; ++z)
    for (int y = 0; y < g.ny; ++y)
      for (int x = 0; x < g.nx; ++x) {
        const glm::vec3 p(x + 0.5f, y + 0.5f, z + 0.5f);
        glm::vec3& t = out->tau[out->index(x, y, z)];
        t.y = optical_depth_to_exit(cloud, p, up);
        t.z = optical_depth_to_exit(cloud, p, -up);
      }
}

void compute_light_depth_slices(const CloudVolume& cloud, const glm::dvec3& light_dir_enu, int z_begin, int z_end,
                                LightDepths* out) {
  const DenseGrid& g = cloud.density;
  const glm::vec3 dir = grid_direction(cloud, light_dir_enu);
  for (int z = std::max(z_begin, 0); z < std::min(z_end, g.nz); ++z)
    for (int y = 0; y < g.ny; ++y)
      for (int x = 0; x < g.nx; ++x) {
        out->tau[out->index(x, y, z)].x =
            optical_depth_to_exit(cloud, glm::vec3(x + 0.5f, y + 0.5f, z + 0.5f), dir);
      }
}

LightDepths compute_light_depths(const CloudVolume& cloud, const glm::dvec3& light_dir_enu) {
  LightDepths d;
  compute_ambient_depths(cloud, &d);
  compute_light_depth_slices(cloud, light_dir_enu, 0, cloud.density.nz, &d);
  return d;
}

glm::vec4 fetch_cloud_volume(const CpuCloudVolume& v, const glm::vec3& index_point) {
  const DenseGrid& g = *v.density;
  const LightDepths& d = *v.depths;
  return trilinear_zero_border<glm::vec4>(g.nx, g.ny, g.nz, index_point, [&](int x, int y, int z) {
    const glm::vec3& t = d.tau[d.index(x, y, z)];
    return glm::vec4(g.at(x, y, z), t.x, t.y, t.z);
  });
}

std::vector<float> pack_cloud_texels(const DenseGrid& density, const LightDepths& depths) {
  std::vector<float> out(density.voxel_count() * 4);
  for (size_t i = 0; i < density.voxel_count(); ++i) {
    out[4 * i + 0] = density.values[i];
    out[4 * i + 1] = depths.tau[i].x;
    out[4 * i + 2] = depths.tau[i].y;
    out[4 * i + 3] = depths.tau[i].z;
  }
  return out;
}

twin::CloudMarch make_cloud_march(const CloudVolume& cloud, const CloudLight& light, float step_voxels,
                                  int max_steps) {
  twin::CloudMarch m{};
  m.grid_size = glm::vec3(cloud.density.nx, cloud.density.ny, cloud.density.nz);
  m.voxel_size_m = cloud.voxel_size_m;
  m.extinction_per_m = cloud.optics.extinction_per_m;
  m.albedo = cloud.optics.albedo;
  m.step_voxels = step_voxels;
  m.max_steps = max_steps;
  m.light_illuminance = glm::vec3(light.illuminance_lux);
  m.light_dir_grid = grid_direction(cloud, light.direction_enu);
  m.sky_radiance = glm::vec3(light.sky_radiance);
  m.ground_radiance = glm::vec3(light.ground_radiance);
  return m;
}

twin::CloudSample march_cloud_ray(const CloudVolume& cloud, const LightDepths& depths, const twin::CloudMarch& march,
                                  const twin::CloudPhase& phase, const twin::CloudOctaves& octaves,
                                  const glm::dvec3& eye_enu_m, const glm::dvec3& dir_enu, double t_max_m) {
  const glm::dquat inv = glm::inverse(cloud.rotation);
  const glm::vec3 origin_index(inv * (eye_enu_m - cloud.origin_enu_m) / static_cast<double>(cloud.voxel_size_m));
  const CpuCloudVolume vol{&cloud.density, &depths};
  return twin::cloud_march(vol, march, phase, octaves, origin_index, grid_direction(cloud, dir_enu),
                           static_cast<float>(t_max_m));
}

}  // namespace atmo::clouds
