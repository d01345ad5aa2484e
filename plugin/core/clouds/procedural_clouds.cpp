#include "core/clouds/procedural_clouds.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "core/clouds/noise.h"
#include "core/clouds/parallel_bands.h"

namespace atmo::clouds {
namespace {

using noise::Rng;

// A ground column is "under cloud" when its vertical optical depth exceeds
// 0.1 (the direct sun dimmed by ~10 %): thinner wisps do not count as cover.
constexpr double kCoveredOpticalDepth = 0.1;
constexpr double kPi = 3.14159265358979323846;

std::string format(const char* fmt, ...) {
  char buf[512];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  return buf;
}

float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// Polynomial smooth maximum (blend width k): blobs merge without creases.
float smooth_max(float a, float b, float k) {
  const float h = std::clamp(0.5f + 0.5f * (a - b) / k, 0.0f, 1.0f);
  return b + (a - b) * h + k * h * (1.0f - h);
}

CloudOptics optics_for(CloudLayerType t) {
  CloudOptics o;
  switch (t) {
    case CloudLayerType::Cumulus:  // 10-20 um droplets, LWC ~0.5 g/m^3: in-cloud visibility ~50 m
      o = {0.06f, 0.999f, 20.0f};
      break;
    case CloudLayerType::Stratus:  // smaller droplets, LWC ~0.2-0.3 g/m^3
      o = {0.04f, 0.999f, 12.0f};
      break;
    case CloudLayerType::Overcast:  // a thick dense deck (stratus/nimbostratus)
      o = {0.06f, 0.999f, 12.0f};
      break;
    case CloudLayerType::Cirrus:
      // Ice: IWC ~0.01 g/m^3 and large crystals give ~0.002 /m (layer optical
      // depth 0.1-1). The droplet phase fit clamps at 50 um; ice halos (22 and
      // 46 degree) are not modelled.
      o = {0.002f, 0.9999f, 50.0f};
      break;
  }
  return o;
}

void validate(const CloudLayerSpec& s) {
  auto bad = [](const char* field, const std::string& why) {
    throw std::invalid_argument(std::string("CloudLayerSpec.") + field + ": " + why);
  };
  const int type = static_cast<int>(s.type);
  if (type < 0 || type > 3) bad("type", format("unknown layer type %d", type));
  if (s.coverage_oktas < 0 || s.coverage_oktas > 8)
    bad("coverage_oktas", format("must be 0..8 (got %d)", s.coverage_oktas));
  if (!std::isfinite(s.base_m)) bad("base_m", "must be finite");
  if (!std::isfinite(s.top_m)) bad("top_m", "must be finite");
  if (!(s.top_m > s.base_m)) bad("top_m", format("must exceed base_m (got top %g m, base %g m)", s.top_m, s.base_m));
  if (!std::isfinite(s.area_size_m) || !(s.area_size_m > 0.0))
    bad("area_size_m", format("must be finite and > 0 (got %g)", s.area_size_m));
  if (!std::isfinite(s.area_centre_enu_m.x) || !std::isfinite(s.area_centre_enu_m.y))
    bad("area_centre_enu_m", "must be finite");
  if (!std::isfinite(s.max_voxel_size_m) || s.max_voxel_size_m < 0.0f)
    bad("max_voxel_size_m", format("must be finite and >= 0, 0 for the default (got %g)", s.max_voxel_size_m));
  // Below a few thousand voxels no layer can be represented at all.
  if (s.max_total_voxels < 4096) bad("max_total_voxels", format("must be >= 4096 (got %zu)", s.max_total_voxels));
}

// ---------------------------------------------------------------------------
// Cumulus: prototypes (a union of soft ellipsoids eroded by noise), placed as
// translated copies until the measured ground coverage reaches oktas/8.

// Largest cloud: 94 interior voxels at the coarsest default voxel (40 m), so
// one cloud fits in 96^3 voxels.
constexpr double kCumulusMaxWidthM = 94.0 * 40.0;
constexpr int kCumulusInteriorVoxels = 94;
constexpr size_t kMaxInstances = size_t(1) << 20;

struct Blob {
  double cx, cy, cz;  // x, y in units of the cloud's width w (centred); z in units of its height (0 = base)
  double rx, ry, rz;
};

struct CumulusPlan {
  double h_m = 0;  // height before quantisation to whole voxels
  double w_m = 0;  // horizontal size: the larger side of the blobs' bounding box
  double ext_x = 1, ext_y = 1;  // that box in units of w (the larger is 1)
  std::vector<Blob> blobs;
  uint64_t noise_seed = 0;
};

// Sizes in metres and the blob layout (normalised), independent of the voxel.
CumulusPlan plan_cumulus(uint64_t seed, double depth_m) {
  Rng rng(seed);
  CumulusPlan p;
  // Fair-weather to mediocris: heights 40-100 % of the layer depth, widths
  // 1-2x the height (humilis are wider than tall, mediocris about square).
  p.h_m = std::min(depth_m * rng.uniform(0.4, 1.0), kCumulusMaxWidthM);
  p.w_m = std::min(p.h_m * rng.uniform(1.0, 2.0), kCumulusMaxWidthM);
  const int n = 3 + static_cast<int>(rng.below(5));  // 3-7 blobs
  // The main tower reaches the top; its lower half is cut by the base (flat).
  const double r0 = rng.uniform(0.28, 0.36);
  p.blobs.push_back({rng.uniform(-0.03, 0.03), rng.uniform(-0.03, 0.03), 0.4, r0, r0 * rng.uniform(0.85, 1.15), 0.6});
  for (int i = 1; i < n; ++i) {
    const double a = rng.uniform(0.0, 2.0 * kPi);
    const double d = rng.uniform(0.12, 0.32);
    const double top = rng.uniform(0.4, 0.85);        // shoulders lower than the tower
    const double rz = top * rng.uniform(0.6, 0.8);    // bottom below 0: every blob sits on the base
    const double rx = rng.uniform(0.16, 0.28);
    p.blobs.push_back({d * std::cos(a), d * std::sin(a), top - rz, rx, rx * rng.uniform(0.8, 1.25), rz});
  }
  // Centre the blobs' bounding box and scale it so its larger side is 1 (= w).
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const Blob& b : p.blobs) {
    x0 = std::min(x0, b.cx - b.rx), x1 = std::max(x1, b.cx + b.rx);
    y0 = std::min(y0, b.cy - b.ry), y1 = std::max(y1, b.cy + b.ry);
  }
  const double scale = 1.0 / std::max(x1 - x0, y1 - y0);
  for (Blob& b : p.blobs) {
    b.cx = (b.cx - 0.5 * (x0 + x1)) * scale, b.cy = (b.cy - 0.5 * (y0 + y1)) * scale;
    b.rx *= scale, b.ry *= scale;
  }
  p.ext_x = (x1 - x0) * scale, p.ext_y = (y1 - y0) * scale;
  p.noise_seed = rng.next();
  return p;
}

struct CumulusDims {
  int nx, ny, nz;  // interior voxels (the grid adds one empty voxel per face)
};

CumulusDims cumulus_dims(const CumulusPlan& p, double v, double depth_m) {
  CumulusDims d;
  d.nx = std::max(1, static_cast<int>(std::ceil(p.ext_x * p.w_m / v - 1e-6)));
  d.ny = std::max(1, static_cast<int>(std::ceil(p.ext_y * p.w_m / v - 1e-6)));
  // Whole voxels, never above the layer top: the grid spans [base - v, base + (nz + 1) v].
  const int max_nz = std::max(1, static_cast<int>(std::floor(depth_m / v)));
  d.nz = std::clamp(static_cast<int>(std::lround(p.h_m / v)), 1, max_nz);
  return d;
}

double cumulus_voxels(const std::vector<CumulusPlan>& plans, double v, double depth_m) {
  double total = 0;
  for (const CumulusPlan& p : plans) {
    const CumulusDims d = cumulus_dims(p, v, depth_m);
    total += double(d.nx + 2) * (d.ny + 2) * (d.nz + 2);
  }
  return total;
}

CloudVolume build_cumulus(const CumulusPlan& p, float v, double depth_m, int index) {
  const CumulusDims d = cumulus_dims(p, v, depth_m);
  CloudVolume vol;
  vol.name = format("cumulus #%d", index);
  vol.voxel_size_m = v;
  vol.density = DenseGrid(d.nx + 2, d.ny + 2, d.nz + 2);
  const double w = p.w_m;
  const double h = d.nz * double(v);  // quantised height: the shape's top is the grid's last interior voxel
  // Noise scales follow the cloud's size (clouds are roughly self-similar):
  // cauliflower lumps at ~1/7 and ~1/16 of the width (Worley), turbulent
  // ripples by fBm from ~1/3 down to ~1/24.
  const double lump = 0.15 * w, lump2 = 0.065 * w, wave = 0.3 * w;
  const uint64_t s_lump = noise::derive_seed(p.noise_seed, 1), s_lump2 = noise::derive_seed(p.noise_seed, 2),
                 s_wave = noise::derive_seed(p.noise_seed, 3);
  const double half_x = 0.5 * vol.density.nx * v, half_y = 0.5 * vol.density.ny * v;
  for (int k = 1; k <= d.nz; ++k) {
    const double z = (k - 0.5) * v;  // above the base
    const float hf = static_cast<float>(z / h);
    // Erosion grows with height: flat, dense, smooth base; billowy top.
    const float erosion = 0.12f + 0.6f * smoothstep(0.05f, 0.85f, hf);
    // Denser low down (the darker base of real cumulus comes from lighting,
    // but the lower part also holds the most condensate per column).
    const float vertical = 1.0f - 0.3f * hf;
    for (int j = 1; j <= d.ny; ++j) {
      const double y = (j + 0.5) * v - half_y;
      for (int i = 1; i <= d.nx; ++i) {
        const double x = (i + 0.5) * v - half_x;
        const double qx = x / w, qy = y / w, qz = z / h;
        float shape = -1e9f;
        for (size_t b = 0; b < p.blobs.size(); ++b) {
          const Blob& bl = p.blobs[b];
          const double ux = (qx - bl.cx) / bl.rx, uy = (qy - bl.cy) / bl.ry, uz = (qz - bl.cz) / bl.rz;
          const float f = 1.0f - static_cast<float>(std::sqrt(ux * ux + uy * uy + uz * uz));
          shape = b == 0 ? f : smooth_max(shape, f, 0.15f);
        }
        // smooth_max bulges by at most k/4 over the plain max: take it off,
        // so nothing lies outside the blobs (and their bounding box).
        shape -= 0.0375f;
        if (shape <= 0.0f) continue;
        // cells and waves lie in [0, 1]: where no noise can bring the shape
        // below the soft edge the density is `vertical`, and the noise is
        // skipped (the margins keep the result bit-identical).
        if (shape - 1.01f * erosion >= 0.1f) {
          vol.density.at(i, j, k) = vertical;
          continue;
        }
        const float cells = 0.7f * std::min(1.0f, noise::worley(x / lump, y / lump, z / lump, s_lump)) +
                            0.3f * std::min(1.0f, noise::worley(x / lump2, y / lump2, z / lump2, s_lump2));
        if (shape - 0.75f * erosion * cells < -1e-4f) continue;  // empty whatever the waves
        const float waves = std::clamp(0.5f + noise::fbm(x / wave, y / wave, z / wave, 3, s_wave), 0.0f, 1.0f);
        const float raw = shape - erosion * (0.75f * cells + 0.25f * waves);
        if (raw <= 0.0f) continue;
        // Soft edge over 0.1 of a blob radius (2-4 voxels); the core is 0.7-1.
        vol.density.at(i, j, k) = smoothstep(0.0f, 0.1f, raw) * vertical;
      }
    }
  }
  return vol;
}

struct Footprint {
  int nx = 0, ny = 0;
  std::vector<uint8_t> covered;  // per column: vertical optical depth > 0.1
  size_t count = 0;
  double radius_m = 0;  // half the larger side of the covered columns' box (spacing)
};

Footprint footprint_of(const CloudVolume& vol) {
  Footprint f;
  const DenseGrid& g = vol.density;
  f.nx = g.nx, f.ny = g.ny;
  f.covered.assign(size_t(g.nx) * g.ny, 0);
  const double scale = double(vol.voxel_size_m) * vol.optics.extinction_per_m;
  int i0 = g.nx, i1 = -1, j0 = g.ny, j1 = -1;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      double sum = 0;
      for (int k = 0; k < g.nz; ++k) sum += g.at(i, j, k);
      if (sum * scale > kCoveredOpticalDepth) {
        f.covered[size_t(j) * g.nx + i] = 1;
        ++f.count;
        i0 = std::min(i0, i), i1 = std::max(i1, i), j0 = std::min(j0, j), j1 = std::max(j1, j);
      }
    }
  if (f.count) f.radius_m = 0.5 * std::max(i1 - i0 + 1, j1 - j0 + 1) * double(vol.voxel_size_m);
  return f;
}

