// objects.h — what the opaque handles point to. A Context is one world (the
// air, the time, GL objects); a View is one channel's camera and target.
// Handles are registered so a stale or foreign pointer is refused, not used.
#pragma once

#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "abi/cloud_inputs.h"
#include "abi/fog_inputs.h"
#include "abi/light_inputs.h"
#include "abi/occluder_inputs.h"
#include "abi/state_hash.h"
#include "core/lights/light_clusters.h"
#include "abi/host_services.h"
#include "abi/table_builder.h"
#include "atmo/atmo.h"
#include "core/atmosphere/atmosphere_model.h"
#include "core/astro/ephemeris.h"
#include "core/geo/eye_frame.h"
#include "core/night_sky/night_plan.h"
#include "core/night_sky/point_sources.h"
#include "core/astro/sky_bodies.h"
#include "core/sky/sky_lighting.h"
#include "gl/cloud_renderer.h"
#include "gl/fog_renderer.h"
#include "gl/light_point_renderer.h"
#include "gl/night_renderer.h"
#include "gl/occlusion_renderer.h"
#include "gl/renderer.h"

struct AtmoView_T;

struct AtmoContext_T {
  // The default fog's tables (fog::fog_tables), made at creation on a worker; its destructor waits for
  // them (a context never outlives what it started).
  std::future<void> fog_prepared;
  atmo::abi::HostServices services;
  std::string asset_root;
  std::string application_name;
  uint64_t seed = 0;
  std::string last_error;

  atmo::core::AtmosphereSettings atmosphere;
  bool have_frame = false;
  double utc_posix_s = 0.0;
  double dut1_s = 0.0;
  uint64_t frame_number = 0;   // AtmoFrameState.host_frame_number
  // The frame clock deferred work is due by: host_frame_number once the host has numbered a frame (sent a
  // non-zero number), else the count of set_frame calls before this one (a host that never numbers its frames:
  // 0, 1, 2 ... as if it had).
  uint64_t frame_clock = 0, set_frame_calls = 0;
  uint64_t deferred_frames = ATMO_DEFERRED_FRAMES;  // AtmoFrameState.deferred_frames (0 there: the default)
  bool host_numbers_frames = false;
  uint64_t views_created = 0;  // each view's serial: its key for per-view GL state (the clouds' history)

  // The CPU lookup tables the passes upload and get_lighting reads, and what
  // (air, ground albedo, sphere radius) they were built for. The first use
  // builds them on the calling thread; later changes of the key are built by
  // table_worker while frames keep these, and the calling thread swaps the new
  // ones in (abi/scene_inputs.cpp): only the host's thread reads or writes
  // these members, so no lock.
  atmo::abi::TableKey tables_key;
  atmo::twin::Lut2D transmittance;        // to the top of the air
  atmo::twin::Lut2D multiple_scattering;  // Psi_ms, built from the transmittance
  uint64_t tables_version = 0;            // bumps when the CPU tables change (0: none yet)
  uint64_t uploaded_tables_version = 0;   // what the GL texture holds (0: nothing)
  atmo::abi::TableKey tables_wanted;      // the key asked for last (the current air at the last view's sphere)
  // The key the worker was asked for last, the host frame it was asked at and the frame the new tables take
  // effect (asked + ATMO_DEFERRED_FRAMES: every channel switches on the same frame, however fast it builds).
  atmo::abi::TableKey tables_requested;
  uint64_t tables_requested_frame = 0, tables_due_frame = 0;
  atmo::abi::TableWorker table_worker;  // joined by destroy_context (and its destructor)

  // The clouds (set_clouds) and their GL objects (built by the first cloud pass with clouds).
  atmo::abi::ContextClouds clouds;
  atmo::gl::CloudRenderer cloud_renderer;

  // Fog (set_fog) and the host's lights (set_lights, update_lights,
  // set_light_group_pose); their GL objects are built by the first pass or
  // get_fog_lighting that needs them.
  atmo::fog::FogMedium fog;
  atmo::lights::LightSet lights;
  atmo::gl::FogRenderer fog_renderer;
  atmo::gl::LightPointRenderer light_point_renderer;
  uint64_t fog_serial = 0;  // bumps on every change of the fog or the lights (the views' fog frames follow)
  bool warned_old_fog_lighting = false;  // a host's AtmoFogLighting from before the clusters was told once

