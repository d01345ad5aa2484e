#include "core/clouds/cloud_lighting.h"

#include <algorithm>
#include <cmath>

namespace atmo::clouds {

glm::vec4 continuing_sides_vector(const ContinuingSides& s) {
  return glm::vec4(s.west ? 1.0f : 0.0f, s.east ? 1.0f : 0.0f, s.south ? 1.0f : 0.0f, s.north ? 1.0f : 0.0f);
}

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

namespace {

// Optical depth to the grid's boundary from every voxel centre along one
// direction, all voxels in one sweep: slices are visited against the
// direction's dominant axis, and each voxel adds the segment to the next
// slice (trapezoid of the density at both ends) to the depth found there
// (bilinear between that slice's voxel centres, zero outside the grid). Exact
// along an axis; elsewhere it blurs by up to a voxel, which the hemispherical
// means below do not notice. O(voxels) per direction.
//
// Across a side face in `sides` (the cloud goes on there: a deck's next tile)
// the grid is taken as extended by its outermost voxels with density (the
// procedural tiles keep a ring of empty voxels for the GL sampler's zero
// border; it lies over the neighbour's interior, so it reads as the voxel
// inside it): lookups beyond the face clamp to it, and a ray leaving through
// it goes on through that column to the top or bottom (column_up /
// column_down over |dir.z|).
void sweep_depths(const DenseGrid& g, const glm::vec3& dir, float per_index_unit, const ContinuingSides& sides,
                  const std::vector<float>& column_up, const std::vector<float>& column_down,
                  std::vector<float>* tau) {
  const int n[3] = {g.nx, g.ny, g.nz};
  const bool low[3] = {sides.west && g.nx >= 3, sides.south && g.ny >= 3, false};
  const bool high[3] = {sides.east && g.nx >= 3, sides.north && g.ny >= 3, false};
  int a = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(dir[i]) > std::abs(dir[a])) a = i;
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  const float step = 1.0f / std::abs(dir[a]);  // index units per slice
  const int next = dir[a] > 0.0f ? 1 : -1;     // the slice the ray enters next
  const bool exit_continues = next > 0 ? high[a] : low[a];
  const std::vector<float>& column = dir.z > 0.0f ? column_up : column_down;
  const float column_scale = 1.0f / std::max(std::abs(dir.z), 1e-3f);
  // The next slice is met at (ib + ob, ic + oc): between voxel centres
  // floor(.) and floor(.) + 1 of that slice, weights fb, fc.
  const float ob = dir[b] * step, oc = dir[c] * step;
  const int db = static_cast<int>(std::floor(ob)), dc = static_cast<int>(std::floor(oc));
  const float fb = ob - static_cast<float>(db), fc = oc - static_cast<float>(dc);
  tau->assign(g.voxel_count(), 0.0f);
  // Where index i along `axis` reads the density (the outermost voxel inside
  // the empty ring across a continuing face) and the depths (the grid's edge
  // there); -1: outside, zero.
  auto density_index = [&](int axis, int i) {
    if (i <= 0 && low[axis]) return 1;
    if (i >= n[axis] - 1 && high[axis]) return n[axis] - 2;
    return i < 0 || i >= n[axis] ? -1 : i;
  };
  auto depth_index = [&](int axis, int i) {
    if (i < 0) return low[axis] ? 0 : -1;
    if (i >= n[axis]) return high[axis] ? n[axis] - 1 : -1;
    return i;
  };
  auto density = [&](int ia, int ib, int ic) -> float {
    int idx[3];
    idx[a] = density_index(a, ia), idx[b] = density_index(b, ib), idx[c] = density_index(c, ic);
    if (idx[a] < 0 || idx[b] < 0 || idx[c] < 0) return 0.0f;
    return g.values[g.index(idx[0], idx[1], idx[2])];
  };
  auto depth = [&](int ia, int ib, int ic) -> float {
    int idx[3];
    idx[a] = ia, idx[b] = depth_index(b, ib), idx[c] = depth_index(c, ic);
    if (idx[b] < 0 || idx[c] < 0) return 0.0f;
    return (*tau)[g.index(idx[0], idx[1], idx[2])];
  };
  auto bilinear = [&](const auto& at, int ia, int ib, int ic) {
    const int b0 = ib + db, c0 = ic + dc;
    return (1.0f - fb) * (1.0f - fc) * at(ia, b0, c0) + fb * (1.0f - fc) * at(ia, b0 + 1, c0) +
           (1.0f - fb) * fc * at(ia, b0, c0 + 1) + fb * fc * at(ia, b0 + 1, c0 + 1);
  };
  const int first = next > 0 ? n[a] - 1 : 0;
  int idx[3];
  for (int ia = first; ia >= 0 && ia < n[a]; ia -= next)
    for (int ic = 0; ic < n[c]; ++ic)
      for (int ib = 0; ib < n[b]; ++ib) {
        idx[a] = ia, idx[b] = ib, idx[c] = ic;
        const size_t i = g.index(idx[0], idx[1], idx[2]);
        const float rho = density(ia, ib, ic);
        const int na = ia + next;
        float t;
        if (na < 0 || na >= n[a]) {
          if (exit_continues) {
            idx[a] = density_index(a, ia), idx[b] = std::max(density_index(b, ib), 0);
            idx[c] = std::max(density_index(c, ic), 0);
            t = column[g.index(idx[0], idx[1], idx[2])] * column_scale;
          } else {
            // Half a step to the face, where the trilinear density is half the voxel's.
            t = 0.5f * step * 0.75f * rho * per_index_unit;
          }
        } else {
          const float rho_next = bilinear(density, na, ib, ic);
          t = 0.5f * step * (rho + rho_next) * per_index_unit + bilinear(depth, na, ib, ic);
        }
        (*tau)[i] = t;
      }
}

// Optical depth from every voxel centre straight up (up) and down (down) to
// the grid's top and bottom faces (trapezoid between voxel centres, half a
// voxel at 0.75 rho to the face, as sweep_depths).
void column_depths(const DenseGrid& g, float per_index_unit, std::vector<float>* up, std::vector<float>* down) {
  up->assign(g.voxel_count(), 0.0f);
  down->assign(g.voxel_count(), 0.0f);
  for (int y = 0; y < g.ny; ++y)
    for (int x = 0; x < g.nx; ++x) {
      for (int z = g.nz - 1; z >= 0; --z) {
        const float rho = g.at(x, y, z);
        (*up)[g.index(x, y, z)] = z == g.nz - 1 ? 0.375f * rho * per_index_unit
                                                : 0.5f * (rho + g.at(x, y, z + 1)) * per_index_unit +
                                                      (*up)[g.index(x, y, z + 1)];
      }
      for (int z = 0; z < g.nz; ++z) {
        const float rho = g.at(x, y, z);
        (*down)[g.index(x, y, z)] = z == 0 ? 0.375f * rho * per_index_unit
                                           : 0.5f * (rho + g.at(x, y, z - 1)) * per_index_unit +
                                                 (*down)[g.index(x, y, z - 1)];
      }
    }
}

}  // namespace