// Cumulus over more than this is one tile of it repeated: placing clouds is
// O(area) (a ground raster and darts), repeating them O(clouds).
constexpr double kCumulusTileM = 40000.0;

void generate_cumulus(const CloudLayerSpec& spec, uint64_t seed, GeneratedLayer* out, int threads);

// The layer over spec's area as copies of one kCumulusTileM tile, each row of
// tiles shifted east by its own random fraction of the tile (wrapped inside
// it), so the copies do not line up into a lattice. Clouds whose footprint's
// centre falls outside the area are dropped. The coverage is the tile's.
void repeat_cumulus_tile(const CloudLayerSpec& spec, uint64_t seed, GeneratedLayer* out, int threads) {
  CloudLayerSpec tile = spec;
  tile.area_size_m = kCumulusTileM;
  GeneratedLayer t;
  generate_cumulus(tile, seed, &t, threads);
  const double T = kCumulusTileM, A = spec.area_size_m;
  const glm::dvec2 tile_min = spec.area_centre_enu_m - 0.5 * T, amin = spec.area_centre_enu_m - 0.5 * A;
  const int n = static_cast<int>(std::ceil(A / T - 1e-9));
  out->field.prototypes = std::move(t.field.prototypes);
  out->coverage_fraction = t.coverage_fraction;
  out->notes = std::move(t.notes);
  for (int j = 0; j < n; ++j) {
    const double shift = T * Rng(noise::derive_seed(seed, 500 + static_cast<uint64_t>(j))).uniform();
    for (int i = 0; i < n; ++i)
      for (const CloudInstance& inst : t.field.instances) {
        const CloudVolume& v = out->field.prototypes[static_cast<size_t>(inst.prototype)];
        const glm::dvec2 centre = glm::dvec2(inst.origin_enu_m) + 0.5 * glm::dvec2(v.extent_m());
        const glm::dvec2 local = centre - tile_min;
        const double x = std::fmod(std::fmod(local.x + shift, T) + T, T);
        const glm::dvec2 placed = amin + glm::dvec2(x + i * T, local.y + j * T);
        if (placed.x < amin.x || placed.y < amin.y || placed.x >= amin.x + A || placed.y >= amin.y + A) continue;
        const glm::dvec2 d = placed - centre;
        out->field.instances.push_back({inst.prototype, inst.origin_enu_m + glm::dvec3(d, 0.0)});
      }
  }
  out->notes.push_back(format("cumulus: a %.0f km tile (%zu clouds) repeated over the %.0f km area, each row of "
                              "tiles shifted; coverage measured on the tile",
                              T / 1000.0, t.field.instances.size(), A / 1000.0));
}

