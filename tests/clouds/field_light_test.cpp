// Light across deck tiles (core/clouds/field_light): a deck lit as one grid
// against the same density cut into 2x2 tiles (separate prototypes, one
// instance each) plus the optical depth through the neighbours; shared
// prototypes untouched; empty fields, a single tile and an overhead light;
// the real procedural overcast deck at a 2 degree sun: seams at the tile
// borders, error against an independent march of field_density_at and
// against the exact option (every voxel's ray marched), run times (printed,
// not asserted); a stratus deck with holes against the exact option.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/clouds/field_light.h"
#include "core/clouds/procedural_clouds.h"

namespace {

using namespace atmo::clouds;

constexpr double kDeg = 3.14159265358979323846 / 180.0;

glm::dvec3 light_from(double elevation_deg, double azimuth_deg) {  // azimuth from east towards north
  const double e = elevation_deg * kDeg, a = azimuth_deg * kDeg;
  return glm::dvec3(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
}

// A deck on a lattice of n x n columns and `layers` voxels: smooth, with
// holes and a wavy top, so the light meets clear and cloudy stretches.
float deck_value(int gi, int gj, int k, int layers) {
  const double hole = std::sin(gi * 0.23) * std::cos(gj * 0.17) + 0.5 * std::sin((gi + 2 * gj) * 0.11);
  if (hole < -0.7) return 0.0f;
  const double top = layers - 1.5 + 1.5 * std::sin(gi * 0.09 + gj * 0.05);
  if (k + 0.5 > top) return 0.0f;
  const double v = 0.55 + 0.25 * std::sin(gi * 0.31 + k) * std::cos(gj * 0.27) + 0.15 * std::min(1.0, hole + 0.7);
  return static_cast<float>(std::clamp(v, 0.0, 1.0));
}

struct DeckPair {
  CloudVolume single;   // (n + 2)^2 x (layers + 2), one voxel of zero border
  CloudField tiled;     // 2 x 2 tiles of n/2 interior columns, each with its own zero border (grids overlap by 2)
  int n = 0, half = 0;
};

DeckPair make_deck_pair(int n, int layers, float voxel_m) {
  DeckPair d;
  d.n = n;
  d.half = n / 2;
  const glm::dvec3 corner(-1234.0, 567.0, 800.0);  // scene position of lattice column (0, 0)'s corner, base
  d.single.name = "single";
  d.single.voxel_size_m = voxel_m;
  d.single.density = DenseGrid(n + 2, n + 2, layers + 2);
  d.single.origin_enu_m = corner - glm::dvec3(voxel_m);
  for (int k = 0; k < layers; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) d.single.density.at(i + 1, j + 1, k + 1) = deck_value(i, j, k, layers);
  for (int ty = 0; ty < 2; ++ty)
    for (int tx = 0; tx < 2; ++tx) {
      CloudVolume t;
      t.name = "tile";
      t.voxel_size_m = voxel_m;
      t.density = DenseGrid(d.half + 2, d.half + 2, layers + 2);
      for (int k = 0; k < layers; ++k)
        for (int j = 0; j < d.half; ++j)
          for (int i = 0; i < d.half; ++i)
            t.density.at(i + 1, j + 1, k + 1) = deck_value(tx * d.half + i, ty * d.half + j, k, layers);
      t.origin_enu_m = corner + glm::dvec3((tx * d.half - 1) * double(voxel_m), (ty * d.half - 1) * double(voxel_m),
                                           -double(voxel_m));
      d.tiled.instances.push_back({static_cast<int>(d.tiled.prototypes.size()), t.origin_enu_m});
      d.tiled.prototypes.push_back(std::move(t));
    }
  return d;
}

std::vector<LightDepths> own_depths(const CloudField& f, const glm::dvec3& light) {
  std::vector<LightDepths> out;
  for (const CloudVolume& v : f.prototypes) out.push_back(compute_light_depths(v, light));
  return out;
}

// The tolerance of the tiled deck against one grid: |d tau| <= 0.3 + 3 % of
// tau. Relative to max(tau, 1) below: the octaves see exp(-a^n tau).
constexpr double kTolAbs = 0.3, kTolRel = 0.03;

struct ErrorStats {
  double max_abs = 0, mean_abs = 0, max_rel = 0, p99_rel = 0;
  double tau_at_max_rel = 0, tau_at_max_abs = 0;
  double worst_over_tolerance = 0;  // max |d tau| / (kTolAbs + kTolRel * tau)
  size_t count = 0;
};

// Every tile voxel (border rings included: they lie over the neighbours'
// interiors) against the single grid's voxel at the same place.
ErrorStats compare_tiles(const DeckPair& d, const LightDepths& single, const std::vector<LightDepths>& tiles) {
  ErrorStats s;
  double sum = 0;
  std::vector<double> rels;
  for (int ty = 0; ty < 2; ++ty)
    for (int tx = 0; tx < 2; ++tx) {
      const LightDepths& t = tiles[size_t(ty) * 2 + tx];
      for (int k = 0; k < t.nz; ++k)
        for (int j = 0; j < t.ny; ++j)
          for (int i = 0; i < t.nx; ++i) {
            const int si = tx * d.half + i, sj = ty * d.half + j;  // single-grid index (both have the border at 0)
            const double ref = single.tau[single.index(si, sj, k)].x;
            const double got = t.tau[t.index(i, j, k)].x;
            const double e = std::abs(got - ref);
            if (e > s.max_abs) s.max_abs = e, s.tau_at_max_abs = ref;
            const double rel = e / std::max(ref, 1.0);
            if (rel > s.max_rel) s.max_rel = rel, s.tau_at_max_rel = ref;
            rels.push_back(rel);
            s.worst_over_tolerance = std::max(s.worst_over_tolerance, e / (kTolAbs + kTolRel * ref));
            sum += e;
            ++s.count;
          }
    }
  s.mean_abs = sum / double(s.count);
  std::sort(rels.begin(), rels.end());
  s.p99_rel = rels[rels.size() * 99 / 100];
  return s;
}

TEST(FieldLight, TiledDeckMatchesOneGrid) {
  const DeckPair d = make_deck_pair(64, 8, 50.0f);
  for (double elevation : {2.0, 10.0, 45.0})
    for (double azimuth : {35.0, 200.0}) {
      const glm::dvec3 light = light_from(elevation, azimuth);
      const LightDepths single = compute_light_depths(d.single, light);
      std::vector<LightDepths> tiles = own_depths(d.tiled, light);
      const ErrorStats before = compare_tiles(d, single, tiles);
      add_field_light_depths(d.tiled, light, &tiles);
      const ErrorStats after = compare_tiles(d, single, tiles);
      std::vector<LightDepths> exact = own_depths(d.tiled, light);
      FieldLightOptions ex;
      ex.exact = true;
      add_field_light_depths(d.tiled, light, &exact, ex);
      const ErrorStats marched = compare_tiles(d, single, exact);
      double max_tau = 0;
      for (const glm::vec3& t : single.tau) max_tau = std::max(max_tau, double(t.x));
      std::printf("sun %4.1f deg az %5.1f (max tau %5.1f): own grid only: max %6.2f mean %6.3f | maps: max %.3f (tau "
                  "%.1f) mean %.4f, rel max %.3f (tau %.1f) p99 %.1e | marched: max %.3f mean %.4f rel max %.3f p99 %.1e\n",
                  elevation, azimuth, max_tau, before.max_abs, before.mean_abs, after.max_abs, after.tau_at_max_abs,
                  after.mean_abs, after.max_rel, after.tau_at_max_rel, after.p99_rel, marched.max_abs,
                  marched.mean_abs, marched.max_rel, marched.p99_rel);
      EXPECT_LT(after.worst_over_tolerance, 1.0) << elevation << " deg";
      EXPECT_LT(after.mean_abs, 0.05) << elevation << " deg";
      EXPECT_LT(after.p99_rel, 0.01) << elevation << " deg";
      EXPECT_LT(marched.worst_over_tolerance, 1.0) << elevation << " deg";
      EXPECT_GT(before.max_abs, 20.0) << "the tiles should differ from one grid without the neighbours";
    }
}

TEST(FieldLight, SharedPrototypesAreLeftAsTheyAre) {
  // Prototype 0: a blob placed twice; prototype 1: a blob placed once, with
  // one copy of prototype 0 between it and the light and the other west of
  // it, in its shadow.
  auto blob = [](int n) {
    CloudVolume c;
    c.voxel_size_m = 40.0f;
    c.density = DenseGrid(n, n, n);
    for (int z = 1; z < n - 1; ++z)
      for (int y = 1; y < n - 1; ++y)
        for (int x = 1; x < n - 1; ++x) {
          const double r = glm::length(glm::dvec3(x + 0.5, y + 0.5, z + 0.5) - 0.5 * n) / (0.5 * n - 1);
          c.density.at(x, y, z) = static_cast<float>(std::clamp(1.2 - r, 0.0, 1.0));
        }
    return c;
  };
  CloudField f;
  f.prototypes.push_back(blob(16));
  f.prototypes.push_back(blob(20));
  const glm::dvec3 light = light_from(20.0, 0.0);  // from the east, low
  f.instances.push_back({1, glm::dvec3(0.0, 0.0, 1000.0)});
  // 2 km east and ~0.73 km up: on prototype 1's light path.
  f.instances.push_back({0, glm::dvec3(0.0, 0.0, 1000.0) + 2000.0 * light / light.x + glm::dvec3(0, 80, 80)});
  f.instances.push_back({0, glm::dvec3(-3000.0, 0.0, 1000.0)});  // west: shaded by prototype 1
  EXPECT_EQ(sole_instance(f, 0), -1);
  EXPECT_EQ(sole_instance(f, 1), 0);

  std::vector<LightDepths> d = own_depths(f, light);
  const std::vector<LightDepths> before = d;
  add_field_light_depths(f, light, &d);
  EXPECT_TRUE(d[0].tau == before[0].tau) << "a shared prototype's light grid changed";
  // Prototype 1 against an independent march of the field's density.
  double worst = 0, added = 0;
  const CloudVolume& p1 = f.prototypes[1];
  for (int z = 0; z < p1.density.nz; ++z)
    for (int y = 0; y < p1.density.ny; ++y)
      for (int x = 0; x < p1.density.nx; ++x) {
        const glm::dvec3 p = f.instances[0].origin_enu_m + glm::dvec3(x + 0.5, y + 0.5, z + 0.5) * 40.0;
        double ref = 0;
        const double ds = 5.0;
        for (double s = 0.5 * ds; s < 4000.0; s += ds) ref += field_density_at(f, p + light * s);
        ref *= ds * p1.optics.extinction_per_m;
        const double got = d[1].tau[d[1].index(x, y, z)].x;
        worst = std::max(worst, std::abs(got - ref) / std::max(ref, 1.0));
        added = std::max(added, got - before[1].tau[d[1].index(x, y, z)].x);
      }
  std::printf("single-instance blob behind a shared one: largest optical depth added %.2f, worst relative error "
              "against a 5 m march of field_density_at %.2e\n",
              added, worst);
  EXPECT_GT(added, 1.0);
  EXPECT_LT(worst, 1e-2);
}

TEST(FieldLight, EmptySingleAndOverheadCases) {
  // Empty field; depths of the wrong count.
  CloudField empty;
  std::vector<LightDepths> none;
  add_field_light_depths(empty, light_from(5, 0), &none);
  EXPECT_TRUE(none.empty());
  EXPECT_EQ(plan_field_light(empty, 0, light_from(5, 0)).prototype, -1);

  const DeckPair d = make_deck_pair(32, 6, 60.0f);
  {
    std::vector<LightDepths> wrong(1);
    add_field_light_depths(d.tiled, light_from(5, 0), &wrong);  // 1 != 4: nothing written
    EXPECT_TRUE(wrong[0].tau.empty());
  }
  // A single tile on its own: nothing to add.
  CloudField one;
  one.prototypes.push_back(d.tiled.prototypes[0]);
  one.instances.push_back(d.tiled.instances[0]);
  std::vector<LightDepths> od = own_depths(one, light_from(3, 30));
  const std::vector<LightDepths> ob = od;
  add_field_light_depths(one, light_from(3, 30), &od);
  EXPECT_TRUE(od[0].tau == ob[0].tau);

  // Light straight up: the interiors keep their depths, the border rings
  // (over the neighbours' outer voxels) gain what lies above them, and all
  // match the single grid.
  const glm::dvec3 up(0, 0, 1);
  std::vector<LightDepths> t = own_depths(d.tiled, up);
  const std::vector<LightDepths> tb = t;
  add_field_light_depths(d.tiled, up, &t);
  double interior_change = 0;
  for (size_t p = 0; p < t.size(); ++p)
    for (int z = 0; z < t[p].nz; ++z)
      for (int y = 1; y < t[p].ny - 1; ++y)
        for (int x = 1; x < t[p].nx - 1; ++x) {
          const size_t i = t[p].index(x, y, z);
          interior_change = std::max(interior_change, double(std::abs(t[p].tau[i].x - tb[p].tau[i].x)));
        }
  const ErrorStats s = compare_tiles(d, compute_light_depths(d.single, up), t);
  std::printf("light overhead: interior change %.2e, against the single grid max %.2e\n", interior_change, s.max_abs);
  EXPECT_LT(interior_change, 1e-4);
  EXPECT_LT(s.max_abs, 1e-3);
}

// Seams: over the deck's world lattice of interior voxels, the difference of
// tau_light between neighbouring columns (x and y), at pairs that straddle a
// tile border against pairs inside a tile; and the "kink", the border
// difference minus the mean of the differences on either side of it, which
// a smooth field keeps near zero and a seam does not.
struct SeamStats {
  double border_max = 0, border_mean = 0, inside_max = 0, inside_mean = 0;
  double kink_border_max = 0, kink_border_mean = 0, kink_inside_max = 0, kink_inside_mean = 0;
};

SeamStats seams(const CloudField& f, const std::vector<LightDepths>& d) {
  const double v = f.prototypes[0].voxel_size_m;
  glm::dvec2 lo(1e300);
  int n = 0, layers = f.prototypes[0].density.nz;
  for (const CloudInstance& in : f.instances) lo = glm::min(lo, glm::dvec2(in.origin_enu_m));
  for (const CloudInstance& in : f.instances) {
    const DenseGrid& g = f.prototypes[in.prototype].density;
    n = std::max(n, static_cast<int>(std::lround((in.origin_enu_m.x - lo.x) / v)) + g.nx - 2);
    n = std::max(n, static_cast<int>(std::lround((in.origin_enu_m.y - lo.y) / v)) + g.ny - 2);
  }
  std::vector<float> tau(size_t(n) * n * layers, -1.0f);
  std::vector<int> tile(size_t(n) * n, -1);
  for (size_t i = 0; i < f.instances.size(); ++i) {
    const CloudInstance& in = f.instances[i];
    const DenseGrid& g = f.prototypes[in.prototype].density;
    const LightDepths& ld = d[in.prototype];
    const int ox = static_cast<int>(std::lround((in.origin_enu_m.x - lo.x) / v));
    const int oy = static_cast<int>(std::lround((in.origin_enu_m.y - lo.y) / v));
    for (int y = 1; y < g.ny - 1; ++y)
      for (int x = 1; x < g.nx - 1; ++x) {
        const int gx = ox + x - 1, gy = oy + y - 1;
        tile[size_t(gy) * n + gx] = static_cast<int>(i);
        for (int z = 0; z < layers; ++z) tau[(size_t(z) * n + gy) * n + gx] = ld.tau[ld.index(x, y, z)].x;
      }
  }
  SeamStats s;
  size_t nb = 0, ni = 0, kb = 0, ki = 0;
  auto at = [&](int x, int y, int z) { return double(tau[(size_t(z) * n + y) * n + x]); };
  for (int axis = 0; axis < 2; ++axis)
    for (int z = 0; z < layers; ++z)
      for (int b = 0; b < n; ++b)
        for (int a = 0; a + 1 < n; ++a) {
          const int x0 = axis == 0 ? a : b, y0 = axis == 0 ? b : a;
          const int x1 = axis == 0 ? a + 1 : b, y1 = axis == 0 ? b : a + 1;
          const int t0 = tile[size_t(y0) * n + x0], t1 = tile[size_t(y1) * n + x1];
          if (t0 < 0 || t1 < 0) continue;
          const double diff = std::abs(at(x1, y1, z) - at(x0, y0, z));
          const bool border = t0 != t1;
          (border ? s.border_max : s.inside_max) = std::max(border ? s.border_max : s.inside_max, diff);
          (border ? s.border_mean : s.inside_mean) += diff;
          ++(border ? nb : ni);
          if (a < 1 || a + 2 >= n) continue;
          const int xm = axis == 0 ? a - 1 : b, ym = axis == 0 ? b : a - 1;
          const int xp = axis == 0 ? a + 2 : b, yp = axis == 0 ? b : a + 2;
          if (tile[size_t(ym) * n + xm] < 0 || tile[size_t(yp) * n + xp] < 0) continue;
          const double mid = at(x1, y1, z) - at(x0, y0, z);
          const double side = 0.5 * ((at(x0, y0, z) - at(xm, ym, z)) + (at(xp, yp, z) - at(x1, y1, z)));
          const double kink = std::abs(mid - side);
          (border ? s.kink_border_max : s.kink_inside_max) =
              std::max(border ? s.kink_border_max : s.kink_inside_max, kink);
          (border ? s.kink_border_mean : s.kink_inside_mean) += kink;
          ++(border ? kb : ki);
        }
  s.border_mean /= std::max<size_t>(nb, 1);
  s.inside_mean /= std::max<size_t>(ni, 1);
  s.kink_border_mean /= std::max<size_t>(kb, 1);
  s.kink_inside_mean /= std::max<size_t>(ki, 1);
  return s;
}

void print_seams(const char* what, const SeamStats& s) {
  std::printf("%s: |d tau| between neighbours across borders max %.2f mean %.3f, inside tiles max %.2f mean %.3f; "
              "kink across borders max %.2f mean %.3f, inside max %.2f mean %.3f\n",
              what, s.border_max, s.border_mean, s.inside_max, s.inside_mean, s.kink_border_max, s.kink_border_mean,
              s.kink_inside_max, s.kink_inside_mean);
}

// The maps (defaults) against FieldLightOptions::exact (every voxel's ray
// marched through the other grids) over a whole field; prints the times.
ErrorStats maps_against_exact(const CloudField& f, const glm::dvec3& light, const std::vector<LightDepths>& own,
                              const char* what) {
  std::vector<LightDepths> maps = own, exact = own;
  FieldLightOptions ex;
  ex.exact = true;
  const auto t0 = std::chrono::steady_clock::now();
  add_field_light_depths(f, light, &maps);
  const auto t1 = std::chrono::steady_clock::now();
  add_field_light_depths(f, light, &exact, ex);
  const auto t2 = std::chrono::steady_clock::now();
  ErrorStats s;
  std::vector<double> rels;
  double sum = 0;
  for (size_t p = 0; p < own.size(); ++p)
    for (size_t i = 0; i < own[p].tau.size(); ++i) {
      const double ref = exact[p].tau[i].x, e = std::abs(maps[p].tau[i].x - ref);
      if (e > s.max_abs) s.max_abs = e, s.tau_at_max_abs = ref;
      const double rel = e / std::max(ref, 1.0);
      if (rel > s.max_rel) s.max_rel = rel, s.tau_at_max_rel = ref;
      rels.push_back(rel);
      s.worst_over_tolerance = std::max(s.worst_over_tolerance, e / (kTolAbs + kTolRel * ref));
      sum += e;
    }
  s.count = rels.size();
  s.mean_abs = sum / double(std::max<size_t>(s.count, 1));
  std::sort(rels.begin(), rels.end());
  s.p99_rel = rels.empty() ? 0.0 : rels[rels.size() * 99 / 100];
  std::printf("%s, sun %.0f deg: maps %.0f ms, exact march %.0f ms (informational); maps against it: max |d tau| %.3f "
              "(tau %.1f) mean %.4f, rel max %.3f (tau %.1f) p99 %.1e\n",
              what, std::asin(light.z) / kDeg, std::chrono::duration<double, std::milli>(t1 - t0).count(),
              std::chrono::duration<double, std::milli>(t2 - t1).count(), s.max_abs, s.tau_at_max_abs, s.mean_abs,
              s.max_rel, s.tau_at_max_rel, s.p99_rel);
  return s;
}

// A procedural deck between these heights, seed 7.
constexpr double kDeckBaseM = 600, kDeckTopM = 1100;
GeneratedLayer deck(CloudLayerType type, int oktas, double area_m) {
  CloudLayerSpec spec;
  spec.type = type;
  spec.coverage_oktas = oktas;
  spec.base_m = kDeckBaseM;
  spec.top_m = kDeckTopM;
  spec.area_size_m = area_m;
  spec.seed = 7;
  return generate_cloud_layer(spec);
}

TEST(FieldLight, OvercastDeckAtLowSunHasNoSeams) {
  const GeneratedLayer layer = deck(CloudLayerType::Overcast, 8, 16000);
  const CloudField& f = layer.field;
  size_t voxels = 0;
  for (const CloudVolume& v : f.prototypes) voxels += v.density.voxel_count();
  const CloudVolume& p0 = f.prototypes.at(0);
  std::printf("overcast 16 km: %zu tiles of %dx%dx%d voxels of %.1f m, %zu voxels\n", f.prototypes.size(),
              p0.density.nx, p0.density.ny, p0.density.nz, p0.voxel_size_m, voxels);
  ASSERT_GT(f.prototypes.size(), 4u);

  const glm::dvec3 light = light_from(2.0, 30.0);
  auto t0 = std::chrono::steady_clock::now();
  std::vector<LightDepths> d = own_depths(f, light);
  auto t1 = std::chrono::steady_clock::now();
  const std::vector<LightDepths> own = d;
  add_field_light_depths(f, light, &d);
  auto t2 = std::chrono::steady_clock::now();
  double plan_ms = 0;
  for (size_t p = 0; p < f.prototypes.size(); ++p) {
    const auto a = std::chrono::steady_clock::now();
    const FieldLightPlan plan = plan_field_light(f, static_cast<int>(p), light);
    plan_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - a).count();
  }
  const double own_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  const double field_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
  std::printf("sun 2 deg: own light grids (compute_light_depths) %.0f ms; across tiles (add_field_light_depths) "
              "%.0f ms, of which exit maps %.0f ms (informational, one core)\n",
              own_ms, field_ms, plan_ms);

  const SeamStats before = seams(f, own), after = seams(f, d);
  print_seams("own grids only ", before);
  print_seams("across tiles   ", after);
  EXPECT_GT(before.border_max, 2.0 * before.inside_max);  // the seam is there without it
  EXPECT_LE(after.border_max, after.inside_max);
  EXPECT_LE(after.border_mean, 1.5 * after.inside_mean);
  EXPECT_LE(after.kink_border_mean, 2.0 * after.kink_inside_mean + 0.05);

  // Against an independent march of the field's summed density (0.25 voxel
  // steps) at voxels spread over the deck.
  double worst = 0, mean = 0, max_tau = 0;
  int count = 0;
  const double v = p0.voxel_size_m, ext = p0.optics.extinction_per_m;
  for (size_t i = 0; i < f.instances.size(); ++i) {
    const CloudInstance& in = f.instances[i];
    const DenseGrid& g = f.prototypes[in.prototype].density;
    for (int s = 0; s < 12; ++s) {
      const int x = (s * 7 + int(i)) % g.nx, y = (s * 11 + 3 * int(i)) % g.ny, z = 1 + s % (g.nz - 2);
      const glm::dvec3 p = in.origin_enu_m + glm::dvec3(x + 0.5, y + 0.5, z + 0.5) * v;
      double ref = 0;
      const double ds = 0.25 * v;
      for (double t = 0.5 * ds; p.z + light.z * t < kDeckTopM + 2 * v; t += ds) ref += field_density_at(f, p + light * t);
      ref *= ds * ext;
      const double got = d[in.prototype].tau[d[in.prototype].index(x, y, z)].x;
      worst = std::max(worst, std::abs(got - ref) / std::max(ref, 1.0));
      mean += std::abs(got - ref) / std::max(ref, 1.0);
      max_tau = std::max(max_tau, ref);
      ++count;
    }
  }
  std::printf("against a march of field_density_at at %d voxels (tau up to %.0f): relative error max %.2e mean %.2e\n",
              count, max_tau, worst, mean / count);
  EXPECT_LT(worst, 1e-2);

  const ErrorStats e = maps_against_exact(f, light, own, "overcast");
  EXPECT_LT(e.worst_over_tolerance, 1.0);
  EXPECT_LT(e.p99_rel, 0.01);
}

// Real holes: a 5-okta stratus deck, 12 km, at 2 and 10 degrees.
TEST(FieldLight, StratusWithHolesAgainstTheExactMarch) {
  const GeneratedLayer layer = deck(CloudLayerType::Stratus, 5, 12000);
  ASSERT_GT(layer.field.prototypes.size(), 4u);
  for (double elevation : {2.0, 10.0}) {
    const glm::dvec3 light = light_from(elevation, 30.0);
    const ErrorStats e = maps_against_exact(layer.field, light, own_depths(layer.field, light), "stratus 5 oktas 12 km");
    EXPECT_LT(e.worst_over_tolerance, 1.0) << elevation;
    EXPECT_LT(e.p99_rel, 0.01) << elevation;
  }
}

}  // namespace

