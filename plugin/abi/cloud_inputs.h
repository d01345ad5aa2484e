// cloud_inputs.h — the clouds of a context (set_clouds): validation of the
// host's layers, building the cloud field (procedural generation, VDB files
// through the host's file service), and per frame what the cloud pass needs:
// the light, the eye in the clouds' frame, and the light grids, relit when the
// light has moved beyond the threshold. No GL.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "atmo/atmo.h"
#include "abi/cloud_relight.h"
#include "abi/validation.h"
#include "core/astro/sky_bodies.h"
#include "core/clouds/cloud_clipmap.h"
#include "core/clouds/cloud_field.h"
#include "core/clouds/cloud_lighting.h"
#include "core/clouds/cloud_optics.h"
#include "core/clouds/cloud_shadow.h"
#include "core/clouds/cloud_temporal.h"
#include "core/clouds/cloud_transmittance.h"
#include "core/clouds/impostor_policy.h"
#include "core/geo/geodesy.h"

struct AtmoContext_T;
struct AtmoView_T;

namespace atmo::core {
struct Scene;
}

namespace atmo::abi {

struct CloudSettings {
  int march_divisor = 2;               // the march renders at 1/n per axis
  float march_step_voxels = 1.0f;
  int octaves = 6;
  double light_threshold_rad = 0.5 * M_PI / 180.0;
  bool direct_only = false;            // ATMO_CLOUD_DRAW_DIRECT: no impostors (the reference)
  bool layer = false;                  // ATMO_CLOUD_DRAW_LAYER: the layer march over the clipmap
  bool wait = false;                   // ATMO_CLOUD_SETUP_WAIT: every worker result is waited for
  clouds::ClipmapSpec clipmap;
  // Benchmarks and tests only: the layer march's cost instead of the view's
  // cloud_quality (0, -1: the view's).
  int layer_divisor = 0, layer_max_steps = 0, layer_temporal = -1;
  clouds::ImpostorSettings impostors;
};

// The layer march's cost for a view of AtmoViewState.cloud_quality `quality`
// (validated), with the settings' overrides.
clouds::CloudViewCost layer_view_cost(const CloudSettings& settings, uint32_t quality);

// A context's clouds. Only the host's thread touches it (and the workers,
// which read the field; see CloudJobSlot).
//
// In the layer march with ATMO_CLOUD_SETUP_STREAM the first lighting is of
// `draft` (the field at half resolution: its ambient depths in set_clouds,
// its light, mips and clipmap on the first pass) while a worker lights the
// field in full; `full_lit` says which one the mips and clipmap are made of.
// Decks (stratus, overcast, cirrus: their generation is most of a large
// set_clouds) are first generated with half as many voxels across, and
// `field_job` generates them in full: the pass that finds it done swaps the
// field in and starts its full lighting (the draft is drawn until then).
struct ContextClouds {
  CloudRelightSlot relight;                  // first: see CloudJobSlot
  CloudClipmapSlot clipmap_job;
  CloudFieldSlot field_job;
  clouds::CloudField field;
  clouds::CloudRayIndex ray_index;          // the field's instances in buckets (get_lighting's Sun and Moon)
  std::vector<clouds::ContinuingSides> sides;  // per prototype (core/clouds/field_light.h continuing_sides)
  std::vector<int> sole_instance;           // per prototype (FieldNeighbours::sole, with ray_index)
  std::vector<clouds::LightDepths> depths;  // per prototype; tau_light for lit_direction_enu once full_lit
  glm::dvec3 lit_direction_enu{0.0};        // the clouds' frame; zero: never lit
  bool full_lit = false;                    // depths hold the field's whole lighting (else only the draft's)
  clouds::CloudField draft;                 // the streamed layer march's first frames (else empty)
  std::vector<clouds::LightDepths> draft_depths;
  clouds::CloudRayIndex draft_index;        // the draft's instances (the field's may be replaced under it)
  double field_ms = 0.0;                    // the field job's generation, once it landed
  uint64_t version = 0;                      // bumps when the field or its light grids change (GL re-uploads)
  uint64_t field_version = 0;                // bumps when the field changes (set_clouds): impostors start over
  core::Geodetic origin;                     // the clouds' ENU frame
  glm::dvec3 origin_ecef_m{0.0};
  glm::dmat3 ecef_from_enu{1.0};
  double mean_centre_height_m = 0.0;         // of the clouds' centres, above origin: where the light is taken
  double lowest_base_m = 0.0, highest_top_m = 0.0;  // of the grids' boxes, above origin (the sky passes' shadow)
  CloudSettings settings;
  uint64_t frame = 0;                        // the host frame of the call (set_frame): when jobs are due
  uint64_t deferred_frames = ATMO_DEFERRED_FRAMES;  // a job started at frame f is due at f + this
  // The Sun and Moon seen from the clouds' origin: the clouds are lit from
  // there, so the light (and what is relit when) is one per frame, whatever
  // the views and their order.
  core::SkyBodiesCache bodies;
  double relight_ms = 0.0;                   // the last relight, for logs and benchmarks
  // The layer march's clipmap (update_clipmap): the prototypes' mips per
  // light, the levels per (light, eye cell); instances found through ray_index.
  std::shared_ptr<const std::vector<clouds::PrototypeMips>> mips;  // shared with a clipmap job
  clouds::ClipmapGeometry clipmap_geometry;  // with the mips
  clouds::ClipmapSpec clipmap_spec;          // with the mips: the draft's is half as many voxels across
  uint64_t mips_version = 0;                 // `version` the mips and the geometry were made for (0: none)
  clouds::CloudClipmap clipmap;
  uint64_t clipmap_version = 0;              // bumps when the clipmap changes (GL re-uploads)
  uint64_t clipmap_built_for = 0;            // `version` of its last build
  double clipmap_ms = 0.0;                   // its last build, for logs and benchmarks
  // The shadow map (get_cloud_shadows): made once a host asks, then with every relight.
  bool shadow_wanted = false;
  clouds::CloudShadowMap shadow;
  uint64_t shadow_version = 0;               // bumps when the map changes (GL re-uploads)
  ContextClouds() = default;
  ContextClouds(ContextClouds&&) = default;
  ContextClouds& operator=(ContextClouds&&) = default;
  ~ContextClouds() {  // the jobs before the field dies
    relight.reset();
    clipmap_job.reset();
    field_job.reset();
  }
  bool empty() const { return field.instances.empty(); }
  bool relighting() const { return relight.job != nullptr; }
  // Lit in full from the full-resolution field, its clipmap (layer march) for that light, no job running.
  bool settled() const;
};

// Validates every layer of `state` and builds the field into *out, all or
// nothing: on any error (a bad field, or a file that fails to load) *out is
// unchanged. Every file is tried; those that fail are listed in *load_errors
// (with the files' warnings) and the verdict is ATMO_ERROR_IO with the first.
Verdict build_clouds(const AtmoCloudsState& state, const AtmoContext_T& context, ContextClouds* out,
                     std::vector<std::string>* load_errors);

// The streamed layer march's draft of the field (set_clouds calls it): the
// prototypes at half resolution, their ambient depths and ray index.
void prepare_draft(ContextClouds* clouds);

// What set_clouds derives from the field: heights, ray index, each
// prototype's continuing sides and sole instance (also when the field job's
// field replaces the coarse one).
void index_field(ContextClouds* clouds);

// The light the clouds are lit by this frame (the Sun, or the Moon when it
// outshines it), in the clouds' frame, with the sky and ground radiance.
clouds::CloudLight cloud_light(AtmoContext_T* context, AtmoView_T* view, const core::Scene& scene);

// Relights the clouds when the light moved beyond the threshold: the first
// lighting at once (with a draft: the draft's, the field's on a worker once
// the field job, if any, has landed: this call swaps its field in),
// later ones on a worker (abi/cloud_relight.h) whose grids are swapped in at
// the frame it is due (at once with settings.wait). Returns true when the
// grids changed.
bool relight_clouds(ContextClouds* clouds, const glm::dvec3& light_direction_enu);

// Brings the clipmap up to date for an eye (the clouds' frame): rebuilt when
// the field or its light changed or the eye entered another cell. The first
// build is on the calling thread; later ones on a worker (shown from the
// frame it is due) unless settings.wait. True when it changed.
bool update_clipmap(ContextClouds* clouds, const glm::dvec3& eye_in_clouds_m);

// Blocks until no job of the clouds runs (their results are taken by the next
// pass). Tests and benchmarks, like wait_for_tables.
void wait_for_cloud_jobs(ContextClouds* clouds);

// Makes the shadow map now if it is wanted for the first time or stale
// (relights then keep it up to date); true when it changed.
bool update_cloud_shadow(ContextClouds* clouds);

// The eye in the clouds' ENU frame, and the rotation from the view's ENU axes
// (at the eye) to the clouds' ENU axes.
glm::dvec3 eye_in_cloud_frame(const ContextClouds& clouds, const glm::dvec3& eye_ecef_m);

// The clouds' direct transmittance exp(-tau) from the eye towards a light
// (unit, the eye's ENU): get_lighting's Sun and Moon. 1 without clouds.
double cloud_transmittance_from_eye(const ContextClouds& clouds, const glm::dvec3& eye_ecef_m,
                                    const glm::dmat3& ecef_from_eye_enu, const glm::dvec3& direction_eye_enu);
glm::dmat3 cloud_enu_from_eye_enu(const ContextClouds& clouds, const glm::dmat3& ecef_from_eye_enu);

}  // namespace atmo::abi
