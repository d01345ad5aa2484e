// atmo_lights_scale_bench — the host's lights at simulator scale (issue 20):
// an airport (two runways, approach, touchdown-zone, centreline, edge and
// taxiway lights) with a town behind it, 15 000 lights, seen on a 3-degree
// approach at night in RVR 550 m fog, in 5 km haze and in clear air; then the
// town alone from 100 to 65 536 lights over one extent (its density grows). Each case prints, per pass, the wall
// time to glFinish (median of the timed frames) of the plugin's light passes
// (LIGHT_GLOWS: the fog and the glows; LIGHT_POINTS), of what the lights add
// to the host's terrain (get_fog_lighting, and the terrain lit through
// atmo_fog_lights.glsl less the same terrain unlit), and of the reference pair drawn in the
// same frames (the LUT sky pass + the aerial-perspective pass), and their
// ratios to the pair; and the CPU time of set_lights (all lights), of
// update_lights (1 000 lights moved a frame) and of set_fog.
//
//   atmo_lights_scale_bench [--size 1280x720] [--frames N] [--only SUBSTRING] [--csv FILE]
//                           [--counts 100,300,...] [--verbose]
#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "atmo/atmo.hpp"
#include "atmo_host_scene/camera.h"
#include "atmo_host_scene/depth_setup.h"
#include "atmo_host_scene/light_layouts.h"
#include "atmo_host_scene/terrain.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/offscreen_target.h"
#include "scale_options.h"

