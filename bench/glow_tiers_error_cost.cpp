// atmo_glow_tiers_error_cost — the glows' tiers (core/lights/glow_tiles.h: per screen tile, the lights
// whose glow is largest exactly, the rest of the tree's cut merged) against every light's exact glow, for
// budgets around the shipped one: error against cost, in RVR 550 m fog and in 5 km haze.
//
//   atmo_glow_tiers_error_cost [--lights N] [--csv FILE]
//
// Scene (a town and an approach, as the scale bench, built here in the eye's ENU frame): the eye 60 m up
// looking north 3 degrees down, 1280 x 720, 40 degrees high; N lights (default 15 000) over 4 km x 3 km
// from 300 m ahead (a third street lights cut off upwards, a sixth headlights along the streets, the rest
// windows and signs, 20-2 500 cd) and 30 approach lights beamed at the eye (20 000 cd) from 300 to 1 200 m;
// the glow threshold 2.4e-3 cd/m^2 (EV100 2).
//
// The smooth image (a quarter of the viewport across, core/lights/glow_tiles.h) at every 4th of its pixels
// each way (80 x 45 rays): the reference is every light's glow along the pixel's ray by the twin
// (atmo_fog_glow, sin gamma floored at the core angle's, as the smooth part is), no list and no tile; the
// tiers' value is the sum over the pixel's tile list (its exact lights and merged lights) by the same twin,
// as fog_glow_smooth.frag does. Error over the pixels whose reference exceeds the threshold: median,
// 95th percentile, total (the image's sum against the reference's). Cost: the glow evaluations per pixel
// (the list length the smooth pass evaluates per reduced pixel: its GPU cost is proportional to it; the
// scale bench measures it against the pair) and bin_glows' CPU time (median of 3, 2 threads).
// The airlight form's own error against the brute-force quadrature: docs/measurements/fog_airlight_error.md.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "core/clouds/parallel_bands.h"
#include "core/fog/fog_frame.h"
#include "core/fog/fog_model.h"
#include "core/fog/fog_twin.h"
#include "core/lights/glow_tiles.h"
#include "core/lights/light_set.h"
#include "core/lights/light_tree.h"

namespace {

using namespace atmo;

constexpr int kWidth = 1280, kHeight = 720;
constexpr double kThreshold = 2.4e-3;  // cd/m^2
constexpr double kEyeHeightM = 60.0;

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

fog::FrameLight cone_light(glm::vec3 p, float cd, glm::vec3 axis, double inner_deg, double outer_deg, float lobes) {
  fog::FrameLight l;
  l.position_enu_m = p;
  l.intensity_cd = glm::vec3(cd);
  l.axis_enu = glm::normalize(axis);
  l.cos_inner = static_cast<float>(std::cos(glm::radians(inner_deg)));
  l.cos_outer = static_cast<float>(std::cos(glm::radians(outer_deg)));
  l.lobes = lobes;
  return l;
}

std::vector<fog::FrameLight> town(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<fog::FrameLight> out;
  for (int i = 0; i < n; ++i) {
    const glm::vec3 ground(-2000.0f + 4000.0f * u(rng), 300.0f + 3000.0f * u(rng), float(-kEyeHeightM));
    if (i % 3 == 0) {  // a street light, 9 m up, cut off upwards
      out.push_back(cone_light(ground + glm::vec3(0, 0, 9), 2500.0f, {0, 0, -1}, 55.0, 85.0, 1.0f));
    } else if (i % 6 == 1) {  // a headlight along a street (east or west)
      out.push_back(cone_light(ground + glm::vec3(0, 0, 0.7f), 10000.0f, {u(rng) < 0.5f ? 1.0f : -1.0f, 0, -0.03f},
                               10.0, 30.0, 1.0f));
    } else {  // a window or a sign
      fog::FrameLight l;
      l.position_enu_m = ground + glm::vec3(0, 0, 3.0f + 20.0f * u(rng));
      l.intensity_cd = glm::vec3(20.0f + 130.0f * u(rng));
      out.push_back(l);
    }
  }
  for (int i = 0; i < 30; ++i)  // approach lights beamed at the eye (3 degrees up)
    out.push_back(cone_light({0.0f, 300.0f + 30.0f * i, float(-kEyeHeightM) + 1.0f}, 20000.0f,
                             {0, -1, std::tan(glm::radians(3.0f))}, 10.0, 25.0, 1.0f));
  return out;
}

struct Air {
  const char* name;
  double extinction_per_m;
};

struct Stats {
  double median = 0, p95 = 0, total = 0, evaluations = 0;
  size_t pixels = 0;
};

}  // namespace

