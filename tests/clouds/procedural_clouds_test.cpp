// The procedural cloud generator (core/clouds/procedural_clouds): determinism,
// coverage against oktas (also re-measured here by projecting the instances'
// grids onto a ground raster written out in this file), bounds, the optical
// depth of overcast and cirrus decks, the voxel budget, the seams between deck
// tiles and the generation time.
#include <gtest/gtest.h>

#include <atomic>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "core/clouds/procedural_clouds.h"

namespace {

using namespace atmo::clouds;

CloudLayerSpec make_spec(CloudLayerType type, int oktas, double base, double top, double area, uint64_t seed = 1) {
  CloudLayerSpec s;
  s.type = type;
  s.coverage_oktas = oktas;
  s.base_m = base;
  s.top_m = top;
  s.area_size_m = area;
  s.seed = seed;
  s.area_centre_enu_m = glm::dvec2(1500.0, -700.0);  // off the origin on purpose
  return s;
}

size_t total_voxels(const CloudField& f) {
  size_t n = 0;
  for (const CloudVolume& v : f.prototypes) n += v.density.voxel_count();
  return n;
}

bool has_note(const GeneratedLayer& g, const char* word) {
  for (const std::string& n : g.notes)
    if (n.find(word) != std::string::npos) return true;
  return false;
}

// Vertical optical depth of the whole field on a ground raster (cells of side
// `cell` over the square [amin, amin + size]). A column through one grid is
// extinction * voxel * the integral of its trilinear density in z, which (the
// grids' top and bottom voxels being empty) is the bilinear interpolation of
// the grid's per-column voxel sums. Overlapping grids add.
struct OdRaster {
  int n = 0;
  double cell = 0;
  glm::dvec2 amin{0.0};
  std::vector<double> od;
};

OdRaster project(const CloudField& field, glm::dvec2 amin, double size, double cell) {
  OdRaster r;
  r.n = static_cast<int>(std::lround(size / cell));
  r.cell = size / r.n;
  r.amin = amin;
  r.od.assign(size_t(r.n) * r.n, 0.0);
  std::vector<std::vector<double>> sums(field.prototypes.size());
  for (size_t p = 0; p < field.prototypes.size(); ++p) {
    const DenseGrid& g = field.prototypes[p].density;
    sums[p].assign(size_t(g.nx) * g.ny, 0.0);
    for (int z = 0; z < g.nz; ++z)
      for (int y = 0; y < g.ny; ++y)
        for (int x = 0; x < g.nx; ++x) sums[p][size_t(y) * g.nx + x] += g.at(x, y, z);
  }
  for (const CloudInstance& inst : field.instances) {
    const CloudVolume& vol = field.prototypes[inst.prototype];
    const DenseGrid& g = vol.density;
    const double v = vol.voxel_size_m;
    const double k = v * vol.optics.extinction_per_m;
    auto sum_at = [&](int x, int y) {
      return (x < 0 || y < 0 || x >= g.nx || y >= g.ny) ? 0.0 : sums[inst.prototype][size_t(y) * g.nx + x];
    };
    const int i0 = std::max(0, static_cast<int>(std::floor((inst.origin_enu_m.x - amin.x) / r.cell)));
    const int i1 = std::min(r.n - 1, static_cast<int>(std::ceil((inst.origin_enu_m.x + g.nx * v - amin.x) / r.cell)));
    const int j0 = std::max(0, static_cast<int>(std::floor((inst.origin_enu_m.y - amin.y) / r.cell)));
    const int j1 = std::min(r.n - 1, static_cast<int>(std::ceil((inst.origin_enu_m.y + g.ny * v - amin.y) / r.cell)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        // Index-space point of the cell centre, then bilinear between centres.
        const double px = (amin.x + (i + 0.5) * r.cell - inst.origin_enu_m.x) / v - 0.5;
        const double py = (amin.y + (j + 0.5) * r.cell - inst.origin_enu_m.y) / v - 0.5;
        const int x0 = static_cast<int>(std::floor(px)), y0 = static_cast<int>(std::floor(py));
        const double fx = px - x0, fy = py - y0;
        const double s = (1 - fy) * ((1 - fx) * sum_at(x0, y0) + fx * sum_at(x0 + 1, y0)) +
                         fy * ((1 - fx) * sum_at(x0, y0 + 1) + fx * sum_at(x0 + 1, y0 + 1));
        r.od[size_t(j) * r.n + i] += k * s;
      }
  }
  return r;
}

double covered_fraction(const OdRaster& r, double threshold = 0.1) {
  size_t n = 0;
  for (double d : r.od) n += d > threshold;
  return double(n) / r.od.size();
}

OdRaster project_area(const GeneratedLayer& g, const CloudLayerSpec& s, double cell) {
  return project(g.field, s.area_centre_enu_m - 0.5 * s.area_size_m, s.area_size_m, cell);
}

// Scene density: the sum of every instance's trilinear density (written here,
// not the generator's field_density_at).
double scene_density(const CloudField& f, const glm::dvec3& p) {
  double sum = 0;
  for (const CloudInstance& inst : f.instances) {
    const CloudVolume& vol = f.prototypes[inst.prototype];
    const glm::dvec3 q = (p - inst.origin_enu_m) / double(vol.voxel_size_m);
    if (q.x < 0 || q.y < 0 || q.z < 0 || q.x > vol.density.nx || q.y > vol.density.ny || q.z > vol.density.nz) continue;
    sum += vol.density.sample(glm::vec3(q));
  }
  return sum;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ---------------------------------------------------------------------------

TEST(ProceduralDeterminism, SameSeedIdenticalDifferentSeedDifferent) {
  for (CloudLayerType type : {CloudLayerType::Cumulus, CloudLayerType::Stratus, CloudLayerType::Cirrus}) {
    const CloudLayerSpec s = type == CloudLayerType::Cirrus ? make_spec(type, 5, 8000, 9500, 10000, 77)
                                                            : make_spec(type, 4, 600, 1800, 10000, 77);
    const GeneratedLayer a = generate_cloud_layer(s), b = generate_cloud_layer(s);
    ASSERT_EQ(a.field.prototypes.size(), b.field.prototypes.size());
    ASSERT_EQ(a.field.instances.size(), b.field.instances.size());
    size_t values = 0;
    for (size_t p = 0; p < a.field.prototypes.size(); ++p) {
      const CloudVolume &x = a.field.prototypes[p], &y = b.field.prototypes[p];
      ASSERT_EQ(x.voxel_size_m, y.voxel_size_m);
      ASSERT_EQ(x.density.nx, y.density.nx);
      ASSERT_EQ(x.density.ny, y.density.ny);
      ASSERT_EQ(x.density.nz, y.density.nz);
      ASSERT_EQ(0, std::memcmp(x.density.values.data(), y.density.values.data(), x.memory_bytes())) << x.name;
      values += x.density.voxel_count();
    }
    for (size_t i = 0; i < a.field.instances.size(); ++i) {
      EXPECT_EQ(a.field.instances[i].prototype, b.field.instances[i].prototype);
      EXPECT_EQ(a.field.instances[i].origin_enu_m, b.field.instances[i].origin_enu_m);
    }
    EXPECT_EQ(a.coverage_fraction, b.coverage_fraction);

    CloudLayerSpec s2 = s;
    s2.seed = 78;
    const GeneratedLayer c = generate_cloud_layer(s2);
    bool differs = c.field.prototypes.size() != a.field.prototypes.size() ||
                   c.field.instances.size() != a.field.instances.size();
    for (size_t p = 0; !differs && p < a.field.prototypes.size(); ++p)
      differs = c.field.prototypes[p].density.values != a.field.prototypes[p].density.values;
    EXPECT_TRUE(differs) << cloud_layer_type_name(type);
    std::printf("%s: %zu prototypes, %zu instances, %zu values identical; seed 78 differs: %d\n",
                cloud_layer_type_name(type), a.field.prototypes.size(), a.field.instances.size(), values, int(differs));
  }
}

TEST(ProceduralCoverage, CumulusMatchesOktas) {
  for (int oktas : {2, 4, 6}) {
    const CloudLayerSpec s = make_spec(CloudLayerType::Cumulus, oktas, 1200, 2500, 20000, 11);
    const GeneratedLayer g = generate_cloud_layer(s);
    const double mine = covered_fraction(project_area(g, s, 25.0));
    const double want = oktas / 8.0;
    std::printf("cumulus %d oktas: want %.3f, generator %.3f, re-projected %.3f, %zu instances of %zu prototypes\n",
                oktas, want, g.coverage_fraction, mine, g.field.instances.size(), g.field.prototypes.size());
    for (const std::string& n : g.notes) std::printf("  note: %s\n", n.c_str());
    EXPECT_NEAR(g.coverage_fraction, want, 0.08);
    EXPECT_NEAR(mine, want, 0.08);
    EXPECT_NEAR(mine, g.coverage_fraction, 0.03);
  }
}

TEST(ProceduralCoverage, StratusMatchesOktas) {
  for (int oktas : {4, 8}) {
    const CloudLayerSpec s = make_spec(CloudLayerType::Stratus, oktas, 300, 700, 20000, 12);
    const GeneratedLayer g = generate_cloud_layer(s);
    const double mine = covered_fraction(project_area(g, s, 25.0));
    const double want = oktas / 8.0;
    std::printf("stratus %d oktas: want %.3f, generator %.3f, re-projected %.3f, %zu tiles\n", oktas, want,
                g.coverage_fraction, mine, g.field.instances.size());
    EXPECT_NEAR(g.coverage_fraction, want, 0.08);
    EXPECT_NEAR(mine, want, 0.08);
    EXPECT_NEAR(mine, g.coverage_fraction, 0.03);
  }
}

TEST(ProceduralSpec, ZeroOktasGivesNoInstances) {
  for (CloudLayerType type :
       {CloudLayerType::Cumulus, CloudLayerType::Stratus, CloudLayerType::Overcast, CloudLayerType::Cirrus}) {
    const GeneratedLayer g = generate_cloud_layer(make_spec(type, 0, 1000, 2000, 10000));
    EXPECT_TRUE(g.field.instances.empty()) << cloud_layer_type_name(type);
    EXPECT_TRUE(g.field.prototypes.empty()) << cloud_layer_type_name(type);
    EXPECT_EQ(g.coverage_fraction, 0.0);
  }
}

TEST(ProceduralSpec, InvalidSpecsThrowNamingTheField) {
  struct Case {
    const char* field;
    void (*edit)(CloudLayerSpec&);
  };
  const Case cases[] = {
      {"coverage_oktas", [](CloudLayerSpec& s) { s.coverage_oktas = 9; }},
      {"coverage_oktas", [](CloudLayerSpec& s) { s.coverage_oktas = -1; }},
      {"top_m", [](CloudLayerSpec& s) { s.top_m = s.base_m; }},
      {"top_m", [](CloudLayerSpec& s) { s.top_m = s.base_m - 100; }},
      {"base_m", [](CloudLayerSpec& s) { s.base_m = std::nan(""); }},
      {"top_m", [](CloudLayerSpec& s) { s.top_m = INFINITY; }},
      {"area_size_m", [](CloudLayerSpec& s) { s.area_size_m = 0; }},
      {"area_size_m", [](CloudLayerSpec& s) { s.area_size_m = -5; }},
      {"area_size_m", [](CloudLayerSpec& s) { s.area_size_m = INFINITY; }},
      {"area_centre_enu_m", [](CloudLayerSpec& s) { s.area_centre_enu_m.y = std::nan(""); }},
      {"max_voxel_size_m", [](CloudLayerSpec& s) { s.max_voxel_size_m = -1; }},
      {"max_total_voxels", [](CloudLayerSpec& s) { s.max_total_voxels = 10; }},
  };
  for (const Case& c : cases) {
    CloudLayerSpec s;
    c.edit(s);
    try {
      generate_cloud_layer(s);
      ADD_FAILURE() << "no throw for " << c.field;
    } catch (const std::invalid_argument& e) {
      std::printf("%s\n", e.what());
      EXPECT_NE(std::string(e.what()).find(c.field), std::string::npos) << e.what();
    }
  }
}

TEST(ProceduralBounds, GridsStayInTheLayerAndAreaWithEmptyBorders) {
  const CloudLayerSpec specs[] = {
      make_spec(CloudLayerType::Cumulus, 5, 1200, 2500, 15000, 3),
      make_spec(CloudLayerType::Stratus, 4, 300, 700, 12000, 3),
      make_spec(CloudLayerType::Overcast, 8, 500, 1500, 12000, 3),
      make_spec(CloudLayerType::Cirrus, 5, 8000, 9500, 12000, 3),
  };
  for (const CloudLayerSpec& s : specs) {
    const GeneratedLayer g = generate_cloud_layer(s);
    ASSERT_FALSE(g.field.instances.empty());
    const glm::dvec2 amin = s.area_centre_enu_m - 0.5 * s.area_size_m, amax = amin + s.area_size_m;
    double worst_z = -1e9, worst_xy = -1e9;  // > 0: outside by that many metres
    size_t bad_values = 0, nonzero_border = 0;
    for (const CloudInstance& inst : g.field.instances) {
      const CloudVolume& vol = g.field.prototypes[inst.prototype];
      const double v = vol.voxel_size_m;
      const glm::dvec3 lo = inst.origin_enu_m, hi = lo + vol.extent_m();
      worst_z = std::max({worst_z, (s.base_m - v) - lo.z, hi.z - (s.top_m + v)});
      const double half_w = 0.5 * std::max(vol.extent_m().x, vol.extent_m().y);
      worst_xy = std::max({worst_xy, (amin.x - half_w) - lo.x, (amin.y - half_w) - lo.y, hi.x - (amax.x + half_w),
                           hi.y - (amax.y + half_w)});
    }
    for (const CloudVolume& vol : g.field.prototypes) {
      const DenseGrid& d = vol.density;
      for (int z = 0; z < d.nz; ++z)
        for (int y = 0; y < d.ny; ++y)
          for (int x = 0; x < d.nx; ++x) {
            const float val = d.at(x, y, z);
            if (!std::isfinite(val) || val < 0.0f || val > 1.0f) ++bad_values;
            const bool border = x == 0 || y == 0 || z == 0 || x == d.nx - 1 || y == d.ny - 1 || z == d.nz - 1;
            if (border && val != 0.0f) ++nonzero_border;
          }
    }
    std::printf("%s: %zu instances, worst vertical excess %.2f m, horizontal %.2f m (<= 0 is inside), "
                "%zu bad values, %zu nonzero border voxels\n",
                cloud_layer_type_name(s.type), g.field.instances.size(), worst_z, worst_xy, bad_values, nonzero_border);
    EXPECT_LE(worst_z, 1e-3);  // a millimetre: float voxel sizes
    EXPECT_LE(worst_xy, 1e-3);
    EXPECT_EQ(bad_values, 0u);
    EXPECT_EQ(nonzero_border, 0u);
  }
}

TEST(ProceduralCumulus, PrototypesAreCumulusSized) {
  const CloudLayerSpec s = make_spec(CloudLayerType::Cumulus, 4, 1200, 2500, 20000, 5);
  const GeneratedLayer g = generate_cloud_layer(s);
  const double depth = s.top_m - s.base_m;
  const size_t np = g.field.prototypes.size();
  EXPECT_GE(np, 12u);
  EXPECT_LE(np, 24u);
  double hmin = 1e9, hmax = 0, aspect_min = 1e9, aspect_max = 0;
  int dim_max = 0;
  size_t inside = 0, core = 0;
  double base_fill = 0;
  for (const CloudVolume& vol : g.field.prototypes) {
    const DenseGrid& d = vol.density;
    dim_max = std::max({dim_max, d.nx, d.ny, d.nz});
    int top = 0, x0 = d.nx, x1 = -1, y0 = d.ny, y1 = -1;
    for (int z = 0; z < d.nz; ++z)
      for (int y = 0; y < d.ny; ++y)
        for (int x = 0; x < d.nx; ++x)
          if (d.at(x, y, z) > 0.01f) {
            top = std::max(top, z), x0 = std::min(x0, x), x1 = std::max(x1, x);
            y0 = std::min(y0, y), y1 = std::max(y1, y);
            ++inside;
            core += d.at(x, y, z) >= 0.3f;
          }
    const double h = top * double(vol.voxel_size_m);  // voxel `top` ends top voxels above the base
    const double w = std::max(x1 - x0 + 1, y1 - y0 + 1) * double(vol.voxel_size_m);
    hmin = std::min(hmin, h / depth), hmax = std::max(hmax, h / depth);
    aspect_min = std::min(aspect_min, w / h), aspect_max = std::max(aspect_max, w / h);
    // Flat base: the first layer of cloud covers a good part of the footprint.
    size_t first = 0, any = 0;
    for (int y = 0; y < d.ny; ++y)
      for (int x = 0; x < d.nx; ++x) {
        bool col = false;
        for (int z = 1; z < d.nz; ++z) col = col || d.at(x, y, z) > 0.01f;
        any += col;
        first += d.at(x, y, 1) > 0.01f;
      }
    base_fill += double(first) / double(any) / np;
  }
  std::printf("%zu prototypes, voxel %.1f m, largest grid side %d, heights %.2f-%.2f of the layer, "
              "width/height %.2f-%.2f, density >= 0.3 in %.0f %% of cloudy voxels, base layer fills %.0f %% "
              "of the footprint, %.1f MiB\n",
              np, g.field.prototypes[0].voxel_size_m, dim_max, hmin, hmax, aspect_min, aspect_max,
              100.0 * core / inside, 100.0 * base_fill, g.field.memory_bytes() / 1048576.0);
  EXPECT_LE(dim_max, 96);
  EXPECT_GE(g.field.prototypes[0].voxel_size_m, 20.0f);
  EXPECT_LE(g.field.prototypes[0].voxel_size_m, 40.0f);
  EXPECT_GE(hmin, 0.3);
  EXPECT_LE(hmax, 1.0 + 1e-9);
  EXPECT_GE(hmax, 0.8);
  EXPECT_GE(aspect_min, 0.7);
  EXPECT_LE(aspect_max, 2.5);
  EXPECT_GE(double(core) / inside, 0.6);
  EXPECT_GE(base_fill, 0.4);
}

TEST(ProceduralOvercast, ThreeHundredMetreDeckBlocksTheDirectSun) {
  const CloudLayerSpec s = make_spec(CloudLayerType::Overcast, 8, 500, 800, 10000, 9);
  const GeneratedLayer g = generate_cloud_layer(s);
  const OdRaster r = project_area(g, s, 97.0);  // ~10 000 columns, not aligned with the voxels
  std::vector<double> od = r.od;
  std::sort(od.begin(), od.end());
  const double pass = double(std::count_if(od.begin(), od.end(), [](double d) { return d >= 4.6; })) / od.size();
  std::printf("overcast 300 m: %zu columns, optical depth min %.2f, p10 %.2f, median %.2f, max %.2f; "
              "%.1f %% >= 4.6 (direct transmittance <= 1 %%), coverage %.3f\n",
              od.size(), od.front(), od[od.size() / 10], od[od.size() / 2], od.back(), 100.0 * pass,
              g.coverage_fraction);
  EXPECT_GE(pass, 0.9);
  EXPECT_NEAR(g.coverage_fraction, 1.0, 0.02);
}

TEST(ProceduralCirrus, OpticalDepthIsThin) {
  for (int oktas : {8, 5}) {
    const CloudLayerSpec s = make_spec(CloudLayerType::Cirrus, oktas, 8000, 9500, 15000, 21);
    const GeneratedLayer g = generate_cloud_layer(s);
    const OdRaster r = project_area(g, s, 50.0);
    std::vector<double> od;
    for (double d : r.od)
      if (d > 1e-4) od.push_back(d);
    ASSERT_FALSE(od.empty());
    std::sort(od.begin(), od.end());
    const double in_range =
        double(std::count_if(od.begin(), od.end(), [](double d) { return d > 0.02 && d < 3.0; })) / od.size();
    std::printf("cirrus %d oktas: cloudy columns %.3f of the area, optical depth p10 %.3f, median %.3f, p90 %.3f, "
                "max %.3f; %.1f %% in (0.02, 3); coverage %.3f; voxel %.1f m\n",
                oktas, double(od.size()) / r.od.size(), od[od.size() / 10], od[od.size() / 2],
                od[od.size() * 9 / 10], od.back(), 100.0 * in_range, g.coverage_fraction,
                g.field.prototypes[0].voxel_size_m);
    EXPECT_LT(od.back(), 3.0);
    EXPECT_GT(od[od.size() / 2], 0.02);
    EXPECT_LT(od[od.size() / 2], 1.0);
    if (oktas == 8) {
      EXPECT_GT(in_range, 0.99);
    }
  }
}

TEST(ProceduralMemory, HugeAreasStayWithinTheVoxelBudget) {
  // Generates `s`, prints what it cost, and checks the budget held by coarsening.
  auto check = [](const char* label, const CloudLayerSpec& s) {
    const auto t0 = std::chrono::steady_clock::now();
    const GeneratedLayer g = generate_cloud_layer(s);
    std::printf("%s, budget %zu: %zu voxels (%.1f MiB), voxel %.1f m, %zu instances, coverage %.3f, %.2f s\n", label,
                s.max_total_voxels, total_voxels(g.field), g.field.memory_bytes() / 1048576.0,
                g.field.prototypes[0].voxel_size_m, g.field.instances.size(), g.coverage_fraction, seconds_since(t0));
    for (const std::string& n : g.notes) std::printf("  note: %s\n", n.c_str());
    EXPECT_LE(total_voxels(g.field), s.max_total_voxels) << label;
    EXPECT_TRUE(has_note(g, "coarsened")) << label;
  };
  // Cumulus prototypes are shared, so a 200 km area costs what a 20 km one
  // does; a small budget forces the coarsening.
  CloudLayerSpec cumulus = make_spec(CloudLayerType::Cumulus, 8, 1200, 2500, 200000, 4);
  cumulus.max_total_voxels = 1u << 20;
  check("cumulus 200 km, 8 oktas", cumulus);
  check("stratus 200 km, 8 oktas", make_spec(CloudLayerType::Stratus, 8, 300, 700, 200000, 4));
}

TEST(ProceduralSeams, StratusTilesJoinWithoutASeam) {
  for (int oktas : {8, 5}) {
    const CloudLayerSpec s = make_spec(CloudLayerType::Stratus, oktas, 300, 700, 12000, 8);
    const GeneratedLayer g = generate_cloud_layer(s);
    const double v = g.field.prototypes[0].voxel_size_m;
    const glm::dvec2 amin = s.area_centre_enu_m - 0.5 * s.area_size_m;
    for (int axis = 0; axis < 2; ++axis) {
      // Tile borders: where a tile's interior starts (one voxel in from its grid corner).
      std::vector<double> bs;
      for (const CloudInstance& inst : g.field.instances) bs.push_back(inst.origin_enu_m[axis] + v);
      std::sort(bs.begin(), bs.end());
      bs.erase(std::unique(bs.begin(), bs.end(), [](double a, double b) { return std::abs(a - b) < 1e-6; }), bs.end());
      bs.erase(std::remove_if(bs.begin(), bs.end(), [&](double b) { return b < amin[axis] + 1.0; }), bs.end());
      ASSERT_FALSE(bs.empty());
      double seam = 0, control = 0;
      size_t n = 0;
      for (double b : bs)
        for (int it = 0; it < 40; ++it)
          for (int iz = 0; iz < 6; ++iz) {
            const double along = amin[1 - axis] + (it + 0.37) * s.area_size_m / 40.0;
            const double z = s.base_m + (iz + 0.5) * (s.top_m - s.base_m) / 6.0;
            auto at = [&](double across) {
              glm::dvec3 p(0.0, 0.0, z);
              p[axis] = across, p[1 - axis] = along;
              return scene_density(g.field, p);
            };
            // Half a voxel across the border, and (control) the same step well inside a tile.
            seam += std::abs(at(b - 0.25 * v) - at(b + 0.25 * v));
            control += std::abs(at(b - 7.25 * v) - at(b - 6.75 * v));
            ++n;
          }
      seam /= n, control /= n;
      std::printf("stratus %d oktas: %zu tile borders across %c, mean |density step| across a border %.4f, "
                  "inside a tile %.4f (%zu samples)\n",
                  oktas, bs.size(), axis ? 'y' : 'x', seam, control, n);
      EXPECT_LT(seam, 0.1);
      EXPECT_LT(seam, 2.0 * control + 0.01);
    }
  }
}

TEST(ProceduralPerformance, DefaultLayersGenerateQuickly) {
  const CloudLayerSpec specs[] = {
      CloudLayerSpec{},  // the default: cumulus, 20 km, 4 oktas
      make_spec(CloudLayerType::Stratus, 6, 300, 700, 40000, 1),
      make_spec(CloudLayerType::Overcast, 8, 500, 1500, 40000, 1),
      make_spec(CloudLayerType::Cirrus, 5, 8000, 9500, 40000, 1),
  };
  for (const CloudLayerSpec& s : specs) {
    const auto t0 = std::chrono::steady_clock::now();
    const GeneratedLayer g = generate_cloud_layer(s);
    const double t = seconds_since(t0);
    std::printf("%s %.0f km, %d oktas: %.2f s, %zu prototypes, %zu instances, %zu voxels (%.1f MiB), voxel %.1f m, "
                "coverage %.3f\n",
                cloud_layer_type_name(s.type), s.area_size_m / 1000.0, s.coverage_oktas, t, g.field.prototypes.size(),
                g.field.instances.size(), total_voxels(g.field), g.field.memory_bytes() / 1048576.0,
                g.field.prototypes[0].voxel_size_m, g.coverage_fraction);
    for (const std::string& n : g.notes) std::printf("  note: %s\n", n.c_str());
#ifdef NDEBUG
    EXPECT_LT(t, 10.0);
#endif
  }
}

// Over more than 40 km a cumulus layer is one 40 km tile repeated, each row
// of tiles shifted by its own amount: the clouds cover the whole area at the
// tile's coverage (measured here on the whole area, independently), stay in
// it, and the rows do not repeat one another.
TEST(ProceduralCumulus, LargeAreasRepeatATileWithShiftedRows) {
  const CloudLayerSpec s = make_spec(CloudLayerType::Cumulus, 4, 1200, 2500, 100000, 5);
  const GeneratedLayer g = generate_cloud_layer(s);
  const double mine = covered_fraction(project_area(g, s, 100.0));
  std::printf("cumulus 100 km, 4 oktas: %zu instances, generator %.3f, re-projected over the area %.3f\n",
              g.field.instances.size(), g.coverage_fraction, mine);
  for (const std::string& n : g.notes) std::printf("  note: %s\n", n.c_str());
  EXPECT_TRUE(has_note(g, "repeated"));
  EXPECT_NEAR(mine, 0.5, 0.08);
  const glm::dvec2 amin = s.area_centre_enu_m - 0.5 * s.area_size_m;
  std::vector<double> row0, row1;  // east positions (mod the tile) of the clouds in the first two rows
  for (const CloudInstance& inst : g.field.instances) {
    const CloudVolume& v = g.field.prototypes[static_cast<size_t>(inst.prototype)];
    const glm::dvec2 c = glm::dvec2(inst.origin_enu_m) + 0.5 * glm::dvec2(v.extent_m()) - amin;
    ASSERT_GE(c.x, 0.0);
    ASSERT_GE(c.y, 0.0);
    ASSERT_LT(c.x, s.area_size_m);
    ASSERT_LT(c.y, s.area_size_m);
    if (c.y < 40000.0) row0.push_back(std::fmod(c.x, 40000.0));
    else if (c.y < 80000.0) row1.push_back(std::fmod(c.x, 40000.0));
  }
  std::sort(row0.begin(), row0.end());
  int same = 0;
  for (double x : row1) {
    const auto it = std::lower_bound(row0.begin(), row0.end(), x - 1.0);
    if (it != row0.end() && *it <= x + 1.0) ++same;
  }
  std::printf("  clouds of row 1 at a row-0 cloud's east position (mod 40 km): %d of %zu\n", same, row1.size());
  EXPECT_LT(same, static_cast<int>(row1.size()) / 10);
  EXPECT_EQ(generate_cloud_layer(s).field.instances.size(), g.field.instances.size());  // deterministic
}

}  // namespace

// The streamed set-up's coarse decks: about twice the voxel edge (an eighth
// of the voxels), the same layer (heights, area, coverage); cumulus as asked.
TEST(ProceduralCoarse, CoarserDecksHaveAnEighthOfTheVoxelsAndTheSameCoverage) {
  for (CloudLayerType type : {CloudLayerType::Stratus, CloudLayerType::Overcast, CloudLayerType::Cirrus}) {
    const CloudLayerSpec s = type == CloudLayerType::Cirrus ? make_spec(type, 4, 8000, 9000, 30000, 5)
                                                            : make_spec(type, 6, 800, 1300, 30000, 5);
    const GeneratedLayer full = generate_cloud_layer(s), coarse = generate_cloud_layer(coarser_layer_spec(s, 2));
    const double ratio = double(total_voxels(full.field)) / double(total_voxels(coarse.field));
    const double edge = coarse.field.prototypes[0].voxel_size_m / full.field.prototypes[0].voxel_size_m;
    std::printf("%s: %zu voxels of %.1f m, coarse %zu of %.1f m (%.1fx fewer); coverage %.3f, coarse %.3f\n",
                cloud_layer_type_name(type), total_voxels(full.field), full.field.prototypes[0].voxel_size_m,
                total_voxels(coarse.field), coarse.field.prototypes[0].voxel_size_m, ratio, full.coverage_fraction,
                coarse.coverage_fraction);
    EXPECT_GE(ratio, 6.0) << cloud_layer_type_name(type);
    EXPECT_LE(ratio, 16.0) << cloud_layer_type_name(type);
    EXPECT_GE(edge, 1.6) << cloud_layer_type_name(type);
    EXPECT_NEAR(coarse.coverage_fraction, full.coverage_fraction, 0.05) << cloud_layer_type_name(type);
    for (const CloudVolume& v : coarse.field.prototypes) EXPECT_LE(v.voxel_size_m, s.top_m - s.base_m);
  }
  const CloudLayerSpec cumulus = make_spec(CloudLayerType::Cumulus, 4, 1200, 2500, 10000, 5);
  EXPECT_EQ(coarser_layer_spec(cumulus, 2).max_total_voxels, cumulus.max_total_voxels);
}

// A raised cancel flag stops a deck's generation: nothing is returned.
TEST(ProceduralCoarse, CancelledGenerationReturnsNothing) {
  const std::atomic<bool> raised{true};
  const GeneratedLayer g = generate_cloud_layer(make_spec(CloudLayerType::Overcast, 8, 600, 1100, 20000, 3), &raised);
  EXPECT_TRUE(g.cancelled);
  EXPECT_TRUE(g.field.prototypes.empty());
  const std::atomic<bool> lowered{false};
  EXPECT_FALSE(generate_cloud_layer(make_spec(CloudLayerType::Overcast, 8, 600, 1100, 20000, 3), &lowered).cancelled);
}

// generate_cloud_layer's `threads` share the work; the layer is bit-identical
// for any count (determinism: a frame may not depend on thread timing).
TEST(ProceduralThreads, AnyThreadCountGivesTheSameLayer) {
  const CloudLayerSpec specs[] = {make_spec(CloudLayerType::Cumulus, 8, 1000, 2800, 20000, 3),
                                  make_spec(CloudLayerType::Cumulus, 2, 1000, 2800, 60000, 5),
                                  make_spec(CloudLayerType::Stratus, 6, 800, 1300, 30000, 3),
                                  make_spec(CloudLayerType::Cirrus, 4, 8000, 9000, 30000, 7)};
  for (const CloudLayerSpec& spec : specs) {
    const GeneratedLayer one = generate_cloud_layer(spec, nullptr, 1);
    const GeneratedLayer three = generate_cloud_layer(spec, nullptr, 3);
    SCOPED_TRACE(cloud_layer_type_name(spec.type));
    ASSERT_FALSE(one.field.prototypes.empty());
    ASSERT_EQ(one.field.prototypes.size(), three.field.prototypes.size());
    ASSERT_EQ(one.field.instances.size(), three.field.instances.size());
    EXPECT_EQ(one.coverage_fraction, three.coverage_fraction);
    for (size_t p = 0; p < one.field.prototypes.size(); ++p) {
      const DenseGrid& a = one.field.prototypes[p].density;
      const DenseGrid& b = three.field.prototypes[p].density;
      ASSERT_EQ(a.values.size(), b.values.size()) << "prototype " << p;
      ASSERT_EQ(0, std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(float))) << "prototype " << p;
    }
    for (size_t i = 0; i < one.field.instances.size(); ++i) {
      ASSERT_EQ(one.field.instances[i].prototype, three.field.instances[i].prototype);
      ASSERT_EQ(one.field.instances[i].origin_enu_m, three.field.instances[i].origin_enu_m);
    }
  }
}