namespace {

namespace hs = atmo::host_scene;

const hs::Geodetic kOrigin{47.26, 11.35, 580.0};  // the airfield datum
constexpr double kNightUtc = 1.72e9 + 12 * 3600.0;  // 2024-07-03 21:46 UTC: the Sun well below the horizon

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Wall time of f() to glFinish, ms.
double timed(const std::function<void()>& f) {
  glFinish();
  const double t0 = now_ms();
  f();
  glFinish();
  return now_ms() - t0;
}

struct Air {
  std::string name;
  double visibility_m;      // the air's (set_atmosphere)
  double fog_visibility_m;  // 0: no fog
  double fog_top_m;         // above the datum
};

struct Case {
  std::string name;
  Air air;
  bool airport;
  uint32_t town_lights;
};

// The airport: runway 36 (3 km) at the datum and a crossing one; the town 6 km north, beyond it.
hs::AirportSpec airport() {
  hs::AirportSpec a;
  hs::RunwaySpec second;
  second.centre_enu_m = {900.0, 1200.0};
  second.heading_deg = 60.0;
  second.length_m = 2500.0;
  a.runways = {hs::RunwaySpec{{0.0, 0.0}, 0.0, 3000.0, 45.0}, second};
  a.taxiway_length_m = 9000.0;
  return a;
}

// The town 6 km north: `lights` at the layout's density (1 300 a square kilometre) with the airport; alone,
// `lights` over the extent the 15 000-light scene's town has (its 13 170 lights at that density, 10.1 km^2), so
// the sweep adds lights, not lit ground.
constexpr double kTownDensity = 1300.0;
constexpr double kSweepTownKm2 = 13170.0 / kTownDensity;
hs::TownSpec town(uint32_t lights, bool with_airport) {
  hs::TownSpec t;
  t.centre_enu_m = {0.0, 6000.0};
  t.lights = lights;
  t.lights_per_km2 = with_airport ? kTownDensity : lights / kSweepTownKm2;
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  int width = 1280, height = 720;
  bench_scale::CommonOptions common;
  bool verbose = false;
  std::vector<uint32_t> counts = {100, 300, 1000, 3000, 10000, 30000, 65536};
  for (int i = 1; i < argc; ++i) {
    if (common.take(argc, argv, &i)) continue;
    const std::string a = argv[i];
    const char* v = i + 1 < argc ? argv[i + 1] : "";
    if (a == "--size" && std::sscanf(v, "%dx%d", &width, &height) == 2) {
      ++i;
    } else if (a == "--verbose") {
      verbose = true;
    } else if (a == "--counts") {
      counts.clear();
      for (const char* p = v; *p;) {
        char* end = nullptr;
        const unsigned long n = std::strtoul(p, &end, 10);
        if (end == p) break;
        counts.push_back(static_cast<uint32_t>(n));
        p = *end == ',' ? end + 1 : end;
      }
      ++i;
    } else {
      std::fprintf(stderr, "atmo_lights_scale_bench: unknown option %s\n", a.c_str());
      return 2;
    }
  }

  std::string error;
  auto gl = atmo::support::HeadlessGl::create(atmo::support::HeadlessGl::Profile::Core, &error);
  if (!gl) {
    std::fprintf(stderr, "no headless GL context: %s\n", error.c_str());
    return 1;
  }
  auto target = atmo::support::OffscreenTarget::create(width, height, &error);
  if (!target) {
    std::fprintf(stderr, "offscreen target: %s\n", error.c_str());
    return 1;
  }
  atmo::Plugin plugin(ATMO_PLUGIN_PATH, "atmo lights bench");
  AtmoHostServices services = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  services.gl_get_proc_address = &atmo::support::HeadlessGl::get_proc_address;
  // --verbose: the passes' debug lines (what each culled, listed and drew).
  services.log = [](void* user, int32_t severity, const char* message) {
    if (severity >= ATMO_LOG_WARNING || *static_cast<bool*>(user)) std::fprintf(stderr, "[atmo] %s\n", message);
  };
  services.user = &verbose;

  // The host's terrain: hills with the runway at the datum, flat under the approach; its own light points off.
  hs::TerrainOptions terrain_options;
  terrain_options.runway_heading_deg = 0.0;
  terrain_options.draw_light_points = false;
  hs::Terrain terrain(terrain_options);
  if (!terrain.gl_init(&error)) {
    std::fprintf(stderr, "terrain: %s\n", error.c_str());
    return 1;
  }

  const Air fog{"RVR 550 m fog", 8000.0, 550.0, 300.0}, haze{"5 km haze", 5000.0, 5000.0, 1500.0},
      clear{"clear night", 40000.0, 0.0, 0.0};
  std::vector<Case> cases;
  const uint32_t airport_count = static_cast<uint32_t>(hs::airport_lights(airport()).size());
  for (const Air& a : {fog, haze, clear})
    cases.push_back({"airport + town, 15000 lights, " + a.name, a, true, 15000 - airport_count});
  for (const Air& a : {fog, clear})
    for (uint32_t n : counts) cases.push_back({"town " + std::to_string(n) + " lights, " + a.name, a, false, n});

  std::FILE* csv = common.csv_path.empty() ? nullptr : std::fopen(common.csv_path.c_str(), "w");
  if (csv)
    std::fprintf(csv, "case,air,lights,pair_ms,glows_ms,points_ms,light_passes_ms,light_x,host_ms,host_x,"
                      "get_fog_lighting_ms,set_lights_ms,update_1000_ms,set_fog_ms\n");
  std::printf("== %dx%d, %s, %d timed frames a case (wall time to glFinish, median) ==\n", width, height,
              gl->renderer().c_str(), common.frames);
  std::printf("%-48s %7s %8s %8s %8s %7s %8s %7s %8s %8s %8s %8s\n", "case", "lights", "pair_ms", "glows_ms",
              "points_ms", "light_x", "host_ms", "host_x", "lit_cpu", "set_ms", "upd_ms", "fog_ms");
  for (const Case& c : cases) {
    if (common.skips(c.name)) continue;
    atmo::Context context(plugin, &services);
    context.gl_init();
    atmo::View view(context, 0);
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = kNightUtc;
    context.set_frame(frame);
    auto air = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
    air.visibility_m = c.air.visibility_m;
    context.set_atmosphere(air);
    double set_fog_ms = 0.0;
    if (c.air.fog_visibility_m > 0.0) {
      auto fog_state = atmo::make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
      fog_state.visibility_m = c.air.fog_visibility_m;
      fog_state.top_height_m = kOrigin.height_m + c.air.fog_top_m;
      const double t0 = now_ms();
      context.set_fog(fog_state);
      set_fog_ms = now_ms() - t0;
    }
    // The lights: the airport in group 0, the town in group 1, its cars' lights (the first 1 000 after its
    // street lights) moved each frame through update_lights.
    std::vector<AtmoLightPoint> airport_lights = c.airport ? hs::airport_lights(airport()) : std::vector<AtmoLightPoint>{};
    std::vector<AtmoLightPoint> town_lights = hs::town_lights(town(c.town_lights, c.airport));
    const double t0 = now_ms();
    if (!airport_lights.empty())
      context.set_lights(atmo::lights_state(0, airport_lights, kOrigin.latitude_deg, kOrigin.longitude_deg,
                                            kOrigin.height_m));
    context.set_lights(atmo::lights_state(1, town_lights, kOrigin.latitude_deg, kOrigin.longitude_deg,
                                          kOrigin.height_m));
    const double set_lights_ms = now_ms() - t0;
    const uint32_t moved_first = static_cast<uint32_t>(town_lights.size() / 3);
    const uint32_t moved = std::min<uint32_t>(1000, static_cast<uint32_t>(town_lights.size()) - moved_first);

    // On a 3-degree approach at 60 m (CAT I's decision height), 1.15 km before runway 36's threshold, looking
    // along it at the town.
    hs::ViewSetup setup;
    setup.world_origin = kOrigin;
    setup.pose.position_enu_m = {0.0, -2650.0, 60.0};
    setup.pose.heading_deg = 0.0;
    setup.pose.pitch_deg = -3.0;
    setup.vfov_rad = glm::radians(40.0);
    setup.near_m = 1.0;
    setup.far_m = 100000.0;
    setup.depth_convention = hs::DepthConvention::Reversed;
    setup.viewport = {0, 0, width, height};
    setup.depth_texture = target->depth_texture();
    setup.exposure_scale = hs::exposure_scale_from_ev100(2.0);
    const hs::SceneLighting lighting;

    std::vector<double> pair, glows, points, host, cpu, update;
    for (int f = -1; f < common.frames; ++f) {  // frame -1 warms up (programs, tables)
      setup.pose.position_enu_m.y += 5.0;
      view.set(hs::make_view_state(setup));
      // 1 000 cars' lights move 1 m along x.
      for (uint32_t k = moved_first; k < moved_first + moved; ++k) town_lights[k].position_m[0] += 1.0;
      auto u = atmo::make<AtmoLightsUpdate>(ATMO_TYPE_LIGHTS_UPDATE);
      u.group = 1;
      u.first = moved_first;
      u.lights = town_lights.data() + moved_first;
      u.light_count = moved;
      u.light_size = sizeof(AtmoLightPoint);
      const double u0 = now_ms();
      if (moved) context.update_lights(u);
      const double update_ms = now_ms() - u0;
      target->bind();
      glClearColor(0, 0, 0, 1);
      double lighting_ms = 0.0, lit_ms = 0.0, plain_ms = 0.0;
      {
        hs::DepthSetup depth(setup.depth_convention);
        glClearDepth(hs::clear_depth_value(setup.depth_convention));
        // The terrain without the lights (the host's own cost), then lit through the include.
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        plain_ms = timed([&] { terrain.draw(setup, lighting, nullptr); });
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        AtmoFogLighting fl{};
        lighting_ms = timed([&] { fl = view.fog_lighting(); });
        lit_ms = timed([&] { terrain.draw(setup, lighting, &fl); });
      }
      const double host_ms = lighting_ms + lit_ms - plain_ms;  // what the lights add to the host's pass
      const double pair_ms = timed([&] {
        view.render(ATMO_PASS_SKY);
        view.render(ATMO_PASS_AERIAL_PERSPECTIVE);
      });
      const double glows_ms = timed([&] { view.render(ATMO_PASS_LIGHT_GLOWS); });
      const double points_ms = timed([&] { view.render(ATMO_PASS_LIGHT_POINTS); });
      if (f < 0) continue;
      pair.push_back(pair_ms);
      glows.push_back(glows_ms);
      points.push_back(points_ms);
      host.push_back(host_ms);
      cpu.push_back(lighting_ms);
      update.push_back(update_ms);
    }
    const double p = median(pair), g = median(glows), pt = median(points), h = median(host);
    const uint32_t total = static_cast<uint32_t>(airport_lights.size() + town_lights.size());
    std::printf("%-48s %7u %8.1f %8.1f %8.1f %7.2f %8.1f %7.2f %8.1f %8.2f %8.3f %8.1f\n", c.name.c_str(), total, p,
                g, pt, (g + pt) / p, h, h / p, median(cpu), set_lights_ms, median(update), set_fog_ms);
    if (csv)
      std::fprintf(csv, "\"%s\",%s,%u,%.2f,%.2f,%.2f,%.2f,%.3f,%.2f,%.3f,%.2f,%.3f,%.4f,%.2f\n", c.name.c_str(),
                   c.air.name.c_str(), total, p, g, pt, g + pt, (g + pt) / p, h, h / p, median(cpu), set_lights_ms,
                   median(update), set_fog_ms);
    std::fflush(stdout);
  }
  if (csv) std::fclose(csv);
  terrain.gl_shutdown();
  return 0;
}