void generate_cumulus(const CloudLayerSpec& spec, uint64_t seed, GeneratedLayer* out, int threads) {
  if (spec.area_size_m > kCumulusTileM) {
    repeat_cumulus_tile(spec, seed, out, threads);
    return;
  }
  const double depth = spec.top_m - spec.base_m;
  const double area = spec.area_size_m;
  if (depth > kCumulusMaxWidthM)
    out->notes.push_back(format("cumulus heights capped at %.0f m (layer %.0f m deep): one cloud fits in 96^3 voxels",
                                kCumulusMaxWidthM, depth));
  // 12 prototypes for a 10 km area, 4 more per doubling, at most 24: enough
  // variety that repeats are not noticed, few enough to light every frame.
  const int n_proto = std::clamp(static_cast<int>(std::lround(12.0 + 4.0 * std::log2(area / 10000.0))), 12, 24);
  std::vector<CumulusPlan> plans;
  double w_max = 0;
  for (int i = 0; i < n_proto; ++i) {
    plans.push_back(plan_cumulus(noise::derive_seed(seed, 100 + i), depth));
    w_max = std::max(w_max, plans.back().w_m);
  }
  // The largest cloud spans ~94 voxels, voxels 20-40 m.
  double v = std::clamp(w_max / kCumulusInteriorVoxels, 20.0, 40.0);
  if (spec.max_voxel_size_m > 0) v = std::min(v, double(spec.max_voxel_size_m));
  const double v_wanted = v;
  const double needed = cumulus_voxels(plans, v, depth);
  while (cumulus_voxels(plans, v, depth) > double(spec.max_total_voxels)) v *= 1.03;
  if (v > v_wanted)
    out->notes.push_back(format("voxels coarsened from %.1f m to %.1f m to fit max_total_voxels = %zu (%.0f needed)",
                                v_wanted, v, spec.max_total_voxels, needed));
  {
    // The voxel is stored as float: compute with exactly that value, rounded up (never more voxels).
    float vf = static_cast<float>(v);
    if (double(vf) < v) vf = std::nextafter(vf, 1e30f);
    v = vf;
  }

  const glm::dvec2 amin = spec.area_centre_enu_m - 0.5 * area;
  std::vector<Footprint> prints;
  std::vector<CloudVolume> built(static_cast<size_t>(n_proto));  // each its own seed: any thread count
  for_bands(n_proto, threads, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) built[size_t(i)] = build_cumulus(plans[size_t(i)], static_cast<float>(v), depth, i);
  });
  for (int i = 0; i < n_proto; ++i) {
    CloudVolume vol = std::move(built[size_t(i)]);
    vol.optics = optics_for(CloudLayerType::Cumulus);
    // The prototype's own placement (instances replace it): centred on the area.
    vol.origin_enu_m = glm::dvec3(spec.area_centre_enu_m.x - 0.5 * vol.extent_m().x,
                                  spec.area_centre_enu_m.y - 0.5 * vol.extent_m().y, spec.base_m - v);
    Footprint f = footprint_of(vol);
    if (f.count == 0) continue;  // eroded away (only for absurdly coarse voxels)
    out->field.prototypes.push_back(std::move(vol));
    prints.push_back(std::move(f));
  }
  const int np = static_cast<int>(prints.size());
  if (np == 0) {
    out->notes.push_back("no cumulus prototype survived the voxel size; no cloud");
    return;
  }

  // Ground raster over the area: the measured coverage. Cells as fine as a
  // voxel, at most 4096 on a side (16 MiB).
  const int nc = std::clamp(static_cast<int>(std::ceil(area / v)), 1, 4096);
  const double c = area / nc;
  std::vector<uint8_t> ground(size_t(nc) * nc, 0);
  const size_t total_cells = ground.size();
  // Uncovered cells per 16x16 block: a stamp skips the covered blocks (late
  // darts of a dense layer land almost only on cloud).
  constexpr int kBlock = 16;
  const int nbk = (nc + kBlock - 1) / kBlock;
  std::vector<int> block_free(size_t(nbk) * nbk);
  for (int bj = 0; bj < nbk; ++bj)
    for (int bi = 0; bi < nbk; ++bi)
      block_free[size_t(bj) * nbk + bi] = (std::min(nc, (bi + 1) * kBlock) - bi * kBlock) *
                                          (std::min(nc, (bj + 1) * kBlock) - bj * kBlock);
  const size_t target = static_cast<size_t>(std::llround(spec.coverage_oktas / 8.0 * double(total_cells)));
  size_t covered = 0;

  // Cells newly covered by prototype p with its grid corner at o (written when `write`).
  auto stamp = [&](int p, const glm::dvec2& o, bool write) {
    const Footprint& f = prints[p];
    const double vv = v;
    const int i0 = std::max(0, static_cast<int>(std::ceil((o.x - amin.x) / c - 0.5)));
    const int i1 = std::min(nc - 1, static_cast<int>(std::floor((o.x + f.nx * vv - amin.x) / c - 0.5)));
    const int j0 = std::max(0, static_cast<int>(std::ceil((o.y - amin.y) / c - 0.5)));
    const int j1 = std::min(nc - 1, static_cast<int>(std::floor((o.y + f.ny * vv - amin.y) / c - 0.5)));
    size_t added = 0;
    for (int j = j0; j <= j1; ++j) {
      const int gj = static_cast<int>(std::floor((amin.y + (j + 0.5) * c - o.y) / vv));
      if (gj < 0 || gj >= f.ny) continue;
      int* free_row = &block_free[size_t(j / kBlock) * nbk];
      for (int i = i0; i <= i1; ++i) {
        if (free_row[i / kBlock] == 0) {  // to the block's last column
          i = (i / kBlock + 1) * kBlock - 1;
          continue;
        }
        const int gi = static_cast<int>(std::floor((amin.x + (i + 0.5) * c - o.x) / vv));
        if (gi < 0 || gi >= f.nx || !f.covered[size_t(gj) * f.nx + gi]) continue;
        uint8_t& cell = ground[size_t(j) * nc + i];
        if (cell) continue;
        ++added;
        if (write) {
          cell = 1;
          --free_row[i / kBlock];
        }
      }
    }
    return added;
  };

  // Spacing: a blue-noise (Poisson-disc) rule on the bounding footprints'
  // circles, |a - b| >= s (r_a + r_b). s starts at 1 (no overlap) and shrinks
  // when darts keep failing, down to 0.3, so broken layers get well-separated
  // clouds and 6-8 oktas get clouds that touch and merge.
  double r_max = 0, mean_cells = 0;
  for (const Footprint& f : prints) r_max = std::max(r_max, f.radius_m), mean_cells += double(f.count);
  mean_cells *= (v * v) / (c * c) / np;
  const double bucket = std::max(2.0 * r_max, c);
  const int nb = static_cast<int>(std::ceil(area / bucket)) + 1;
  std::vector<std::vector<uint32_t>> buckets(size_t(nb) * nb);
  struct Placed {
    glm::dvec2 centre;
    double r;
  };
  std::vector<Placed> placed;
  Rng rng(noise::derive_seed(seed, 7));
  double s = 1.0;
  constexpr double kMinSpacing = 0.3;
  int fails = 0;
  const double expected = double(target) / std::max(mean_cells, 1.0);
  const size_t max_attempts = static_cast<size_t>(std::min(1e8, 20000.0 + 100.0 * expected));
  bool capped = false;
  for (size_t attempt = 0; covered < target && attempt < max_attempts; ++attempt) {
    if (placed.size() >= kMaxInstances) {
      capped = true;
      break;
    }
    const int p = static_cast<int>(rng.below(static_cast<uint32_t>(np)));
    // Darts aim at gaps: a few re-draws while the centre lands on cloud.
    glm::dvec2 centre;
    for (int t = 0; t < 8; ++t) {
      centre = amin + area * glm::dvec2(rng.uniform(), rng.uniform());
      const int ci = std::min(nc - 1, static_cast<int>((centre.x - amin.x) / c));
      const int cj = std::min(nc - 1, static_cast<int>((centre.y - amin.y) / c));
      if (!ground[size_t(cj) * nc + ci]) break;
    }
    const double r = prints[p].radius_m;
    const int bi = std::min(nb - 1, static_cast<int>((centre.x - amin.x) / bucket));
    const int bj = std::min(nb - 1, static_cast<int>((centre.y - amin.y) / bucket));
    bool ok = true;
    for (int dj = -1; dj <= 1 && ok; ++dj)
      for (int di = -1; di <= 1 && ok; ++di) {
        const int x = bi + di, y = bj + dj;
        if (x < 0 || y < 0 || x >= nb || y >= nb) continue;
        for (uint32_t q : buckets[size_t(y) * nb + x]) {
          const double min_d = s * (r + placed[q].r);
          const glm::dvec2 dd = centre - placed[q].centre;
          if (dd.x * dd.x + dd.y * dd.y < min_d * min_d) {
            ok = false;
            break;
          }
        }
      }
    const CloudVolume& proto = out->field.prototypes[p];
    const glm::dvec2 corner = centre - 0.5 * glm::dvec2(proto.extent_m());
    size_t added = 0;
    if (ok) {
      added = stamp(p, corner, false);
      // A copy hidden under others adds nothing to see; want >= 10 % new cover.
      ok = double(added) >= 0.1 * double(prints[p].count) * (v * v) / (c * c) && added > 0;
    }
    // At the end, take the cloud only if it brings the coverage closer.
    if (ok && covered + added > target && covered + added - target > target - covered) ok = false;
    if (!ok) {
      if (++fails >= 64 && s > kMinSpacing) {
        s = std::max(kMinSpacing, s * 0.9);
        fails = 0;
      } else if (fails >= 4096) {
        break;
      }
      continue;
    }
    fails = 0;
    covered += stamp(p, corner, true);
    buckets[size_t(bj) * nb + bi].push_back(static_cast<uint32_t>(placed.size()));
    placed.push_back({centre, r});
    out->field.instances.push_back({p, glm::dvec3(corner.x, corner.y, spec.base_m - v)});
    if (covered >= target) break;
  }
  out->coverage_fraction = double(covered) / double(total_cells);
  const double want = spec.coverage_oktas / 8.0;
  if (std::abs(out->coverage_fraction - want) > 1.0 / 16.0)
    out->notes.push_back(format("cumulus coverage %.3f of %.3f requested: %s", out->coverage_fraction, want,
                                capped ? "instance limit reached" : "no more clouds fit at the minimum spacing"));
}

