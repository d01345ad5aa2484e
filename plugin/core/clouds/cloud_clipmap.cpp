#include "core/clouds/cloud_clipmap.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/clouds/cloud_optics.h"
#include "core/clouds/parallel_bands.h"
#include "core/clouds/cloud_twin.h"

namespace atmo::clouds {
namespace {

// Voxels over all levels (12 bytes each on the GPU: RGBA16F + RG16F): level
// 0's voxel grows until they fit (192 MiB).
constexpr double kMaxClipmapVoxels = 16.0 * (1 << 20);

// A mip's five terms (density, the four depths) trilinearly at an index point (zero outside).
struct Terms {
  glm::vec4 a{0.0f};
  float back = 0.0f;
  Terms& operator+=(const Terms& o) {
    a += o.a;
    back += o.back;
    return *this;
  }
  friend Terms operator*(float w, const Terms& t) { return Terms{w * t.a, w * t.back}; }
  explicit Terms(float v = 0.0f) : a(v), back(v) {}
  Terms(const glm::vec4& x, float y) : a(x), back(y) {}
};

Terms sample_mip(const PrototypeMips::Mip& m, const glm::vec3& q) {
  return trilinear_zero_border<Terms>(m.nx, m.ny, m.nz, q, [&](int x, int y, int z) {
    const size_t i = (static_cast<size_t>(z) * m.ny + y) * m.nx + x;
    return Terms(m.terms[i], m.tau_back[i]);
  });
}

// Half the resolution: the mean density, and the depths weighted by density
// (the light that reaches the cloud in the cell; their plain mean where the
// cell is empty).
PrototypeMips::Mip half_of(const PrototypeMips::Mip& f) {
  PrototypeMips::Mip h;
  h.nx = (f.nx + 1) / 2, h.ny = (f.ny + 1) / 2, h.nz = (f.nz + 1) / 2;
  h.terms.assign(static_cast<size_t>(h.nx) * h.ny * h.nz, glm::vec4(0.0f));
  h.tau_back.assign(h.terms.size(), 0.0f);
  for (int z = 0; z < h.nz; ++z)
    for (int y = 0; y < h.ny; ++y)
      for (int x = 0; x < h.nx; ++x) {
        float rho = 0.0f, back_w = 0.0f, back = 0.0f;
        glm::vec3 tau_w(0.0f), tau(0.0f);
        int n = 0;
        for (int c = 0; c < 8; ++c) {
          const int fx = 2 * x + (c & 1), fy = 2 * y + ((c >> 1) & 1), fz = 2 * z + ((c >> 2) & 1);
          if (fx >= f.nx || fy >= f.ny || fz >= f.nz) continue;  // outside: zero density
          const size_t i = (static_cast<size_t>(fz) * f.ny + fy) * f.nx + fx;
          const glm::vec4& t = f.terms[i];
          rho += t.x;
          tau_w += t.x * glm::vec3(t.y, t.z, t.w);
          back_w += t.x * f.tau_back[i];
          tau += glm::vec3(t.y, t.z, t.w);
          back += f.tau_back[i];
          ++n;
        }
        const size_t o = (static_cast<size_t>(z) * h.ny + y) * h.nx + x;
        const glm::vec3 t = rho > 0.0f ? tau_w / rho : tau / float(std::max(n, 1));
        h.terms[o] = glm::vec4(rho * 0.125f, t);
        h.tau_back[o] = rho > 0.0f ? back_w / rho : back / float(std::max(n, 1));
      }
  return h;
}

void field_bounds(const CloudField& field, glm::dvec3* lo, glm::dvec3* hi) {
  *lo = glm::dvec3(std::numeric_limits<double>::max());
  *hi = -*lo;
  for (const CloudInstance& inst : field.instances) {
    const InstanceBox b = instance_box(field, inst);
    *lo = glm::min(*lo, b.lo);
    *hi = glm::max(*hi, b.hi);
  }
}

// Levels until one centred at `centre` holds the whole field (less its
// 2-voxel margins), or spec.max_levels.
int levels_needed(const glm::dvec3& lo, const glm::dvec3& hi, const ClipmapSpec& spec, double base_m,
                  const glm::dvec2& centre) {
  const double reach = std::max({centre.x - lo.x, hi.x - centre.x, centre.y - lo.y, hi.y - centre.y});
  int n = 1;
  while (n < spec.max_levels && (0.5 * spec.size - 3.0) * base_m * std::ldexp(1.0, n - 1) < reach) ++n;
  return n;
}

double voxels_for(const glm::dvec3& lo, const glm::dvec3& hi, const ClipmapSpec& spec, double base_m) {
  double total = 0.0;
  // The most levels any centre over the field needs: one centred at a corner.
  const int n = levels_needed(lo, hi, spec, base_m, glm::dvec2(lo));
  for (int l = 0; l < n; ++l)
    total += double(spec.size) * spec.size * (std::ceil((hi.z - lo.z) / std::ldexp(base_m, l)) + 2.0);
  return total;
}

// A level's corner, on multiples of its voxel v (the levels' lattices nest):
// centred on `centre`, then moved over the field's boxes (lo, hi, plus 3
// voxels) where it sticks out past them, so no voxel is spent on clear air
// that could hold cloud (an eye outside or near the edge of the field keeps
// its finest voxels on the clouds: a cumulus 2 km away, half of it at level
// 1, was 23.2 % off the path tracer against the per-cloud march's 19.7 %),
// and kept around the finer level (each level holds the one inside it, so
// the march's coarser fetches read voxels that were built). A function of
// the cell, as before.
glm::dvec2 level_corner(const glm::dvec2& lo, const glm::dvec2& hi, const glm::dvec2& centre, int size, double v,
                        const ClipmapLevel* finer) {
  const double width = size * v;
  glm::dvec2 corner;
  for (int a = 0; a < 2; ++a) {
    // The corners that put the field inside the level (or the level inside the field).
    const double first = lo[a] - 3.0 * v, last = hi[a] + 3.0 * v - width;
    double k = std::floor((centre[a] - 0.5 * width) / v);
    k = std::clamp(k, std::floor(std::min(first, last) / v), std::ceil(std::max(first, last) / v));
    if (finer) {
      const double f = finer->origin_m[a];
      const int n = a == 0 ? finer->nx : finer->ny;
      k = std::clamp(k, std::ceil((f + n * finer->voxel_m - width) / v), std::floor(f / v));
    }
    corner[a] = k * v;
  }
  return corner;
}

// The level's clear bricks (cloud_clipmap.h): occupied bricks 0, the rest
// the exact Chebyshev distance by two raster sweeps over the 26
// neighbours (a unit-weight chamfer is exact for it), seeded with the
// distance to the grid's sides.
void build_clear_bricks(ClipmapLevel* L) {
  L->bx = (L->nx + 1) / 2, L->by = (L->ny + 1) / 2, L->bz = (L->nz + 1) / 2;
  const int bx = L->bx, by = L->by, bz = L->bz;
  std::vector<uint8_t>& d = L->clear;
  d.assign(static_cast<size_t>(bx) * by * bz, 255);
  for (int y = 0; y < by; ++y)
    for (int x = 0; x < bx; ++x) {
      const int side = std::min({x + 1, bx - x, y + 1, by - y, 255});
      for (int z = 0; z < bz; ++z) d[L->brick_index(x, y, z)] = static_cast<uint8_t>(side);
    }
  for (int z = 0; z < L->nz; ++z)
    for (int y = 0; y < L->ny; ++y)
      for (int x = 0; x < L->nx; ++x)
        if (L->a[L->index(x, y, z)].x > 0.0f) d[L->brick_index(x / 2, y / 2, z / 2)] = 0;
  auto sweep = [&](int dir) {
    const int z0 = dir > 0 ? 0 : bz - 1, y0 = dir > 0 ? 0 : by - 1, x0 = dir > 0 ? 0 : bx - 1;
    for (int z = z0; z >= 0 && z < bz; z += dir)
      for (int y = y0; y >= 0 && y < by; y += dir)
        for (int x = x0; x >= 0 && x < bx; x += dir) {
          uint8_t& c = d[L->brick_index(x, y, z)];
          if (c == 0) continue;
          // The 13 neighbours already swept: the previous slice, the previous row, the previous brick.
          int best = c;
          for (int dz = -1; dz <= 0; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0))) continue;
                const int nx = x + dir * dx, ny = y + dir * dy, nz = z + dir * dz;
                if (nx < 0 || ny < 0 || nz < 0 || nx >= bx || ny >= by || nz >= bz) continue;
                best = std::min(best, d[L->brick_index(nx, ny, nz)] + 1);
              }
          c = static_cast<uint8_t>(std::min(best, 255));
        }
  };
  sweep(+1);
  sweep(-1);
}

}  // namespace

