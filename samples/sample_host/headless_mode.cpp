// Headless mode: an EGL context and an offscreen target instead of a window;
// the camera flies the fixed approach path; frames go to DIR/frame_NNN.png.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

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
  for (int i = 0; status == 0 && i < options.frames; ++i) {
    settings.pose = approach_path(options.frames > 1 ? static_cast<double>(i) / (options.frames - 1) : 0.0);
    const FrameReport report = renderer->render_frame(settings, static_cast<uint64_t>(i), target->fbo(),
                                                      options.width, options.height, true);
    char label[32];
    std::snprintf(label, sizeof label, "frame %03d (ms):", i);
    print_timings(label, report.gpu_ms.data(), kSectionCount);
    for (int s = 0; s < kSectionCount; ++s) {
      if (!std::isnan(report.gpu_ms[static_cast<size_t>(s)])) {
        sum[s] += report.gpu_ms[static_cast<size_t>(s)];
        ++counted[s];
      }
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
    std::printf("wrote %d frames to %s\n", options.frames, options.out_dir.c_str());
  }

  target.reset();
  renderer->gl_shutdown();
  renderer.reset();
  return status;
}

}  // namespace atmo::sample