// ---------------------------------------------------------------------------
// Decks (stratus, overcast, cirrus): the area's voxel lattice cut into square
// tiles, each its own prototype with one instance. Every density is a function
// of the world (ENU) position, so neighbouring tiles sample one continuous
// field.
//
// The seam: tile interiors abut (each world voxel belongs to exactly one
// tile's interior), and each tile adds a ring of empty voxels that lies over
// its neighbours' outermost interior voxels: adjacent grids overlap by TWO
// voxels (one border ring each). Trilinear sampling with zero outside makes
// the sum of the overlapping tiles' densities equal, everywhere, to the
// trilinear interpolation of the one continuous lattice: no seam in optical
// depth (extinction adds where volumes overlap), and every grid still has
// zero borders. Per-tile lighting sees only its own tile (a limit of the
// per-volume light grids, not of the density).

struct DeckColumn {
  float m = 0;           // coverage noise, thresholded for holes
  float a = 0, b = 0;    // stratus/overcast: deck top (m); cirrus: sheet centre and half thickness (m)
  double u = 0, w = 0;   // cirrus: along- and across-streak coordinates (m)
};

class DeckModel {
 public:
  DeckModel(const CloudLayerSpec& spec, CloudLayerType type, uint64_t seed, double v)
      : type_(type), base_(spec.base_m), top_(spec.top_m), depth_(spec.top_m - spec.base_m), v_(v) {
    for (int i = 0; i < 6; ++i) seeds_[i] = noise::derive_seed(seed, 200 + i);
    // Cirrus streaks run along the upper wind: one direction from the seed.
    const double dir = Rng(noise::derive_seed(seed, 300)).uniform(0.0, kPi);
    cos_ = std::cos(dir), sin_ = std::sin(dir);
  }