size_t CloudClipmap::memory_bytes() const {
  size_t b = 0;
  for (const ClipmapLevel& l : levels)
    b += l.a.size() * sizeof(glm::vec4) + l.b.size() * sizeof(glm::vec2) + l.clear.size();
  return b;
}

std::vector<PrototypeMips> build_prototype_mips(const CloudField& field, const std::vector<LightDepths>& depths,
                                                const glm::dvec3& light_dir_enu) {
  std::vector<PrototypeMips> out(field.prototypes.size());
  for (size_t p = 0; p < field.prototypes.size(); ++p) {
    const CloudVolume& v = field.prototypes[p];
    const DenseGrid& g = v.density;
    const LightDepths& d = depths[p];
    PrototypeMips::Mip m;
    m.nx = g.nx, m.ny = g.ny, m.nz = g.nz;
    m.terms.resize(g.voxel_count());
    m.tau_back.resize(g.voxel_count());
    // tau_back at each voxel centre as the per-cloud march takes it (cloud_march.glsl).
    twin::CloudMarch march{};
    march.grid_size = glm::vec3(g.nx, g.ny, g.nz);
    march.light_dir_grid = grid_direction(v, light_dir_enu);
    march.continuing_sides = continuing_sides_vector(d.sides);
    const CpuCloudVolume vol{&g, &d};
    for (int z = 0; z < g.nz; ++z)
      for (int y = 0; y < g.ny; ++y)
        for (int x = 0; x < g.nx; ++x) {
          const size_t i = g.index(x, y, z);
          const float rho = g.values[i];
          const glm::vec3& tau = d.tau[i];
          // Every voxel, empty or not: the depths are interpolated between voxels as the
          // per-cloud march interpolates them.
          const glm::vec3 point(x + 0.5f, y + 0.5f, z + 0.5f);
          const glm::vec2 hit = twin::cloud_box_hit(point, -march.light_dir_grid, march.grid_size);
          const glm::vec3 exit = point - march.light_dir_grid * hit.y;
          const glm::vec3 far_point = glm::clamp(exit, glm::vec3(0.5f), march.grid_size - glm::vec3(0.5f));
          const float back = std::max(std::max(fetch_cloud_volume(vol, far_point).y - tau.x, 0.0f),
                                      twin::cloud_depth_beyond_side(march, exit, tau.y, tau.z));
          m.terms[i] = glm::vec4(rho, tau);
          m.tau_back[i] = back;
        }
    out[p].mips.push_back(std::move(m));
    while (out[p].mips.back().nx > 1 || out[p].mips.back().ny > 1 || out[p].mips.back().nz > 1)
      out[p].mips.push_back(half_of(out[p].mips.back()));
  }
  return out;
}