void compute_ambient_depths(const CloudVolume& cloud, LightDepths* out, const ContinuingSides& sides,
                            int directions) {
  const DenseGrid& g = cloud.density;
  out->nx = g.nx;
  out->ny = g.ny;
  out->nz = g.nz;
  out->tau.assign(g.voxel_count(), glm::vec3(0.0f));
  out->sides = sides;
  // Each hemisphere's directions, uniform in solid angle (a spiral of
  // `directions`, cos theta at the centres of equal bands), in ENU then
  // in the grid's axes.
  const float per_index_unit = cloud.voxel_size_m * cloud.optics.extinction_per_m;
  const int n = std::max(1, directions);
  std::vector<double> conductance[2];
  for (auto& v : conductance) v.assign(g.voxel_count(), 0.0);
  std::vector<float> tau, column_up, column_down;
  if (sides.any()) column_depths(g, per_index_unit, &column_up, &column_down);
  for (int h = 0; h < 2; ++h)
    for (int k = 0; k < n; ++k) {
      const double cos_t = 1.0 - (k + 0.5) / n, sin_t = std::sqrt(1.0 - cos_t * cos_t);
      const double phi = 2.399963229728653 * k;  // golden angle
      const glm::dvec3 d_enu(sin_t * std::cos(phi), sin_t * std::sin(phi), h == 0 ? cos_t : -cos_t);
      sweep_depths(g, grid_direction(cloud, d_enu), per_index_unit, sides, column_up, column_down, &tau);
      for (size_t i = 0; i < tau.size(); ++i) conductance[h][i] += 1.0 / (1.0 + tau[i] / kAmbientEscapeDepth);
    }
  for (size_t i = 0; i < g.voxel_count(); ++i) {
    const double up_mean = conductance[0][i] / n, down_mean = conductance[1][i] / n;
    out->tau[i].y = static_cast<float>(kAmbientEscapeDepth * (1.0 / up_mean - 1.0));
    out->tau[i].z = static_cast<float>(kAmbientEscapeDepth * (1.0 / down_mean - 1.0));
  }
}

void sweep_light_depths(const CloudVolume& cloud, const glm::dvec3& light_dir_enu, LightDepths* out) {
  const DenseGrid& g = cloud.density;
  const float per_index_unit = cloud.voxel_size_m * cloud.optics.extinction_per_m;
  std::vector<float> tau, column_up, column_down;
  if (out->sides.any()) column_depths(g, per_index_unit, &column_up, &column_down);
  sweep_depths(g, grid_direction(cloud, light_dir_enu), per_index_unit, out->sides, column_up, column_down, &tau);
  for (size_t i = 0; i < tau.size() && i < out->tau.size(); ++i) out->tau[i].x = tau[i];
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
  twin::CloudMarch m = march;
  m.continuing_sides = continuing_sides_vector(depths.sides);
  return twin::cloud_march(vol, m, phase, octaves, origin_index, grid_direction(cloud, dir_enu),
                           static_cast<float>(t_max_m));
}

}  // namespace atmo::clouds