  DeckColumn column(double x, double y) const {
    DeckColumn c;
    switch (type_) {
      case CloudLayerType::Stratus:
        // Holes ~1-4 km; the top undulates over 30 % of the depth at ~2.5 km.
        c.m = noise::fbm(x / 3500.0, y / 3500.0, 4, seeds_[0]);
        c.a = static_cast<float>(top_ - 0.3 * depth_ * (0.5 + 0.5 * noise::fbm(x / 2500.0, y / 2500.0, 3, seeds_[1])));
        break;
      case CloudLayerType::Overcast:
        c.a = static_cast<float>(top_ - 0.12 * depth_ * (0.5 + 0.5 * noise::fbm(x / 2500.0, y / 2500.0, 3, seeds_[1])));
        break;
      case CloudLayerType::Cirrus:
      default: {
        c.u = cos_ * x + sin_ * y, c.w = -sin_ * x + cos_ * y;
        // Streaks 10:1 (7 km along, 0.7 km across), a sheet whose height and
        // thickness wander: centre 30-70 % of the depth, half thickness 8-28 %.
        c.m = noise::fbm(c.u / 7000.0, c.w / 700.0, 4, seeds_[0]);
        const double zc = std::clamp(0.5 + 0.35 * noise::fbm(x / 9000.0, y / 9000.0, 2, seeds_[1]), 0.3, 0.7);
        const double th = std::clamp(0.17 + 0.2 * noise::fbm(x / 5000.0, y / 5000.0, 2, seeds_[2]), 0.08, 0.28);
        c.a = static_cast<float>(base_ + zc * depth_), c.b = static_cast<float>(th * depth_);
        break;
      }
    }
    return c;
  }