ClipmapGeometry clipmap_geometry(const CloudField& field, const ClipmapSpec& spec) {
  ClipmapGeometry g;
  field_bounds(field, &g.lo, &g.hi);
  double base = spec.base_voxel_m;
  if (!(base > 0.0)) {
    base = std::numeric_limits<double>::max();
    for (const CloudVolume& v : field.prototypes) base = std::min(base, double(v.voxel_size_m));
    if (field.prototypes.empty()) base = 50.0;
  }
  if (!field.instances.empty())
    while (voxels_for(g.lo, g.hi, spec, base) > kMaxClipmapVoxels) base *= 1.25;
  g.base_voxel_m = base;
  g.cell_m = 0.25 * spec.size * base;
  return g;
}

glm::ivec2 clipmap_cell(const ClipmapGeometry& g, const glm::dvec3& eye_m) {
  return glm::ivec2(static_cast<int>(std::floor(eye_m.x / g.cell_m)), static_cast<int>(std::floor(eye_m.y / g.cell_m)));
}

CloudClipmap build_clipmap(const CloudField& field, const std::vector<PrototypeMips>& mips,
                           const CloudRayIndex& index, const ClipmapSpec& spec, const ClipmapGeometry& geometry,
                           const glm::ivec2& cell, const std::atomic<bool>* cancel, int threads) {
  CloudClipmap out;
  out.cell = cell;
  // The field's droplet diameters, ascending, at most the table's size.
  for (const CloudVolume& v : field.prototypes) {
    out.droplet_um.push_back(std::clamp(v.optics.droplet_diameter_um, 5.0f, 50.0f));
    out.albedo = std::min(out.albedo, v.optics.albedo);
  }
  if (out.droplet_um.empty()) out.droplet_um.push_back(20.0f);
  std::vector<float>& um = out.droplet_um;
  std::sort(um.begin(), um.end());
  um.erase(std::unique(um.begin(), um.end()), um.end());
  while (um.size() > CLOUD_LAYER_PHASES) um.erase(um.begin() + 1);  // keep the ends
  if (field.instances.empty()) return out;
  const glm::dvec3& lo = geometry.lo;
  const glm::dvec3& hi = geometry.hi;
  out.bottom_m = lo.z, out.top_m = hi.z;
  const double base = geometry.base_voxel_m;
  const glm::dvec2 centre = (glm::dvec2(cell) + 0.5) * geometry.cell_m;
  const int n_levels = levels_needed(lo, hi, spec, base, centre);
  // A prototype as one level samples it: its mip, and index space from the
  // clouds' frame (per prototype: the instances are translated copies).
  struct Placed {
    const PrototypeMips::Mip* mip;
    glm::dmat3 index_from_enu;
    float extinction, droplet_um;
  };
  std::vector<InstanceBox> boxes(field.instances.size());
  for (size_t i = 0; i < boxes.size(); ++i) boxes[i] = instance_box(field, field.instances[i]);
  std::vector<Placed> placed(field.prototypes.size());
  struct Sums {  // one voxel of a column, over the instances covering it
    float sigma = 0.0f, droplet = 0.0f;
    glm::vec4 weighted{0.0f}, plain{0.0f};  // (tau_light, tau_up, tau_down, tau_back)
    int n = 0;
  };
  for (int l = 0; l < n_levels; ++l) {
    ClipmapLevel L;
    L.voxel_m = std::ldexp(base, l);
    const double v = L.voxel_m;
    for (size_t p = 0; p < field.prototypes.size(); ++p) {
      const CloudVolume& vol = field.prototypes[p];
      const PrototypeMips& pm = mips[p];
      // The mip whose voxel is nearest the level's (the box filter that level needs).
      const int mip = std::clamp(static_cast<int>(std::lround(std::log2(v / vol.voxel_size_m))), 0,
                                 static_cast<int>(pm.mips.size()) - 1);
      placed[p] = {&pm.mips[static_cast<size_t>(mip)],
                   glm::mat3_cast(glm::inverse(vol.rotation)) / (double(vol.voxel_size_m) * std::ldexp(1.0, mip)),
                   vol.optics.extinction_per_m, vol.optics.droplet_diameter_um};
    }
    L.nx = L.ny = spec.size;
    L.nz = static_cast<int>(std::ceil((hi.z - lo.z) / v)) + 2;
    const glm::dvec2 corner =
        level_corner(glm::dvec2(lo), glm::dvec2(hi), centre, spec.size, v, l == 0 ? nullptr : &out.levels.back());
    L.origin_m = glm::dvec3(corner, lo.z - v);
    L.a.assign(static_cast<size_t>(L.nx) * L.ny * L.nz, glm::vec4(0.0f));
    L.b.assign(L.a.size(), glm::vec2(0.0f));
    // Bands of rows: each voxel is written by one thread, so the result does
    // not depend on how many share the work.
    for_bands(L.ny, threads, [&](int y_begin, int y_end) {
      std::vector<uint32_t> column;
      std::vector<Sums> sums(static_cast<size_t>(L.nz));
      for (int y = y_begin; y < y_end; ++y) {
        if (cancel && cancel->load(std::memory_order_relaxed)) return;
        for (int x = 0; x < L.nx; ++x) {
          const glm::dvec2 p(L.origin_m.x + (x + 0.5) * v, L.origin_m.y + (y + 0.5) * v);
          const int bx = static_cast<int>(std::floor((p.x - index.corner_enu_m.x) / index.cell_m));
          const int by = static_cast<int>(std::floor((p.y - index.corner_enu_m.y) / index.cell_m));
          if (bx < 0 || by < 0 || bx >= index.nx || by >= index.ny) continue;
          // The instances whose box covers the column, give or take a voxel (trilinear reach).
          column.clear();
          const size_t bucket = static_cast<size_t>(by) * index.nx + bx;
          for (uint32_t k = index.start[bucket]; k < index.start[bucket + 1]; ++k) {
            const uint32_t i = index.items[k];
            if (p.x >= boxes[i].lo.x - v && p.x <= boxes[i].hi.x + v && p.y >= boxes[i].lo.y - v &&
                p.y <= boxes[i].hi.y + v)
              column.push_back(i);
          }
          // Instance by instance over the voxels of its height range: along the
          // column its index point moves by a constant step per voxel.
          for (const uint32_t i : column) {
            const Placed& c = placed[static_cast<size_t>(field.instances[i].prototype)];
            const double z0 = boxes[i].lo.z - v, z1 = boxes[i].hi.z + v;
            const int z_lo = std::max(0, static_cast<int>(std::ceil((z0 - L.origin_m.z) / v - 0.5)));
            const int z_hi = std::min(L.nz - 1, static_cast<int>(std::floor((z1 - L.origin_m.z) / v - 0.5)));
            if (z_lo > z_hi) continue;
            const glm::dvec3 q0 =
                c.index_from_enu * (glm::dvec3(p, L.origin_m.z + (z_lo + 0.5) * v) - field.instances[i].origin_enu_m);
            const glm::dvec3 dq = c.index_from_enu[2] * v;
            for (int z = z_lo; z <= z_hi; ++z) {
              const Terms t = sample_mip(*c.mip, glm::vec3(q0 + dq * double(z - z_lo)));
              const float w = c.extinction * t.a.x;
              Sums& u = sums[static_cast<size_t>(z)];
              u.sigma += w;
              u.weighted += w * glm::vec4(t.a.y, t.a.z, t.a.w, t.back);
              u.plain += glm::vec4(t.a.y, t.a.z, t.a.w, t.back);
              u.droplet += w * c.droplet_um;
              ++u.n;
            }
          }
          // Overlapping instances: their depths weighted by density (plain where all are empty).
          for (int z = 0; z < L.nz; ++z) {
            Sums& u = sums[static_cast<size_t>(z)];
            if (u.n == 0) continue;
            const glm::vec4 tau = u.sigma > 0.0f ? u.weighted / u.sigma : u.plain / float(u.n);
            const size_t o = L.index(x, y, z);
            L.a[o] = glm::vec4(u.sigma, tau.x, tau.y, tau.z);
            L.b[o] = glm::vec2(tau.w, u.droplet);
            u = Sums{};
          }
        }
      }
    });
    if (cancel && cancel->load(std::memory_order_relaxed)) return out;
    build_clear_bricks(&L);
    out.levels.push_back(std::move(L));
  }
  return out;
}

