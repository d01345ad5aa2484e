// render_command.h — `atmo render SCENARIO --out DIR`: draws a scenario
// through the real plugin, via the ABI, exactly as a host would; writes EXR
// (linear, absolute cd/m^2) and PNG (tone-mapped), checks the scenario's
// expectations and prints per-pass GPU timings. The scenario's objects are
// handed to set_occluders and drawn by the host (tools/host_scene objects.h):
// ATMO_PASS_SKY_OCCLUSION (facing up) shades the terrain, then the objects are
// drawn through atmo_sky_occlusion.glsl (get_sky_occlusion).
#pragma once

#include <string>

#include "atmo_scenario/scenario.h"

namespace atmo::render {

struct Options {
  std::string scenario_path;
  std::string out_dir;
  std::string plugin_path;  // main.cpp: default_paths.h's, when --plugin is not given
  std::string depth_override;  // "", standard, reversed, logarithmic
  int repeat = 1;
  bool no_sky_occlusion = false;  // objects drawn lit by the open sky; no ATMO_PASS_SKY_OCCLUSION, no get_sky_occlusion
  std::string size;               // "WxH": an OpenSCENARIO file's camera (parsed by run_render)
  scenario::ImportOptions import; // --lat/--lon/--size: OpenSCENARIO files only
};

// 0: rendered and every expectation met; 1: an expectation failed; 2: error.
int run_render(const Options& options);

}  // namespace atmo::render