  // Density before the holes, in [0, 1].
  float density(const DeckColumn& c, double x, double y, double z) const {
    switch (type_) {
      case CloudLayerType::Stratus:
        // Liquid water grows with height in a stratus (adiabatic); a soft top over 20 % of the deck.
        return deck_density(c, x, y, z, 0.2f, 0.55f, 0.3f, 0.2f);
      case CloudLayerType::Overcast:
        // Dense and uniform, denser low down (the dark base of a thick deck).
        return deck_density(c, x, y, z, 0.12f, 0.95f, -0.3f, 0.12f);
      case CloudLayerType::Cirrus:
      default: {
        const double t = (z - c.a) / c.b;
        const float profile = static_cast<float>(1.0 - t * t);
        if (profile <= 0.0f) return 0.0f;
        // Fibrous: detail stretched along the streaks too.
        const float detail = noise::fbm(c.u / 2500.0, c.w / 250.0, z / 200.0, 3, seeds_[3]);
        return profile * std::clamp(0.55f + 0.8f * detail, 0.1f, 1.0f);
      }
    }
  }

  // A stratiform deck: flat base (the grid starts there), a soft top over
  // top_fraction of its depth, and core + slope * (height fraction) +
  // noise_amplitude * fBm inside.
  float deck_density(const DeckColumn& c, double x, double y, double z, float top_fraction, float core, float slope,
                     float noise_amplitude) const {
    const float above = static_cast<float>(c.a - z);
    if (above <= 0.0f) return 0.0f;
    const float thick = static_cast<float>(c.a - base_);
    const float hf = static_cast<float>(z - base_) / thick;
    const float top = smoothstep(0.0f, std::max(0.8f * float(v_), top_fraction * thick), above);
    const float inside = core + slope * hf + noise_amplitude * noise::fbm(x / 600.0, y / 600.0, z / 300.0, 3, seeds_[3]);
    return std::clamp(inside, 0.0f, 1.0f) * top;
  }

  // Width of the soft edge of the holes, in units of the coverage noise.
  float edge() const { return type_ == CloudLayerType::Cirrus ? 0.08f : 0.05f; }

 private:
  CloudLayerType type_;
  double base_, top_, depth_, v_;
  uint64_t seeds_[6];
  double cos_ = 1, sin_ = 0;
};

// A deck's voxels: cubic, whole layers filling exactly [base, top], ~3 km
// tiles; coarsened (fewer layers, then wider) until the budget holds.
struct DeckPlan {
  double v = 0, v_wanted = 0;  // the voxel edge, and the one the type asks (m)
  int layers = 0;              // through the deck
  double voxels = 0, needed = 0;  // with the tiles' borders: planned, and at v_wanted
};

int deck_tile_voxels(double v) { return std::clamp(static_cast<int>(std::lround(3000.0 / v)), 16, 126); }

DeckPlan plan_deck(const CloudLayerSpec& spec) {
  const double depth = spec.top_m - spec.base_m, area = spec.area_size_m;
  // Stratus/overcast: 40-80 m, >= 6 through the deck by default (never fewer
  // than 4); cirrus: 40-80 m, ~16 through the layer so a sheet of 8-28 % of
  // the depth keeps a few voxels.
  double v_target = spec.type == CloudLayerType::Cirrus ? std::clamp(depth / 16.0, 40.0, 80.0)
                                                        : std::clamp(depth / 6.0, 40.0, 80.0);
  if (spec.max_voxel_size_m > 0) v_target = std::min(v_target, double(spec.max_voxel_size_m));
  DeckPlan p;
  p.layers = std::max(4, static_cast<int>(std::ceil(depth / v_target - 1e-9)));
  p.v = p.v_wanted = depth / p.layers;
  // Tiles of 16-126 interior voxels: small enough to light per tile, large enough that there are not thousands.
  auto voxels = [&](double vv, int nl) {
    const double n = std::ceil(area / vv - 1e-3);
    const double tiles = std::max(1.0, std::round(n / deck_tile_voxels(vv)));
    return (n + 2.0 * tiles) * (n + 2.0 * tiles) * (nl + 2.0);
  };
  p.needed = voxels(p.v, p.layers);
  while (voxels(p.v, p.layers) > double(spec.max_total_voxels)) {
    if (p.layers > 1) {
      --p.layers;
      p.v = depth / p.layers;
    } else {
      p.v *= 1.1;  // one layer thicker than the deck: the grid top passes top_m by < one voxel
    }
  }
  p.voxels = voxels(p.v, p.layers);
  return p;
}

