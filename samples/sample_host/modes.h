// modes.h — the sample host's two ways to run: a GLFW window with a Dear ImGui
// panel, or headless (EGL) frames written as PNGs. Both call
// SampleRenderer::render_frame for every frame.
#pragma once

#include <cstdint>
#include <string>

#include "scene_settings.h"

#ifndef ATMO_SAMPLE_OBJECTS_DIR
#define ATMO_SAMPLE_OBJECTS_DIR "data/objects"
#endif

namespace atmo::sample {

struct Options {
  std::string plugin_path;
  int width = 1280;
  int height = 720;
  int frames = 0;        // > 0: headless
  std::string out_dir;   // headless output folder
  int exit_after = 0;    // window: close after this many frames (0: never), for smoke tests
  std::string screenshot;  // window: PNG of the last frame, UI included, written on close
  bool verbose = false;  // plugin debug/info log messages too
  std::string objects_dir = ATMO_SAMPLE_OBJECTS_DIR;  // the apron's meshes and sphere sets (data/objects)
};

// Process exit codes: 0 success, 1 a plugin error, 2 a host/GL setup failure.
int run_window(const Options& options, SceneSettings settings);
int run_headless(const Options& options, SceneSettings settings);

}  // namespace atmo::sample
