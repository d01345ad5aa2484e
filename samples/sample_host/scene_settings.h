// scene_settings.h — what the sample host shows: place, time, air, camera,
// depth convention, exposure. Shared by the window and headless modes.
#pragma once

#include <cstdint>
#include <string>

#include "atmo_host_scene/camera.h"

namespace atmo::sample {

struct SceneSettings {
  host_scene::Geodetic origin{47.4647, 8.5492, 432.0};  // airfield datum (ENU origin)
  host_scene::CameraPose pose;
  double utc_posix_s = 1718982000.0;  // 2024-06-21T15:00:00Z
  double visibility_m = 40000.0;
  // Ground fog lit by the runway's lights (set_fog, set_lights): MOR in the
  // fog, m (0: no fog), and its top above the airfield datum, m.
  double fog_visibility_m = 0.0;
  double fog_top_m = 100.0;
  host_scene::DepthConvention depth_convention = host_scene::DepthConvention::Reversed;
  double ev100 = 15.0;
  double vfov_deg = 60.0;
  uint64_t seed = 1;
};

// POSIX seconds ("1718982000") or an ISO 8601 UTC time stamp, read by the
// plugin's parser (core/astro/iso8601.h: "2024-06-21T15:00:00Z",
// "2024-06-21T17:00:00+02:00"). False with *error saying why if neither.
bool parse_utc(const std::string& text, double* posix_s, std::string* error);
std::string format_utc(double posix_s);  // "2024-06-21T15:00:00Z"

// The fixed headless flight path, t in [0, 1]: a straight-in approach on a
// 3 degree glide path to the runway of host_scene::Terrain (default options),
// from 6 km to 1 km before the threshold.
host_scene::CameraPose approach_path(double t);

}  // namespace atmo::sample
