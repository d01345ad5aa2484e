// atmo_clouds_scale_bench — the clouds pass at simulator scale (issue 19):
// every layer type, from below, inside and above, cumulus at 1, 4 and 8
// oktas over growing areas, the Sun high and low, at 1280x720 and
// 1920x1080 on this machine's GL. Each case prints the clouds pass's wall
// time to glFinish (median of the timed frames), the reference pair drawn in
// the same frames (the LUT sky pass + the aerial-perspective pass, timed
// alike) and their ratio; set_clouds' wall time, the first frame's clouds
// pass (it builds the clipmap) and the whole first frame (sky, aerial
// perspective, clouds) against a steady one (frame1_x: the first sky pass
// relights the clouds for their shadow on the air), and the memory (the
// field's density, the clipmap on the CPU, its GL textures). The eye moves
// 5 m a frame.
//
//   atmo_clouds_scale_bench [--mode layer|auto|impostors|direct] [--frames N]
//                           [--quality default|low|medium|high|full] [--setup stream|wait]
//                           [--sizes 1280x720,1920x1080] [--only SUBSTRING] [--csv FILE]
// --quality: the view's AtmoViewState.cloud_quality (the layer march's cost knob).
// --setup: AtmoCloudsState.setup (default stream: the first frame draws the
// draft). ready_ms: set_clouds until the full lighting and clipmap are shown
// (frames with waits between them); swap_x: the slowest of those frames
// against a steady one.
#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "cloud_scene.h"
#include "scale_options.h"