// The hemispherical depths (tau_up, tau_down) of the 2x2 tiles, each told
// which of its sides go on into a neighbour (continuing_sides), against the
// one grid's, voxel by voxel: near the inner borders (within 4 voxels) and
// elsewhere; and without the sides, which shows the seam this removes.
TEST(FieldLight, TileAmbientDepthsSeeTheNeighbouringTiles) {
  const DeckPair d = make_deck_pair(64, 8, 50.0f);
  for (size_t p = 0; p < d.tiled.prototypes.size(); ++p) {
    const ContinuingSides s = continuing_sides(d.tiled, static_cast<int>(p));
    const int tx = static_cast<int>(p % 2), ty = static_cast<int>(p / 2);
    EXPECT_EQ(s.east, tx == 0) << p;
    EXPECT_EQ(s.west, tx == 1) << p;
    EXPECT_EQ(s.north, ty == 0) << p;
    EXPECT_EQ(s.south, ty == 1) << p;
  }
  LightDepths single;
  compute_ambient_depths(d.single, &single);
  double mean_near[2] = {0, 0}, worst_near[2] = {0, 0}, mean_far[2] = {0, 0};
  size_t count_near = 0, count_far = 0;
  for (int with_sides = 0; with_sides < 2; ++with_sides) {
    count_near = count_far = 0;
    for (size_t p = 0; p < d.tiled.prototypes.size(); ++p) {
      const CloudVolume& v = d.tiled.prototypes[p];
      LightDepths t;
      compute_ambient_depths(v, &t, with_sides ? continuing_sides(d.tiled, static_cast<int>(p)) : ContinuingSides{});
      const int tx = static_cast<int>(p % 2), ty = static_cast<int>(p / 2);
      for (int k = 1; k < t.nz - 1; ++k)
        for (int j = 1; j < t.ny - 1; ++j)
          for (int i = 1; i < t.nx - 1; ++i) {
            if (v.density.at(i, j, k) <= 0.0f) continue;
            const int si = tx * d.half + i, sj = ty * d.half + j;
            const glm::vec3 ref = single.tau[single.index(si, sj, k)], got = t.tau[t.index(i, j, k)];
            const double e = 0.5 * (std::abs(got.y - ref.y) / (1.0 + ref.y) + std::abs(got.z - ref.z) / (1.0 + ref.z));
            const int from_border = std::min(std::abs(si - (d.half + 0.5)), std::abs(sj - (d.half + 0.5)));
            if (from_border <= 4) {
              mean_near[with_sides] += e, ++count_near;
              worst_near[with_sides] = std::max(worst_near[with_sides], e);
            } else {
              mean_far[with_sides] += e, ++count_far;
            }
          }
    }
    mean_near[with_sides] /= double(count_near);
    mean_far[with_sides] /= double(count_far);
    std::printf("tiles %s the neighbours: |d tau| / (1 + tau) near the inner borders mean %.3f worst %.3f (%zu voxels), "
                "elsewhere mean %.3f (%zu)\n",
                with_sides ? "seeing" : "blind to", mean_near[with_sides], worst_near[with_sides], count_near,
                mean_far[with_sides], count_far);
  }
  EXPECT_LE(mean_near[1], 0.05);
  EXPECT_LE(mean_near[1], 0.33 * mean_near[0]);
  EXPECT_LE(mean_far[1], 0.05);
}