  // The host's objects as occluders of the sky (set_occluders, set_occluder_poses) and their textures
  // (get_sky_occlusion).
  atmo::abi::ContextOccluders occluders;
  atmo::gl::OcclusionRenderer occlusion_renderer;

  atmo::abi::StateHashCache state_hash_cache;  // get_state_hash's content hashes

  atmo::gl::Renderer renderer;
  // The night sky's point pass: its programs are built by the first night
  // pass that has something to draw (a daytime host never pays for them).
  atmo::gl::NightRenderer night_renderer;
  bool gl_alive = false;
  // The star catalogue prepared for drawing (9931 stars, parsed from the
  // embedded copy of data/stars on the first night pass that draws points;
  // once). Null before; empty when parsing failed (star_field_error says
  // why, and the planets are still drawn).
  std::unique_ptr<atmo::core::night::StarField> star_field;
  std::string star_field_error;
  // Daylight, when only a planet could show (the plan's limit brighter than
  // Sirius): the last check of the planets against the sky in their own
  // directions, and its UTC. While it is under kDaylightPlanetCheckS old and
  // found none visible, the night pass does nothing at all (no astrometry).
  bool have_daylight_planet_check = false;
  bool daylight_planet_visible = false;
  double daylight_planet_check_utc_posix_s = 0.0;
  std::vector<AtmoView_T*> views;
};

struct AtmoView_T {
  AtmoContext_T* context = nullptr;
  uint32_t channel_id = 0;
  uint64_t serial = 0;  // unique in its context, never reused
  bool have_state = false;
  AtmoViewState state{};
  atmo::core::EyeFrame eye;
  uint64_t state_serial = 0;  // bumps on every set_view
  // The Sun and the Moon at this view's eye, reused while good to 1.5".
  atmo::core::SkyBodiesCache sky_bodies;

  // The astrometry of this view's eye at the frame's time (ERFA context:
  // Earth orientation, aberration, refraction), rebuilt when the time or the
  // eye changes: the sky pass (background) and the night pass share it.
  std::optional<atmo::core::astro::AstrometryFrame> astrometry;
  double astrometry_utc_posix_s = 0.0, astrometry_dut1_s = 0.0;
  glm::dvec3 astrometry_eye_ecef_m{0.0};
  // The night pass's sources of the last frame (the buffer is reused) and what it decided.
  std::vector<atmo::core::night::PointSource> night_points;
  atmo::core::night::NightPlan night_plan;

  // Sky light for get_lighting, recomputed when the sun moves more than
  // kSkyLightingSunStepRad, the eye's altitude changes by more than 1 % (+ 10 m)
  // or the tables change.
  bool have_sky_lighting = false;
  glm::dvec3 sky_lighting_sun_enu{0.0};
  double sky_lighting_altitude_m = 0.0;
  uint64_t sky_lighting_tables_version = 0;
  atmo::core::SkyLighting sky_lighting;

  // The lights of this view's frame in the fog (make_fog_frame: every light
  // against the eye, glow bounds, the diffusion sum), shared by
  // get_fog_lighting and the glow pass, and the serials it was made at.
  std::optional<atmo::fog::FogFrame> fog_frame;
  uint64_t fog_frame_context_serial = 0, fog_frame_view_serial = 0;
  std::optional<atmo::lights::LightTree> light_tree;  // over fog_frame's lights, made with it
  // The clusters of the lights for the host's surfaces (get_fog_lighting), made with the fog frame.
  std::optional<atmo::lights::LightClusters> light_clusters;
  uint64_t light_clusters_context_serial = 0, light_clusters_view_serial = 0;
  // The light points of this view's last pass (the buffer is reused) and what was culled.
  std::vector<atmo::lights::LightPoint> light_points;
  atmo::lights::LightPointStats light_point_stats;
  // The state_serial of this view's last ATMO_PASS_SKY_OCCLUSION_IMAGE pass (0: none) and its reduction:
  // get_sky_occlusion hands the image out while it is this set_view's.
  uint64_t occlusion_image_state_serial = 0;
  int occlusion_image_reduction = 0;
};

namespace atmo::abi {

// Handle registry (process-wide, locked).
void register_context(AtmoContext_T* c);
void unregister_context(AtmoContext_T* c);
bool is_live_context(const AtmoContext_T* c);
void register_view(AtmoView_T* v);
void unregister_view(AtmoView_T* v);
bool is_live_view(const AtmoView_T* v);

}  // namespace atmo::abi