namespace {

using cloud_bench::Camera;
using cloud_bench::Host;
using cloud_bench::median;

struct Case {
  std::string name;
  uint32_t type;
  int oktas;
  double base_m, top_m, area_m;
  Camera cam;
};

std::vector<Case> cases() {
  std::vector<Case> out;
  for (int oktas : {1, 4, 8})
    for (double km : {20.0, 100.0, 400.0})
      out.push_back({"cumulus " + std::to_string(oktas) + " oktas, " + std::to_string(int(km)) + " km, eye 3 km",
                     ATMO_CLOUD_CUMULUS, oktas, 1000.0, 2800.0, km * 1000.0, {0.0, 0.0, 3000.0, -5.0}});
  const struct {
    const char* name;
    uint32_t type;
    int oktas;
    double base, top;
  } decks[] = {{"stratus 6 oktas", ATMO_CLOUD_STRATUS, 6, 800.0, 1300.0},
               {"overcast", ATMO_CLOUD_OVERCAST, 8, 600.0, 1100.0}};
  for (const auto& d : decks) {
    out.push_back({std::string(d.name) + ", 20 km, from below", d.type, d.oktas, d.base, d.top, 20000.0,
                   {0.0, 0.0, 300.0, 20.0}});
    out.push_back({std::string(d.name) + ", 20 km, inside", d.type, d.oktas, d.base, d.top, 20000.0,
                   {0.0, 0.0, 0.5 * (d.base + d.top), 0.0}});
    out.push_back({std::string(d.name) + ", 20 km, from above", d.type, d.oktas, d.base, d.top, 20000.0,
                   {0.0, 0.0, d.top + 1500.0, -20.0}});
    out.push_back({std::string(d.name) + ", 400 km, from below", d.type, d.oktas, d.base, d.top, 400000.0,
                   {0.0, 0.0, 300.0, 20.0}});
  }
  out.push_back({"cirrus 4 oktas, 8-9 km, 20 km, overhead", ATMO_CLOUD_CIRRUS, 4, 8000.0, 9000.0, 20000.0,
                 {0.0, 0.0, 300.0, 30.0}});
  out.push_back({"cirrus 4 oktas, 8-9 km, 400 km, overhead", ATMO_CLOUD_CIRRUS, 4, 8000.0, 9000.0, 400000.0,
                 {0.0, 0.0, 300.0, 30.0}});
  return out;
}

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The UTC (2024-07-10 morning) at which the Sun stands `elevation_deg` up at the camera.
double utc_for_sun(Host& host, const Camera& cam, double elevation_deg) {
  double lo = 1720576800.0 - 5 * 3600.0, hi = 1720576800.0 + 6 * 3600.0;  // 2024-07-10 02:00 .. 13:00 UTC
  host.set_view(cam);
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    host.set_utc(mid);
    (host.sun_elevation_deg() < elevation_deg ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

int main(int argc, char** argv) {
  uint32_t mode = ATMO_CLOUD_DRAW_LAYER;
  uint32_t quality = ATMO_CLOUD_QUALITY_DEFAULT;
  uint32_t setup = ATMO_CLOUD_SETUP_STREAM;
  std::vector<std::pair<int, int>> sizes = {{1280, 720}, {1920, 1080}};
  bench_scale::CommonOptions common;
  for (int i = 1; i < argc; ++i) {
    if (common.take(argc, argv, &i)) continue;
    const std::string a = argv[i];
    const char* v = i + 1 < argc ? argv[i + 1] : "";
    if (a == "--setup") {
      if (std::strcmp(v, "stream") != 0 && std::strcmp(v, "wait") != 0) {
        std::fprintf(stderr, "atmo_clouds_scale_bench: --setup %s: expected stream or wait\n", v);
        return 2;
      }
      setup = std::strcmp(v, "wait") == 0 ? ATMO_CLOUD_SETUP_WAIT : ATMO_CLOUD_SETUP_STREAM;
      ++i;
    } else if (a == "--mode") {
      const std::string m = v;
      mode = m == "direct"      ? ATMO_CLOUD_DRAW_DIRECT
             : m == "impostors" ? ATMO_CLOUD_DRAW_IMPOSTORS
             : m == "auto"      ? ATMO_CLOUD_DRAW_AUTO
                                : ATMO_CLOUD_DRAW_LAYER;
      ++i;
    } else if (a == "--quality") {
      const std::string q = v;
      const char* names[] = {"default", "low", "medium", "high", "full"};
      quality = ATMO_CLOUD_QUALITY_COUNT;
      for (uint32_t k = 0; k < ATMO_CLOUD_QUALITY_COUNT; ++k)
        if (q == names[k]) quality = k;
      if (quality == ATMO_CLOUD_QUALITY_COUNT) {
        std::fprintf(stderr, "atmo_clouds_scale_bench: --quality %s: expected default, low, medium, high or full\n", v);
        return 2;
      }
      ++i;
    } else if (a == "--sizes") {
      sizes.clear();
      for (const char* p = v; *p;) {
        int w = 0, h = 0, n = 0;
        if (std::sscanf(p, "%dx%d%n", &w, &h, &n) != 2) break;
        sizes.push_back({w, h});
        p += n;
        if (*p == ',') ++p;
      }
      ++i;
    } else {
      std::fprintf(stderr, "atmo_clouds_scale_bench: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  FILE* csv = common.csv_path.empty() ? nullptr : std::fopen(common.csv_path.c_str(), "w");
  if (csv)
    std::fprintf(csv, "size,case,sun_deg,clouds,set_clouds_ms,first_frame_ms,clouds_ms,pair_ms,ratio,field_MiB,"
                      "clipmap_MiB,gl_MiB,clipmap_ms,first_pair_ms,first_frame_x,ready_ms,swap_frame_x\n");
  for (const auto& [w, h] : sizes) {
    Host host(w, h);
    host.set_cloud_quality(quality);
    std::printf("== %dx%d, %s, mode %u, cloud quality %u, %d timed frames a case ==\n", w, h,
                host.gl().renderer().c_str(), mode, quality, common.frames);
    std::printf("%-48s %5s %7s %9s %9s %9s %8s %6s %7s %7s %7s %8s %8s %6s\n", "case", "sun", "clouds", "set_ms",
                "first_ms", "clouds_ms", "pair_ms", "ratio", "fieldMB", "mapMB", "glMB", "frame1_x", "ready_ms",
                "swap_x");
    for (const Case& c : cases()) {
      if (common.skips(c.name)) continue;
      for (double sun : {60.0, 5.0}) {
        const double utc = utc_for_sun(host, c.cam, sun);
        host.set_utc(utc);
        // A frame without clouds at this UTC, so the first frame below pays
        // for the clouds' set-up only, not for the sky tables of a new Sun.
        host.set_clouds(cloud_bench::clouds_state(nullptr, mode, setup));
        host.set_view(c.cam);
        host.target().bind();
        host.pass_ms(ATMO_PASS_SKY);
        host.pass_ms(ATMO_PASS_AERIAL_PERSPECTIVE);
        host.next_frame();
        AtmoCloudLayer layer = atmo::make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
        layer.type = c.type;
        layer.coverage_oktas = c.oktas;
        layer.base_m = c.base_m;
        layer.top_m = c.top_m;
        layer.area_size_m = c.area_m;
        layer.seed = 3;
        const double t0 = now_ms();
        host.set_clouds(cloud_bench::clouds_state(&layer, mode, setup));
        const double set_ms = now_ms() - t0;
        Camera cam = c.cam;
        host.set_view(cam);
        host.target().bind();
        glClearColor(0, 0, 0, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        // The whole first frame: the sky pass relights the clouds for their shadow on the air.
        const double first_pair_ms = host.pass_ms(ATMO_PASS_SKY) + host.pass_ms(ATMO_PASS_AERIAL_PERSPECTIVE);
        const double first_ms = host.clouds_ms();
        // Until the worker's full lighting and clipmap are shown: frames with
        // waits between them (the slowest frame is the one that swaps them in).
        atmo::abi::ContextClouds& settling = host.context()->clouds;
        double swap_frame_ms = 0.0;
        for (int f = 0; f < 20 && !settling.settled(); ++f) {
          atmo::abi::wait_for_cloud_jobs(&settling);
          host.next_frame();
          host.set_view(cam);
          host.target().bind();
          const double frame_ms = host.pass_ms(ATMO_PASS_SKY) + host.pass_ms(ATMO_PASS_AERIAL_PERSPECTIVE) +
                                  host.clouds_ms();
          swap_frame_ms = std::max(swap_frame_ms, frame_ms);
        }
        const double ready_ms = now_ms() - t0;
        std::vector<double> clouds, pair;
        for (int f = 0; f < common.frames; ++f) {
          cam.east_m += 5.0;
          host.next_frame();
          host.set_view(cam);
          host.target().bind();
          glClearColor(0, 0, 0, 1);
          glClear(GL_COLOR_BUFFER_BIT);
          const double sky = host.pass_ms(ATMO_PASS_SKY) + host.pass_ms(ATMO_PASS_AERIAL_PERSPECTIVE);
          pair.push_back(sky);
          clouds.push_back(host.clouds_ms());
        }
        const atmo::abi::ContextClouds& cc = host.context()->clouds;
        const double cm = median(clouds), pm = median(pair);
        const double first_x = (first_pair_ms + first_ms) / (pm + cm);  // the first frame against a steady one
        const double swap_x = swap_frame_ms / (pm + cm);
        const double field_mib = cc.field.memory_bytes() / 1048576.0;
        const double map_mib = cc.clipmap.memory_bytes() / 1048576.0;
        const double gl_mib = host.context()->cloud_renderer.layer_bytes() / 1048576.0;
        std::printf("%-48s %5.0f %7zu %9.0f %9.0f %9.1f %8.1f %6.2f %7.1f %7.1f %7.1f %8.1f %8.0f %6.1f\n",
                    c.name.c_str(), sun, cc.field.instances.size(), set_ms, first_ms, cm, pm, cm / pm, field_mib,
                    map_mib, gl_mib, first_x, ready_ms, swap_x);
        std::fflush(stdout);
        std::string csv_name = c.name;  // the CSV is not quoted: ';' for the name's commas
        std::replace(csv_name.begin(), csv_name.end(), ',', ';');
        if (csv)
          std::fprintf(csv, "%dx%d,%s,%.0f,%zu,%.1f,%.1f,%.2f,%.2f,%.3f,%.2f,%.2f,%.2f,%.1f,%.1f,%.2f,%.0f,%.2f\n", w, h,
                       csv_name.c_str(), sun, cc.field.instances.size(), set_ms, first_ms, cm, pm, cm / pm, field_mib,
                       map_mib, gl_mib, cc.clipmap_ms, first_pair_ms, first_x, ready_ms, swap_x);
      }
    }
  }
  if (csv) std::fclose(csv);
  return 0;
}
