// cloud_volume.h — one cloud (or cloud cluster) as the core sees it: a dense
// grid of density in [0, 1] (what an OpenVDB "density" grid holds), its
// placement in the scene, and the optics that turn density into extinction.
// Pure data, no GL and no OpenVDB: the procedural generator and the .vdb
// loader both produce it, the lighting, the references and the GL layer read it.
//
// Frames and units: the grid's index space has voxel CENTRES at integer+0.5
// (OpenVDB cell-centred convention shifted so index 0 spans [0, 1)); grid
// space is index space times voxel_size_m; the scene frame is ENU at the
// scenario/world origin, metres: p_enu = origin_enu_m + rotation * p_grid.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace atmo::clouds {

// Trilinear interpolation over voxel centres (integer + 0.5) of an nx*ny*nz
// grid, zero outside, as GL_LINEAR with a zero border samples a 3D texture:
// `at(x, y, z)` gives the value of an in-range voxel (any type with + and *float).
template <typename T, typename At>
T trilinear_zero_border(int nx, int ny, int nz, const glm::vec3& index_point, const At& at) {
  const glm::vec3 p = index_point - 0.5f;
  const int x0 = static_cast<int>(std::floor(p.x));
  const int y0 = static_cast<int>(std::floor(p.y));
  const int z0 = static_cast<int>(std::floor(p.z));
  const glm::vec3 f = p - glm::vec3(x0, y0, z0);
  T sum = T(0);
  for (int c = 0; c < 8; ++c) {
    const int x = x0 + (c & 1), y = y0 + ((c >> 1) & 1), z = z0 + ((c >> 2) & 1);
    if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz) continue;
    const float w = ((c & 1) ? f.x : 1.0f - f.x) * (((c >> 1) & 1) ? f.y : 1.0f - f.y) *
                    (((c >> 2) & 1) ? f.z : 1.0f - f.z);
    sum += w * at(x, y, z);
  }
  return sum;
}

// Density samples, x fastest then y then z.
struct DenseGrid {
  int nx = 0;
  int ny = 0;
  int nz = 0;
  std::vector<float> values;

  DenseGrid() = default;
  DenseGrid(int x, int y, int z, float fill = 0.0f)
      : nx(x), ny(y), nz(z), values(static_cast<size_t>(x) * y * z, fill) {}

  size_t voxel_count() const { return values.size(); }
  bool empty() const { return values.empty(); }
  size_t index(int x, int y, int z) const { return (static_cast<size_t>(z) * ny + y) * nx + x; }
  float& at(int x, int y, int z) { return values[index(x, y, z)]; }
  float at(int x, int y, int z) const { return values[index(x, y, z)]; }
  // Zero outside the grid (clouds fade to clear air at their borders).
  float at_or_zero(int x, int y, int z) const {
    if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz) return 0.0f;
    return at(x, y, z);
  }
  // Trilinear at an index-space point (voxel centres at i + 0.5), zero outside,
  // as a GL 3D texture with CLAMP_TO_BORDER (border 0) samples it.
  float sample(const glm::vec3& index_point) const;
};

// Optics of cloud droplets (water, visible light).
struct CloudOptics {
  // Extinction coefficient at density 1, 1/m. Cumulus liquid water content
  // 0.2-1 g/m^3 with 10 um droplets gives 0.03-0.15 /m (in-cloud visibility
  // 20-100 m); 0.06 is a mid value.
  float extinction_per_m = 0.06f;
  // Single-scattering albedo: water absorbs almost nothing in the visible.
  float albedo = 0.999f;
  // Effective droplet diameter, micrometres: sets the phase function's
  // forward peak (Jendersie & d'Eon 2023 fit, valid 5-50 um).
  float droplet_diameter_um = 20.0f;
};

struct CloudVolume {
  std::string name;                       // for logs and errors: file/grid or "cumulus #12"
  DenseGrid density;                      // [0, 1] after density_scale
  float voxel_size_m = 1.0f;              // uniform voxel edge, metres
  glm::dvec3 origin_enu_m{0.0};           // scene position of the grid's index-space origin
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};  // grid axes -> ENU axes
  CloudOptics optics;

  glm::dvec3 extent_m() const {
    return glm::dvec3(density.nx, density.ny, density.nz) * static_cast<double>(voxel_size_m);
  }
  // Scene-frame centre of the grid box (of a copy whose origin is `origin`)
  // and the radius of its bounding sphere.
  glm::dvec3 centre_at(const glm::dvec3& origin) const { return origin + rotation * (0.5 * extent_m()); }
  glm::dvec3 centre_enu_m() const { return centre_at(origin_enu_m); }
  double bounding_radius_m() const { return 0.5 * glm::length(extent_m()); }
  size_t memory_bytes() const { return density.values.size() * sizeof(float); }
};

// Largest density in the grid (0 for an empty grid).
float max_density(const DenseGrid& grid);

// The volume at half resolution: each voxel the mean of 2x2x2 (cells past an
// odd edge count as empty), twice the edge, the same origin and rotation. The
// layer march's draft (abi/cloud_inputs: lit in ~1/10 of the time).
CloudVolume half_resolution(const CloudVolume& volume);

}  // namespace atmo::clouds