// Thrown out of a generation whose cancel flag was raised (caught by generate_cloud_layer's caller).
struct GenerationCancelled {};

bool cancelled(const std::atomic<bool>* cancel) { return cancel && cancel->load(std::memory_order_relaxed); }

void generate_deck(const CloudLayerSpec& spec, int oktas, uint64_t seed, GeneratedLayer* out,
                   const std::atomic<bool>* cancel, int threads) {
  const CloudLayerType type = spec.type;
  const double depth = spec.top_m - spec.base_m;
  const double area = spec.area_size_m;
  const DeckPlan plan = plan_deck(spec);
  int layers = plan.layers;
  double v = plan.v;
  if (v > plan.v_wanted)
    out->notes.push_back(format("voxels coarsened from %.1f m to %.1f m to fit max_total_voxels = %zu (%.0f needed)",
                                plan.v_wanted, v, spec.max_total_voxels, plan.needed));
  // The voxel is stored as float: round it down so whole layers never pass top_m.
  {
    float vf = static_cast<float>(v);
    while (layers > 1 && double(vf) * layers > depth) vf = std::nextafter(vf, 0.0f);
    v = vf;
  }
  if (layers < 4) out->notes.push_back(format("deck only %d voxel(s) deep (budget)", layers));

  // World voxels across; the last may pass the area's edge (by < 1 voxel;
  // slivers under a thousandth of a voxel are dropped).
  const int n = static_cast<int>(std::ceil(area / v - 1e-3));
  // Tiles of nt voxels; the last takes the remainder (0.5-1.5 nt), so no
  // tile is so thin that its overhang exceeds its half width.
  const int nt = deck_tile_voxels(v);
  const int tiles = std::max(1, static_cast<int>(std::lround(double(n) / nt)));
  auto tile_size = [&](int t) { return t == tiles - 1 ? n - t * nt : nt; };
  const int n_in = std::max(1, static_cast<int>(std::ceil(area / v - 0.5)));  // columns whose centre is in the area
  const glm::dvec2 amin = spec.area_centre_enu_m - 0.5 * area;
  const DeckModel model(spec, type, seed, v);
  const CloudOptics optics = optics_for(type);
  const double column_scale = v * optics.extinction_per_m;

  std::vector<float> m(size_t(n) * n);
  std::vector<double> od(size_t(n) * n);  // vertical optical depth before the holes
  // Rows of tiles in bands, one per thread: each voxel and column is written
  // by one, so the deck does not depend on the thread count.
  std::vector<CloudVolume> vols(size_t(tiles) * tiles);
  std::atomic<bool> stopped{false};
  for_bands(tiles, threads, [&](int ty_begin, int ty_end) {
    for (int ty = ty_begin; ty < ty_end; ++ty)
      for (int tx = 0; tx < tiles; ++tx) {
        if (tx == 0 && (cancelled(cancel) || stopped.load(std::memory_order_relaxed))) {
          stopped = true;
          return;
        }
        const int sx = tile_size(tx), sy = tile_size(ty);
        CloudVolume& vol = vols[size_t(ty) * tiles + tx];
        vol.name = format("%s tile %d,%d", cloud_layer_type_name(type), tx, ty);
        vol.voxel_size_m = static_cast<float>(v);
        vol.optics = optics;
        vol.density = DenseGrid(sx + 2, sy + 2, layers + 2);
        vol.origin_enu_m = glm::dvec3(amin.x + (tx * nt - 1) * v, amin.y + (ty * nt - 1) * v, spec.base_m - v);
        for (int j = 1; j <= sy; ++j) {
          const int gj = ty * nt + j - 1;
          const double y = amin.y + (gj + 0.5) * v;
          for (int i = 1; i <= sx; ++i) {
            const int gi = tx * nt + i - 1;
            const double x = amin.x + (gi + 0.5) * v;
            const DeckColumn col = model.column(x, y);
            double sum = 0;
            for (int k = 1; k <= layers; ++k) {
              const float d = model.density(col, x, y, spec.base_m + (k - 0.5) * v);
              vol.density.at(i, j, k) = d;
              sum += d;
            }
            m[size_t(gj) * n + gi] = col.m;
            od[size_t(gj) * n + gi] = sum * column_scale;
          }
        }
      }
  });
  if (stopped) throw GenerationCancelled{};

  // Holes: cover = smoothstep(t - e, t + e, m); find t by bisection so that
  // the fraction of the area's columns with optical depth > 0.1 is oktas/8.
  const float e = model.edge();
  const double want = oktas / 8.0;
  auto coverage_at = [&](float t) {  // (a count: the same for any thread count)
    std::atomic<size_t> cnt{0};
    for_bands(n_in, threads, [&](int j_begin, int j_end) {
      size_t c = 0;
      for (int j = j_begin; j < j_end; ++j)
        for (int i = 0; i < n_in; ++i) {
          const size_t q = size_t(j) * n + i;
          if (smoothstep(t - e, t + e, m[q]) * od[q] > kCoveredOpticalDepth) ++c;
        }
      cnt += c;
    });
    return double(cnt.load()) / (double(n_in) * n_in);
  };
  if (oktas < 8) {
    float lo = *std::min_element(m.begin(), m.end()) - 2 * e, hi = *std::max_element(m.begin(), m.end()) + 2 * e;
    for (int it = 0; it < 40; ++it) {
      if (cancelled(cancel)) throw GenerationCancelled{};
      const float mid = 0.5f * (lo + hi);
      (coverage_at(mid) > want ? lo : hi) = mid;
    }
    const float t = 0.5f * (lo + hi);
    for_bands(tiles, threads, [&](int ty_begin, int ty_end) {
      for (int ty = ty_begin; ty < ty_end; ++ty)
        for (int tx = 0; tx < tiles; ++tx) {
          CloudVolume& vol = vols[size_t(ty) * tiles + tx];
          for (int j = 1; j < vol.density.ny - 1; ++j)
            for (int i = 1; i < vol.density.nx - 1; ++i) {
              const float cover = smoothstep(t - e, t + e, m[size_t(ty * nt + j - 1) * n + (tx * nt + i - 1)]);
              for (int k = 1; k <= layers; ++k) vol.density.at(i, j, k) *= cover;
            }
        }
    });
  }

  // Measured on the final grids; empty tiles dropped.
  size_t cnt = 0;
  for (int ty = 0; ty < tiles; ++ty)
    for (int tx = 0; tx < tiles; ++tx) {
      const CloudVolume& vol = vols[size_t(ty) * tiles + tx];
      for (int j = 1; j < vol.density.ny - 1; ++j)
        for (int i = 1; i < vol.density.nx - 1; ++i) {
          const int gi = tx * nt + i - 1, gj = ty * nt + j - 1;
          if (gi >= n_in || gj >= n_in) continue;
          double sum = 0;
          for (int k = 1; k <= layers; ++k) sum += vol.density.at(i, j, k);
          if (sum * column_scale > kCoveredOpticalDepth) ++cnt;
        }
    }
  out->coverage_fraction = double(cnt) / (double(n_in) * n_in);
  for (CloudVolume& vol : vols) {
    if (max_density(vol.density) <= 0.0f) continue;
    out->field.instances.push_back({static_cast<int>(out->field.prototypes.size()), vol.origin_enu_m});
    out->field.prototypes.push_back(std::move(vol));
  }
  if (std::abs(out->coverage_fraction - want) > 1.0 / 16.0)
    out->notes.push_back(format("%s coverage %.3f of %.3f requested (columns under optical depth 0.1 do not count)",
                                cloud_layer_type_name(type), out->coverage_fraction, want));
}

}  // namespace

