// scene_settings.h — what the sample host shows: place, time, air, fog,
// lights, camera, depth convention, exposure, the weather's cloud layers.
// Shared by the window and headless modes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "atmo/atmo.h"
#include "atmo_host_scene/camera.h"
#include "atmo_host_scene/light_layouts.h"

namespace atmo::sample {

// One cloud layer of the weather (an AtmoCloudLayer, in the host's units).
// Heights are above the airfield datum (SceneSettings::origin, the clouds'
// ENU origin); the area is a square of area_size_km centred at
// (area_east_km, area_north_km) from the airfield. A VDB layer puts the
// file's world origin at (area_east_km, area_north_km, base_m) and ignores
// the other procedural fields.
struct CloudLayerSettings {
  AtmoCloudLayerType type = ATMO_CLOUD_CUMULUS;
  int coverage_oktas = 4;
  double base_m = 1200.0;
  double top_m = 2500.0;
  double area_size_km = 20.0;
  double area_east_km = 0.0;
  double area_north_km = 0.0;
  uint64_t seed = 1;
  std::string vdb_path;  // ATMO_CLOUD_VDB_FILE: the file; relative paths resolve against the working directory
  std::string vdb_grid;  // its float grid; empty: "density"
};

// The weather: what set_clouds gets (SampleRenderer::set_clouds).
struct CloudSettings {
  std::vector<CloudLayerSettings> layers;
  AtmoCloudDrawMode draw_mode = ATMO_CLOUD_DRAW_AUTO;
  uint32_t march_resolution_divisor = 2;  // [1, 8]
  AtmoCloudQuality quality = ATMO_CLOUD_QUALITY_DEFAULT;  // the view's cloud_quality (the layer march)
  // The window streams (a draft first, no frame waits); headless screenshots
  // wait, so each saved frame is a function of the settings.
  AtmoCloudSetup setup = ATMO_CLOUD_SETUP_STREAM;
};

// "cumulus", "stratus", "overcast", "cirrus", "vdb"; nullptr outside the enum.
const char* cloud_type_name(AtmoCloudLayerType type);
// "impostors", "direct", "layer", else nullptr (a mode this host has no name for).
const char* cloud_draw_mode_name(uint32_t mode);
// "default", "low", "medium", "high", "full", else nullptr.
const char* cloud_quality_name(uint32_t quality);

// --cloud TYPE:OKTAS:BASE_M:TOP_M[:AREA_KM[:SEED]] (TYPE one of the procedural
// names above) and --vdb FILE[:GRID]. False with *error saying which part of
// the text is wrong and why; ranges are the plugin's to check (set_clouds).
bool parse_cloud_layer(const std::string& text, CloudLayerSettings* out, std::string* error);
bool parse_vdb_layer(const std::string& text, CloudLayerSettings* out, std::string* error);

// The lights the host sends (set_lights; ATMO_PASS_LIGHT_GLOWS draws their
// glows in fog, ATMO_PASS_LIGHT_POINTS their images in any air):
//   None: no lights for the plugin (the terrain still draws its own points);
//   Runway: the terrain's runway (approach, threshold, end and edge lights);
//   Airport: light_layouts.h's airport on the terrain's runway (two runways,
//     touchdown zone, centreline, approach and taxiway lights: 1 830);
//   AirportTown: and a town beyond it, 15 000 lights in all by default (the
//     scene of bench/lights_scale_bench.cpp, turned to this runway).
enum class LightsChoice { None, Runway, Airport, AirportTown };
constexpr LightsChoice kLightsChoices[] = {LightsChoice::None, LightsChoice::Runway, LightsChoice::Airport,
                                           LightsChoice::AirportTown};
// "none", "runway", "airport", "airport+town".
const char* lights_choice_name(LightsChoice choice);
// One of those names; false with *error listing them.
bool parse_lights_choice(const std::string& text, LightsChoice* out, std::string* error);

// The airport: its first runway is host_scene::Terrain's (default options:
// centred on the datum, heading 90, 3 000 x 45 m), the second crosses it
// south-east of the centre, with 9 km of taxiways (the bench's layout turned by
// 90 degrees). Positions on the datum plane; the renderer drapes them on the terrain.
host_scene::AirportSpec sample_airport();
// The town 6 km beyond the runway's centre (east, along the landing
// direction, as the bench's is north), `lights` at 1 300 a square kilometre.
host_scene::TownSpec sample_town(uint32_t lights);
// The town's default: the airport's lights plus it make 15 000 (the bench's scene).
uint32_t default_town_lights();
// The most town lights: all groups together hold ATMO_LIGHTS_MAX.
uint32_t max_town_lights();

// The fog's visibility as runway visual range (its MOR, the same extinction:
// ln 20 / RVR), m: from CAT IIIB's lowest RVR to a thin haze layer.
constexpr double kRvrMinM = 50.0;
constexpr double kRvrMaxM = 10000.0;
// --rvr: "none" or "0" (no fog), or metres in [kRvrMinM, kRvrMaxM]. False
// with *error saying why.
bool parse_rvr(const std::string& text, double* rvr_m, std::string* error);

// The host's objects (data/objects: meshes drawn by the host, sphere sets handed to set_occluders):
//   None: none (the default: the frames are as without the feature);
//   Apron: an aircraft, a parked van, a van driving along the apron and a hangar north of the runway.
enum class ObjectsChoice { None, Apron };
// "none", "apron".
const char* objects_choice_name(ObjectsChoice choice);
// One of those names; false with *error listing them.
bool parse_objects_choice(const std::string& text, ObjectsChoice* out, std::string* error);

// One object of the apron: its files in the objects folder (`stem`.obj, `stem`.spheres.json), where it stands
// (ENU at the airfield datum, on the datum plane: the renderer drapes it on the terrain), its heading (its x
// axis, forward, from north, clockwise) and its albedo.
struct ApronObject {
  const char* stem;
  glm::dvec2 position_enu_m;
  double heading_deg;
  glm::dvec3 albedo;
};
// The apron, north of the runway (host_scene::Terrain, default options: heading 90): the aircraft, nose to the
// runway, a van parked beside it, a van that drives (apron_vehicle_pose; index kApronMovingVehicle) and a hangar.
const std::vector<ApronObject>& apron_objects();
constexpr size_t kApronMovingVehicle = 2;
// The driving van's position and heading at a host frame number (deterministic: back and forth along the apron
// in front of the aircraft, one round trip in 240 frames).
ApronObject apron_vehicle_pose(uint64_t frame_number);
// A camera 3.5 m up at the apron's south-east corner, 50 m from the aircraft, looking north-west across the objects.
host_scene::CameraPose apron_view();

struct SceneSettings {
  host_scene::Geodetic origin{47.4647, 8.5492, 432.0};  // airfield datum (ENU origin)
  host_scene::CameraPose pose;
  double utc_posix_s = 1718982000.0;  // 2024-06-21T15:00:00Z
  double visibility_m = 40000.0;
  // Ground fog (set_fog): its visibility, the RVR (MOR in the fog), m (0: no
  // fog), and its top above the airfield datum, m.
  double fog_visibility_m = 0.0;
  double fog_top_m = 100.0;
  LightsChoice lights = LightsChoice::Runway;
  uint32_t town_lights = default_town_lights();  // LightsChoice::AirportTown's town, [0, max_town_lights()]
  host_scene::DepthConvention depth_convention = host_scene::DepthConvention::Reversed;
  double ev100 = 15.0;
  double vfov_deg = 60.0;
  uint64_t seed = 1;
  CloudSettings clouds;
  ObjectsChoice objects = ObjectsChoice::None;
  // The objects' sky occlusion (set_occluders, ATMO_PASS_SKY_OCCLUSION over the terrain, atmo_sky_occlusion.glsl on
  // the objects): off, the objects are lit by the open sky and cast no shadow.
  bool object_shadows = true;
  bool object_bounce = true;  // false: ATMO_OCCLUSION_NO_BOUNCE
  bool night_sky = true;  // false: ATMO_PASS_NIGHT_SKY is not drawn (a CIGI host's Star Field Enable off)
  // AtmoFrameState.deferred_frames: work off the host's thread (new air tables, the clouds' lighting) lands at the
  // frame it was asked at + this; 0: the plugin's ATMO_DEFERRED_FRAMES.
  uint32_t deferred_frames = 0;
};

// [gl-current] SceneSettings::depth_convention falls back to Standard where
// the context lacks glClipControl; returns true (with a note on stderr) if it changed.
bool fall_back_depth_convention(SceneSettings* settings);

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