int main(int argc, char** argv) {
  int light_count = 15000;
  std::string csv_path;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const char* v = i + 1 < argc ? argv[i + 1] : "";
    if (a == "--lights") {
      light_count = std::atoi(v);
      ++i;
      if (light_count < 1 || light_count > int(lights::kMaxLights)) {
        std::fprintf(stderr, "atmo_glow_tiers_error_cost: --lights %s is outside [1, %u]\n", v, lights::kMaxLights);
        return 2;
      }
    } else if (a == "--csv") {
      csv_path = v;
      ++i;
    } else {
      std::fprintf(stderr, "atmo_glow_tiers_error_cost: unknown option %s (--lights N, --csv FILE)\n", a.c_str());
      return 2;
    }
  }
  const glm::dmat4 projection = glm::perspective(glm::radians(40.0), double(kWidth) / kHeight, 1.0, 1e5);
  const double pitch = glm::radians(-3.0);
  const glm::dmat4 view = glm::lookAt(glm::dvec3(0.0), glm::dvec3(0.0, std::cos(pitch), std::sin(pitch)),
                                      glm::dvec3(0.0, 0.0, 1.0));
  const glm::dmat4 clip_from_enu = projection * view;
  const glm::dmat4 enu_from_clip = glm::inverse(clip_from_enu);
  const double min_sin = fog::glow_min_sin(std::tan(glm::radians(20.0)), kHeight);
  const fog::FogTable table = fog::build_airlight_table(64, fog::kFogPhaseG);
  const float table_size = float(table.width);
  const fog::GlowBound bound(fog::kFogPhaseG);
  const float albedo = float(fog::kFogAlbedo);
  const int sw = kWidth / lights::kGlowDivisor, sh = kHeight / lights::kGlowDivisor;
  const int threads = 2;

  struct Budget {
    const char* name;
    lights::GlowBudget b;
  };
  const lights::GlowBudget shipped;
  const std::vector<Budget> budgets = {
      {"exact 0, merged 4", {0, 4, shipped.opens}},
      {"exact 2, merged 4", {2, 4, shipped.opens}},
      {"exact 6, merged 0", {6, 0, shipped.opens}},
      {"exact 6, merged 1", {6, 1, shipped.opens}},
      {"exact 6, merged 4, 24 opens", {6, 4, 24}},
      {"shipped: exact 6, merged 4, 96 opens", shipped},
      {"exact 6, merged 4, 384 opens", {6, 4, 384}},
      {"exact 12, merged 4", {12, 4, shipped.opens}},
      {"exact 24, merged 4, 384 opens", {24, 4, 384}},
      {"every reaching light exact", {1 << 20, 0, 1 << 30}},
  };

  FILE* csv = csv_path.empty() ? nullptr : std::fopen(csv_path.c_str(), "w");
  if (!csv_path.empty() && !csv) {
    std::fprintf(stderr, "atmo_glow_tiers_error_cost: cannot write %s\n", csv_path.c_str());
    return 1;
  }
  if (csv) std::fprintf(csv, "air,budget,exact,merged,opens,evaluations_per_pixel,cpu_ms,median,p95,total,pixels\n");
  std::printf("== %d lights, %dx%d (smooth image %dx%d, every 4th pixel each way), threshold %.1e cd/m^2 ==\n",
              light_count + 30, kWidth, kHeight, sw, sh, kThreshold);

  for (const Air air : {Air{"RVR 550 m fog", 3.0 / 550.0}, Air{"5 km haze", 3.0 / 5000.0}}) {
    fog::FogFrame frame;
    frame.extinction_per_m = air.extinction_per_m;
    frame.lights = town(light_count, 7);
    for (fog::FrameLight& l : frame.lights) {
      l.beta_per_m = float(air.extinction_per_m);
      l.mean_profile = float(lights::mean_cone_profile(l.cos_inner, l.cos_outer, l.lobes));
      const double d = glm::length(glm::dvec3(l.position_enu_m));
      const double peak = std::max({l.intensity_cd.x, l.intensity_cd.y, l.intensity_cd.z});
      l.glow_radius_rad = float(bound.radius_rad(air.extinction_per_m, albedo, d, peak,
                                                 fog::kGlowReachFraction * kThreshold));
      l.visible_radius_rad = float(bound.radius_rad(air.extinction_per_m, albedo, d, peak, kThreshold));
    }
    const lights::LightTree tree = lights::build_light_tree(frame.lights);
    // The rays: every 4th pixel of the smooth image each way, at its block's centre.
    std::vector<glm::vec3> rays;
    std::vector<int> tiles_of;  // filled per budget (the grid is the same)
    for (int y = 2; y < sh; y += 4)
      for (int x = 2; x < sw; x += 4) {
        const glm::dvec2 ndc((x + 0.5) / sw * 2.0 - 1.0, (y + 0.5) / sh * 2.0 - 1.0);
        const glm::dvec4 p = enu_from_clip * glm::dvec4(ndc, 0.5, 1.0);
        rays.push_back(glm::vec3(glm::normalize(glm::dvec3(p) / p.w)));
      }
    const lights::GlowTiles any = lights::bin_glows(frame, tree, table, clip_from_enu, kWidth, kHeight, min_sin);
    const float core_sin = any.core_sin;
    const auto glow = [&](const fog::FrameLight& l, const glm::vec3& dir) {
      return double(l.intensity_cd.y) * albedo *
             fog::twin::atmo_fog_glow(table, table_size, l.beta_per_m, l.position_enu_m, dir, l.axis_enu,
                                      l.cos_inner, l.cos_outer, l.lobes, fog::twin::ATMO_FOG_FAR, core_sin);
    };
    // The reference: every light along every ray.
    std::vector<double> reference(rays.size(), 0.0);
    const double r0 = now_ms();
    clouds::for_bands(int(rays.size()), threads, [&](int begin, int end) {
      for (int r = begin; r < end; ++r)
        for (const fog::FrameLight& l : frame.lights) reference[size_t(r)] += glow(l, rays[size_t(r)]);
    });
    std::printf("\n%s: the reference (%zu rays x %zu lights) in %.1f s\n", air.name, rays.size(), frame.lights.size(),
                (now_ms() - r0) / 1000.0);
    std::printf("  %-40s %10s %9s %8s %8s %8s %7s\n", "budget", "evals/px", "cpu_ms", "median", "p95", "total",
                "pixels");
    for (const Budget& budget : budgets) {
      std::vector<double> cpu;
      lights::GlowTiles g;
      for (int k = 0; k < 3; ++k) {
        const double t0 = now_ms();
        g = lights::bin_glows(frame, tree, table, clip_from_enu, kWidth, kHeight, min_sin, budget.b);
        cpu.push_back(now_ms() - t0);
      }
      std::sort(cpu.begin(), cpu.end());
      // Each smooth pixel evaluates its tile's list: the mean list length over the smooth image's pixels.
      Stats st;
      double evaluations = 0.0;
      for (int y = 0; y < sh; ++y)
        for (int x = 0; x < sw; ++x) {
          const int tx = std::min(int((x + 0.5) / sw * g.grid.tiles_x), g.grid.tiles_x - 1);
          const int ty = std::min(int((y + 0.5) / sh * g.grid.tiles_y), g.grid.tiles_y - 1);
          evaluations += g.count[size_t(ty * g.grid.tiles_x + tx)];
        }
      st.evaluations = evaluations / (double(sw) * sh);
      std::vector<double> got(rays.size(), 0.0);
      clouds::for_bands(int(rays.size()), threads, [&](int begin, int end) {
        for (int r = begin; r < end; ++r) {
          const glm::dvec4 c = clip_from_enu * glm::dvec4(glm::dvec3(rays[size_t(r)]), 0.0);
          const glm::dvec2 ndc = glm::dvec2(c) / c.w;
          const int tx = std::clamp(int((ndc.x * 0.5 + 0.5) * g.grid.tiles_x), 0, g.grid.tiles_x - 1);
          const int ty = std::clamp(int((ndc.y * 0.5 + 0.5) * g.grid.tiles_y), 0, g.grid.tiles_y - 1);
          const size_t t = size_t(ty * g.grid.tiles_x + tx);
          for (uint32_t k = g.offset[t]; k < g.offset[t] + g.count[t]; ++k) {
            const uint32_t i = g.lists[k];
            got[size_t(r)] += glow(i < frame.lights.size() ? frame.lights[i] : g.merged[i - frame.lights.size()],
                                   rays[size_t(r)]);
          }
        }
      });
      std::vector<double> errors;
      double sum_got = 0.0, sum_want = 0.0;
      for (size_t r = 0; r < rays.size(); ++r) {
        if (!(reference[r] > kThreshold)) continue;
        errors.push_back(std::abs(got[r] / reference[r] - 1.0));
        sum_got += got[r];
        sum_want += reference[r];
      }
      std::sort(errors.begin(), errors.end());
      st.pixels = errors.size();
      if (!errors.empty()) {
        st.median = errors[errors.size() / 2];
        st.p95 = errors[errors.size() * 95 / 100];
        st.total = sum_got / sum_want;
      }
      std::printf("  %-40s %10.2f %9.2f %8.4f %8.4f %8.4f %7zu\n", budget.name, st.evaluations, cpu[1], st.median,
                  st.p95, st.total, st.pixels);
      if (csv)
        std::fprintf(csv, "\"%s\",\"%s\",%d,%d,%d,%.3f,%.3f,%.5f,%.5f,%.5f,%zu\n", air.name, budget.name,
                     budget.b.exact, budget.b.merged, budget.b.opens, st.evaluations, cpu[1], st.median, st.p95,
                     st.total, st.pixels);
    }
  }
  if (csv) std::fclose(csv);
  return 0;
}
