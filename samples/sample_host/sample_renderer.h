// sample_renderer.h — the sample host's frame, the same in the window and
// headless modes: terrain (opaques) into a linear RGBA16F HDR target, then
// the Atmo passes, then a tone-map blit into the caller's framebuffer.
// The plugin is reached only through the host SDK (atmo.hpp).
#pragma once

#include <array>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "atmo/atmo.hpp"
#include "atmo_host_scene/objects.h"
#include "atmo_host_scene/terrain.h"
#include "gpu_timers.h"
#include "scene_settings.h"

namespace atmo::sample {

// Timed sections of a frame, in drawing order: the plugin's passes in the
// order atmo.h asks for (the objects' sky occlusion over the terrain before
// the objects that shade themselves with atmo_sky_occlusion.glsl, both before
// the aerial perspective; clouds after the night sky, so they hide the stars;
// the light points after the glows, as they carry their own fog).
enum Section {
  kSectionTerrain = 0,         // the host's terrain, lit by the plugin's lights when there are any
  kSectionSkyOcclusion,        // ATMO_PASS_SKY_OCCLUSION over the terrain (facing up), with objects and their shadows
  kSectionObjects,             // the host's objects, through atmo_sky_occlusion.glsl (get_sky_occlusion)
  kSectionSky,                 // ATMO_PASS_SKY
  kSectionAerialPerspective,   // ATMO_PASS_AERIAL_PERSPECTIVE
  kSectionNightSky,            // ATMO_PASS_NIGHT_SKY
  kSectionClouds,              // ATMO_PASS_CLOUDS
  kSectionLightGlows,          // ATMO_PASS_LIGHT_GLOWS
  kSectionLightPoints,         // ATMO_PASS_LIGHT_POINTS
  kSectionToneMap,
  kSectionCount
};
// Every section has its timer (GpuTimers keeps at most kMaxSections: the report reads them all).
static_assert(kSectionCount <= GpuTimers::kMaxSections, "a GPU timer for every section");
const char* section_name(int section);
// The plugin pass a section draws; -1 for the host's own sections.
int section_pass(int section);

// The plugin's debug counts of the light work (its ATMO_LOG_DEBUG lines, less
// their "frame N, channel C: " prefix), in the order it does them.
enum LightDebug { kDebugClusters = 0, kDebugGlows, kDebugPoints, kLightDebugCount };

struct FrameReport {
  std::array<double, kSectionCount> gpu_ms{};  // newest available timings; NaN: not run / none yet
  // Wall time of each section to glFinish, ms (render_frame's finish_sections; else NaN).
  std::array<double, kSectionCount> wall_ms{};
  bool timings_valid = false;
  std::array<AtmoResult, ATMO_PASS_COUNT> pass_results{};  // by AtmoPassKind
  AtmoLighting lighting{};          // from get_lighting
  AtmoFogLighting fog_lighting{};   // from get_fog_lighting (light_count 0: no lights)
  double fog_lighting_ms = 0.0;     // CPU time of get_fog_lighting (the lights' clusters for the terrain)
  // The lights the plugin holds, by group (0: the runway's or the airport's, 1: the town's).
  std::array<uint32_t, 2> group_lights{};
  uint32_t lights_sent = 0;         // all groups
  // CPU time of this frame's set_lights calls, ms; NaN: none this frame.
  double set_lights_ms = std::numeric_limits<double>::quiet_NaN();
  std::array<std::string, kLightDebugCount> light_debug;  // empty: the plugin did not say this frame
  host_scene::SceneLighting scene_lighting;
  // The objects: how many the plugin holds as occluders (0: none or their shadows off), the most a screen tile
  // lists (AtmoSkyOcclusion.longest_tile_list) and get_sky_occlusion's CPU time, ms (NaN: not called).
  uint32_t occluders = 0;
  uint32_t longest_tile_list = 0;
  double sky_occlusion_cpu_ms = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::string> errors;  // plugin errors and error-level log messages of this frame
  double cpu_ms = 0.0;              // CPU time of render_frame
};

class SampleRenderer {
 public:
  // Loads the plugin and creates its context (no GL yet). Throws atmo::Error.
  // loader: the host's GL proc-address function, given to the plugin (its user
  // argument is this renderer, as AtmoHostServices.user; the loader ignores it).
  SampleRenderer(const std::string& plugin_path, AtmoGlProcLoader loader, bool verbose);
  ~SampleRenderer();  // call gl_shutdown() first, with the context current
  SampleRenderer(const SampleRenderer&) = delete;
  SampleRenderer& operator=(const SampleRenderer&) = delete;