twin::CloudLayerMarch make_layer_march(const CloudClipmap& clipmap, const glm::dvec3& eye_m, const CloudLight& light,
                                       float step_voxels, int max_steps) {
  twin::CloudLayerMarch m{};
  m.level_count = std::min(static_cast<int>(clipmap.levels.size()), CLOUD_LAYER_MAX_LEVELS);
  int slice = 0, brick_slice = 0;
  for (int l = 0; l < m.level_count; ++l) {
    const ClipmapLevel& L = clipmap.levels[static_cast<size_t>(l)];
    m.level_origin[l] = glm::vec4(glm::vec3(L.origin_m - eye_m), static_cast<float>(L.voxel_m));
    m.level_dims[l] = glm::vec4(L.nx, L.ny, L.nz, slice);
    m.level_bricks[l] = glm::vec4(L.bx, L.by, L.bz, brick_slice);
    slice += L.nz;
    brick_slice += L.bz;
  }
  m.albedo = clipmap.albedo;
  const std::vector<float>& um = clipmap.droplet_um;
  m.phase_count = static_cast<int>(um.size());
  for (int i = 0; i < m.phase_count; ++i) {
    const twin::CloudPhase ph = phase_for_droplet(um[static_cast<size_t>(i)]);
    m.phases[i] = glm::vec4(ph.g_hg, ph.g_draine, ph.alpha_draine, ph.w_draine);
    m.phase_um[i] = um[static_cast<size_t>(i)];
  }
  m.bottom_m = static_cast<float>(clipmap.bottom_m - eye_m.z);
  m.top_m = static_cast<float>(clipmap.top_m - eye_m.z);
  m.step_voxels = step_voxels;
  m.max_steps = max_steps;
  m.light_illuminance = glm::vec3(light.illuminance_lux);
  m.light_dir = glm::vec3(glm::normalize(light.direction_enu));
  m.sky_radiance = glm::vec3(light.sky_radiance);
  m.ground_radiance = glm::vec3(light.ground_radiance);
  return m;
}

