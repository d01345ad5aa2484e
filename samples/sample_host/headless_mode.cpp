// Headless mode: an EGL context and an offscreen target instead of a window;
// the camera flies the fixed approach path; frames go to DIR/frame_NNN.png.
// Each frame prints its sections' GPU times (timer queries) and wall times to
// glFinish, the lights sent and the plugin's counts of its light work.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "atmo_support/headless_gl.h"
#include "atmo_support/image.h"
#include "atmo_support/offscreen_target.h"
#include "modes.h"
#include "sample_renderer.h"

namespace atmo::sample {

namespace {

void print_timings(const char* label, const double* ms, int count) {
  std::printf("%s", label);
  double total = 0.0;
  for (int s = 0; s < count; ++s) {
    if (std::isnan(ms[s])) {
      std::printf("  %s -", section_name(s));
    } else {
      std::printf("  %s %.3f", section_name(s), ms[s]);
      total += ms[s];
    }
  }
  std::printf("  | total %.3f ms\n", total);
}

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void print_air_and_lights(const SceneSettings& s, const FrameReport& first) {
  std::printf("lights: %s, %u sent (group 0: %u, group 1: %u; set_lights %.2f ms)", lights_choice_name(s.lights),
              first.lights_sent, first.group_lights[0], first.group_lights[1], first.set_lights_ms);
  if (s.fog_visibility_m > 0.0) {
    std::printf("; fog: RVR %.0f m, top %.0f m above the airfield", s.fog_visibility_m, s.fog_top_m);
  } else {
    std::printf("; no fog");
  }
  std::printf("; visibility %.0f m\n", s.visibility_m);
}

}  // namespace

int run_headless(const Options& options, SceneSettings settings) {
  namespace support = atmo::support;
  std::string error;
  const std::unique_ptr<support::HeadlessGl> gl = support::HeadlessGl::create(support::HeadlessGl::Profile::Core, &error);
  if (!gl) {
    std::fprintf(stderr, "atmo-sample-host: no headless GL context: %s\n", error.c_str());
    return 2;
  }
  std::printf("GL %s, %s\n", gl->version().c_str(), gl->renderer().c_str());
  fall_back_depth_convention(&settings);

  std::unique_ptr<SampleRenderer> renderer;
  try {
    renderer = std::make_unique<SampleRenderer>(options.plugin_path, &support::HeadlessGl::get_proc_address,
                                                options.verbose);
  } catch (const atmo::Error& e) {
    std::fprintf(stderr, "atmo-sample-host: %s\n", e.what());
    return 1;
  }
  std::printf("plugin %s %u.%u.%u (interface %u) from %s\n", renderer->api().plugin_name,
              renderer->api().plugin_version >> 16, (renderer->api().plugin_version >> 8) & 0xff,
              renderer->api().plugin_version & 0xff, renderer->api().interface_version, options.plugin_path.c_str());

  int status = 0;
  if (!renderer->gl_init(settings.seed, &error)) {
    std::fprintf(stderr, "atmo-sample-host: gl_init: %s\n", error.c_str());
    status = 1;
  }
  if (status == 0 && settings.objects != ObjectsChoice::None && !renderer->load_objects(options.objects_dir, &error)) {
    std::fprintf(stderr, "atmo-sample-host: --objects %s: %s\n", objects_choice_name(settings.objects), error.c_str());
    status = 2;
  }
  settings.clouds.setup = ATMO_CLOUD_SETUP_WAIT;  // screenshots: each frame a function of the settings
  if (status == 0 && !settings.clouds.layers.empty()) {
    std::string message;
    const bool ok = renderer->set_clouds(settings, &message);
    std::fprintf(ok ? stdout : stderr, "%s%s\n", ok ? "" : "atmo-sample-host: ", message.c_str());
    if (!ok) status = 1;
  }
  std::unique_ptr<support::OffscreenTarget> target;
  if (status == 0) {
    target = support::OffscreenTarget::create(options.width, options.height, &error);
    if (!target) {
      std::fprintf(stderr, "atmo-sample-host: offscreen target: %s\n", error.c_str());
      status = 2;
    }
  }
  std::error_code fs_error;
  if (status == 0) {
    std::filesystem::create_directories(options.out_dir, fs_error);
    if (fs_error) {
      std::fprintf(stderr, "atmo-sample-host: cannot create %s: %s\n", options.out_dir.c_str(),
                   fs_error.message().c_str());
      status = 2;
    }
  }

  double sum[kSectionCount] = {};
  int counted[kSectionCount] = {};
  std::vector<double> wall[kSectionCount];
  uint32_t lights_sent = 0;
  if (status == 0) {
    std::printf("%dx%d; per frame: GPU time (timer queries), then the wall time to glFinish of each section, ms\n",
                options.width, options.height);
  }
  for (int i = 0; status == 0 && i < options.frames; ++i) {
    // The approach; with objects the apron's view (the driving van moves from frame to frame).
    settings.pose = settings.objects == ObjectsChoice::Apron
                        ? apron_view()
                        : approach_path(options.frames > 1 ? static_cast<double>(i) / (options.frames - 1) : 0.0);
    // Each section finished before the next: llvmpipe defers rasterisation,
    // and its timer queries would credit the terrain's to the sky pass.
    const FrameReport report = renderer->render_frame(settings, static_cast<uint64_t>(i), target->fbo(),
                                                      options.width, options.height, true, true);
    if (i == 0) print_air_and_lights(settings, report);
    lights_sent = report.lights_sent;
    char label[32];
    std::snprintf(label, sizeof label, "frame %03d (ms):", i);
    print_timings(label, report.gpu_ms.data(), kSectionCount);
    print_timings("  to glFinish:  ", report.wall_ms.data(), kSectionCount);
    const auto wall_ms = [&](int section) { return report.wall_ms[static_cast<size_t>(section)]; };
    std::printf("  lights: %u sent, %u lighting the terrain (get_fog_lighting %.2f ms CPU); light glows %.2f ms, "
                "light points %.2f ms, lit terrain %.2f ms (to glFinish)\n",
                report.lights_sent, report.fog_lighting.light_count, report.fog_lighting_ms,
                wall_ms(kSectionLightGlows), wall_ms(kSectionLightPoints), wall_ms(kSectionTerrain));
    for (const std::string& line : report.light_debug)
      if (!line.empty()) std::printf("  plugin: %s\n", line.c_str());
    if (settings.objects != ObjectsChoice::None) {
      std::printf("  objects: %s, %zu drawn, %u occluders (shadows %s, bounce %s); objects %.2f ms",
                  objects_choice_name(settings.objects), apron_objects().size(), report.occluders,
                  settings.object_shadows ? "on" : "off", settings.object_bounce ? "on" : "off",
                  wall_ms(kSectionObjects));
      if (report.occluders > 0)
        std::printf(", sky occlusion pass %.2f ms (to glFinish); get_sky_occlusion %.2f ms CPU, longest tile list %u",
                    wall_ms(kSectionSkyOcclusion), report.sky_occlusion_cpu_ms, report.longest_tile_list);
      std::printf("\n");
    }
    for (int s = 0; s < kSectionCount; ++s) {
      if (!std::isnan(report.gpu_ms[static_cast<size_t>(s)])) {
        sum[s] += report.gpu_ms[static_cast<size_t>(s)];
        ++counted[s];
      }
      if (!std::isnan(wall_ms(s))) wall[s].push_back(wall_ms(s));
    }
    if (!report.errors.empty()) {
      for (const std::string& message : report.errors) std::fprintf(stderr, "atmo-sample-host: frame %d: %s\n", i, message.c_str());
      status = 1;
      break;
    }
    char name[32];
    std::snprintf(name, sizeof name, "frame_%03d.png", i);
    const std::string path = (std::filesystem::path(options.out_dir) / name).string();
    // The target holds display-referred values: render_frame tone-mapped them.
    if (!support::write_png(path, target->read_color(), &error)) {
      std::fprintf(stderr, "atmo-sample-host: %s\n", error.c_str());
      status = 2;
      break;
    }
  }
  if (status == 0 && options.frames > 0) {
    double mean[kSectionCount];
    for (int s = 0; s < kSectionCount; ++s) mean[s] = counted[s] ? sum[s] / counted[s] : std::nan("");
    print_timings("mean (ms):     ", mean, kSectionCount);
    double medians[kSectionCount];
    for (int s = 0; s < kSectionCount; ++s) medians[s] = median(wall[s]);
    print_timings("median to glFinish (ms):", medians, kSectionCount);
    std::printf("light passes, median to glFinish: light glows %.2f ms, light points %.2f ms, lit terrain %.2f ms; "
                "%u lights, %dx%d, %d frames\n",
                medians[kSectionLightGlows], medians[kSectionLightPoints], medians[kSectionTerrain], lights_sent,
                options.width, options.height, options.frames);
    std::printf("wrote %d frames to %s\n", options.frames, options.out_dir.c_str());
  }

  target.reset();
  renderer->gl_shutdown();
  renderer.reset();
  return status;
}

}  // namespace atmo::sample