  // [gl-current] Plugin gl_init, view, terrain and tone-map objects.
  bool gl_init(uint64_t terrain_seed, std::string* error);
  void gl_shutdown();

  // [gl-current] Renders one frame into target_fbo (0: the window), width x
  // height pixels. wait_for_timings: read this frame's GPU timings (stalls).
  // finish_sections: glFinish after each section and report its wall time
  // (a deferring rasteriser such as llvmpipe credits a section's work to a
  // later one in the timer queries; stalls).
  FrameReport render_frame(const SceneSettings& settings, uint64_t frame_number, unsigned target_fbo, int width,
                           int height, bool wait_for_timings, bool finish_sections = false);

  // [gl-current] Reads the apron's objects from `dir` (aircraft, vehicle, building: .obj and .spheres.json) and
  // uploads their meshes; false with *error naming the file and what is wrong. Without it the objects are not
  // drawn (SceneSettings::objects is ignored).
  bool load_objects(const std::string& dir, std::string* error);
  bool objects_loaded() const { return objects_loaded_; }

  // Replaces the plugin's clouds with settings.clouds (set_clouds; no GL).
  // True on success; *message says what was set, or why the plugin refused
  // it (the clouds are then unchanged).
  bool set_clouds(const SceneSettings& settings, std::string* message);

  // The state the view's next pass draws from, hashed (get_state_hash); false before gl_init or from a plugin
  // without it. Throws atmo::Error if the plugin refuses.
  bool state_hash(AtmoStateHash* out) const { return view_ && view_->state_hash(out); }

  const AtmoPluginApi& api() const { return plugin_->api(); }
  const host_scene::Terrain& terrain() const { return *terrain_; }

 private:
  static void log_callback(void* user, int32_t severity, const char* message);
  bool ensure_targets(int width, int height, std::string* error);
  // set_lights for the settings' lights when they change; throws atmo::Error.
  void send_lights(const SceneSettings& settings, FrameReport* report);
  std::vector<AtmoLightPoint> draped(std::vector<AtmoLightPoint> lights) const;
  void release_targets();
  // set_occluders / set_occluder_poses for the settings' objects at this frame; throws atmo::Error.
  void send_occluders(const SceneSettings& settings, uint64_t frame_number, FrameReport* report);
  // The apron's objects at this frame (the driving van moved), draped on the terrain.
  std::vector<host_scene::ObjectInstance> apron_instances(uint64_t frame_number) const;
  std::vector<std::string> take_logged_errors();

  bool verbose_ = false;
  std::mutex log_mutex_;
  std::vector<std::string> logged_errors_;
  std::array<std::string, kLightDebugCount> light_debug_;  // this frame's, from the log callback

  std::unique_ptr<atmo::Plugin> plugin_;
  std::unique_ptr<atmo::Context> context_;
  std::unique_ptr<atmo::View> view_;
  std::unique_ptr<host_scene::Terrain> terrain_;
  double last_visibility_m_ = -1.0;
  double last_fog_visibility_m_ = -1.0, last_fog_top_m_ = -1.0;
  bool lights_sent_ = false;
  host_scene::Geodetic last_lights_origin_;
  LightsChoice last_lights_ = LightsChoice::None;
  uint32_t last_town_lights_ = 0;
  std::array<uint32_t, 2> group_lights_{};

  // The apron's objects: meshes (aircraft, vehicle, building), each object's mesh and spheres, the GL meshes.
  bool objects_loaded_ = false;
  std::vector<spheres::TriangleMesh> object_meshes_;
  std::vector<size_t> object_mesh_;                        // per apron object
  std::vector<std::vector<AtmoOccluderSphere>> object_spheres_;  // per apron object, object frame
  host_scene::ObjectMeshes object_gl_;
  bool occluders_sent_ = false;  // the plugin holds the apron's objects
  uint32_t occluder_flags_ = 0;
  host_scene::Geodetic occluders_origin_;  // their ENU frame's origin (the airfield datum) when sent

  // scene_fbo_: colour + depth, for opaques. atmo_fbo_: the same colour only,
  // for the plugin's passes, which sample the depth texture (no feedback loop).
  unsigned scene_fbo_ = 0, atmo_fbo_ = 0, hdr_color_ = 0, depth_ = 0;
  int target_width_ = 0, target_height_ = 0;
  unsigned tone_map_program_ = 0, empty_vao_ = 0;
  GpuTimers timers_;
};

}  // namespace atmo::sample