// The neighbour search through the field's ray index (FieldNeighbours, what
// set_clouds and the relight use: a 400 km deck is 10 000 tiles) finds the
// same sides and the same light as the scan of every instance, bit for bit,
// on a stratus deck with holes at low and high Sun, from all four quarters.
TEST(FieldLight, NeighboursThroughTheIndexMatchTheFullScan) {
  const GeneratedLayer layer = deck(CloudLayerType::Stratus, 5, 12000);
  const CloudField& f = layer.field;
  ASSERT_GT(f.prototypes.size(), 9u);
  const CloudRayIndex index = build_cloud_ray_index(f);
  const FieldNeighbours nb = field_neighbours(f, index);
  for (size_t p = 0; p < f.prototypes.size(); ++p) {
    EXPECT_EQ(nb.sole[p], sole_instance(f, static_cast<int>(p)));
    const ContinuingSides a = continuing_sides(f, static_cast<int>(p)), b = continuing_sides(f, static_cast<int>(p), &nb);
    EXPECT_TRUE(a.west == b.west && a.east == b.east && a.south == b.south && a.north == b.north) << p;
  }
  size_t planned = 0;
  for (const glm::dvec3& light : {light_from(3.0, 40.0), light_from(8.0, 130.0), light_from(25.0, 220.0),
                                  light_from(60.0, 310.0)}) {
    const std::vector<LightDepths> own = own_depths(f, light);
    for (size_t p = 0; p < f.prototypes.size(); ++p) {
      const FieldLightPlan scan = plan_field_light(f, static_cast<int>(p), light);
      const FieldLightPlan near = plan_field_light(f, static_cast<int>(p), light, {}, &nb);
      ASSERT_EQ(scan.prototype, near.prototype) << p;
      ASSERT_EQ(scan.ahead.size(), near.ahead.size()) << p;
      if (scan.prototype < 0) continue;
      ++planned;
      LightDepths x = own[p], y = own[p];
      add_field_light_slices(f, scan, 0, x.nz, &x);
      add_field_light_slices(f, near, 0, y.nz, &y);
      ASSERT_TRUE(x.tau == y.tau) << "prototype " << p;
    }
  }
  EXPECT_GT(planned, 0u);
}