twin::CloudLayerSample march_layer_ray(const CloudClipmap& clipmap, const twin::CloudLayerMarch& march,
                                       const twin::CloudOctaves& octaves, const glm::dvec3& dir, double t_max_m) {
  const CpuCloudLayer layer{&clipmap};
  return twin::cloud_layer_march(layer, march, octaves, glm::vec3(glm::normalize(dir)), static_cast<float>(t_max_m));
}

glm::vec4 fetch_cloud_layer_a(const CpuCloudLayer& v, int level, const glm::vec3& q) {
  const ClipmapLevel& L = v.clipmap->levels[static_cast<size_t>(level)];
  return trilinear_zero_border<glm::vec4>(L.nx, L.ny, L.nz, q, [&](int x, int y, int z) { return L.a[L.index(x, y, z)]; });
}

float fetch_cloud_layer_clear(const CpuCloudLayer& v, int level, const glm::ivec3& brick) {
  const ClipmapLevel& L = v.clipmap->levels[static_cast<size_t>(level)];
  const glm::ivec3 k = glm::clamp(brick, glm::ivec3(0), glm::ivec3(L.bx, L.by, L.bz) - 1);
  return L.clear.empty() ? 0.0f : static_cast<float>(L.clear[L.brick_index(k.x, k.y, k.z)]);
}

glm::vec2 fetch_cloud_layer_b(const CpuCloudLayer& v, int level, const glm::vec3& q) {
  const ClipmapLevel& L = v.clipmap->levels[static_cast<size_t>(level)];
  return trilinear_zero_border<glm::vec2>(L.nx, L.ny, L.nz, q, [&](int x, int y, int z) { return L.b[L.index(x, y, z)]; });
}

}  // namespace atmo::clouds