const char* cloud_layer_type_name(CloudLayerType t) {
  switch (t) {
    case CloudLayerType::Cumulus: return "cumulus";
    case CloudLayerType::Stratus: return "stratus";
    case CloudLayerType::Overcast: return "overcast";
    case CloudLayerType::Cirrus: return "cirrus";
  }
  return "unknown";
}

GeneratedLayer generate_cloud_layer(const CloudLayerSpec& spec, const std::atomic<bool>* cancel, int threads) {
  validate(spec);
  GeneratedLayer out;
  out.coverage_fraction = 0.0;
  if (spec.coverage_oktas == 0) {
    out.notes.push_back("0 oktas: no cloud");
    return out;
  }
  // One stream per type, so the same seed gives unrelated layers of different types.
  const uint64_t seed = noise::derive_seed(spec.seed, 1000 + static_cast<uint64_t>(spec.type));
  try {
    switch (spec.type) {
      case CloudLayerType::Cumulus:
        generate_cumulus(spec, seed, &out, threads);
        break;
      case CloudLayerType::Overcast:
        if (spec.coverage_oktas != 8)
          out.notes.push_back(format("overcast is 8 oktas (the spec asked %d)", spec.coverage_oktas));
        generate_deck(spec, 8, seed, &out, cancel, threads);
        break;
      case CloudLayerType::Stratus:
      case CloudLayerType::Cirrus:
        generate_deck(spec, spec.coverage_oktas, seed, &out, cancel, threads);
        break;
    }
  } catch (const GenerationCancelled&) {
    out = GeneratedLayer{};
    out.cancelled = true;
  }
  return out;
}

bool is_deck(CloudLayerType t) { return t != CloudLayerType::Cumulus; }

CloudLayerSpec coarser_layer_spec(const CloudLayerSpec& spec, int factor) {
  validate(spec);
  if (!is_deck(spec.type) || factor <= 1) return spec;
  CloudLayerSpec coarse = spec;
  const double f3 = double(factor) * factor * factor;
  coarse.max_total_voxels = std::max<size_t>(1, static_cast<size_t>(plan_deck(spec).voxels / f3));
  return coarse;
}

float field_density_at(const CloudField& field, const glm::dvec3& p_enu_m) {
  float sum = 0.0f;
  for (const CloudInstance& inst : field.instances) {
    const CloudVolume& vol = field.prototypes[inst.prototype];
    const glm::dvec3 local = glm::inverse(vol.rotation) * (p_enu_m - inst.origin_enu_m) / double(vol.voxel_size_m);
    const DenseGrid& g = vol.density;
    if (local.x < 0 || local.y < 0 || local.z < 0 || local.x > g.nx || local.y > g.ny || local.z > g.nz) continue;
    sum += g.sample(glm::vec3(local));
  }
  return sum;
}

}  // namespace atmo::clouds
