// clouds.cpp — set_clouds, the cloud pass, the clouds' shadow map for the
// host (get_cloud_shadows) and for the sky passes.
#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "abi/cloud_relight.h"
#include "abi/entry/call.h"
#include "abi/entry/entry_points.h"
#include "abi/entry/passes.h"
#include "abi/scene_inputs.h"
#include "abi/validation.h"
#include "abi/world_frame.h"

namespace atmo::abi::entry {

namespace {

// relight_clouds, saying when the field job's decks land.
void relight(AtmoContext_T* ctx, const glm::dvec3& light_direction_enu) {
  ContextClouds& c = ctx->clouds;
  const bool coarse = c.field_job.job != nullptr;
  relight_clouds(&c, light_direction_enu);
  if (coarse && !c.field_job.job && !c.empty())
    ctx->services.log(ATMO_LOG_INFO, "clouds: the decks at full resolution (" +
                                         std::to_string(c.field.memory_bytes() >> 20) + " MiB of density) replaced "
                                         "their coarse first field, generated in " +
                                         std::to_string(static_cast<int>(c.field_ms)) +
                                         " ms on a worker; their full lighting follows");
}

}  // namespace

AtmoResult set_clouds(AtmoContext context, const AtmoCloudsState* state) {
  return context_call(
      context, "set_clouds", state, ATMO_TYPE_CLOUDS_STATE, "AtmoCloudsState",
      [&](AtmoContext_T* ctx, AtmoCloudsState& s) -> AtmoResult {
        std::vector<std::string> load_errors;
        Verdict v = build_clouds(s, *ctx, &ctx->clouds, &load_errors);
        for (const std::string& line : load_errors)
          ctx->services.log(line.find(": warning: ") != std::string::npos ? ATMO_LOG_WARNING : ATMO_LOG_ERROR, line);
        if (!v.ok()) return fail(ctx, v.code, "set_clouds", v.message);
        const clouds::CloudField& f = ctx->clouds.field;
        ctx->services.log(ATMO_LOG_INFO, "clouds: " + std::to_string(f.instances.size()) + " clouds from " +
                                             std::to_string(f.prototypes.size()) + " volumes, " +
                                             std::to_string(f.memory_bytes() >> 20) + " MiB of density" +
                                             (ctx->clouds.field_job.job
                                                  ? " (decks coarse: a worker generates them in full)"
                                                  : ""));
        return ATMO_SUCCESS;
      });
}

void settle_clouds(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene) {
  ContextClouds& c = ctx->clouds;
  if (c.empty()) return;
  relight(ctx, cloud_light(ctx, view, scene).direction_enu);
  // The layer march's clipmap for this eye (the channels share it), as the pass would make it first.
  if (c.settings.layer) update_clipmap(&c, eye_in_cloud_frame(c, view->eye.eye_ecef_m));
}

AtmoResult clouds_pass(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene, const gl::PassInputs& inputs) {
  ContextClouds& c = ctx->clouds;
  gl::CloudFrameInputs frame;
  frame.light = cloud_light(ctx, view, scene);
  relight(ctx, frame.light.direction_enu);
  frame.field = &c.field;
  frame.depths = &c.depths;
  frame.version = c.version;
  frame.eye_in_clouds_m = eye_in_cloud_frame(c, view->eye.eye_ecef_m);
  frame.eye_enu_from_clouds = glm::transpose(cloud_enu_from_eye_enu(c, view->eye.ecef_from_enu));
  frame.field_version = c.field_version;
  frame.direct_only = c.settings.direct_only;
  const clouds::CloudViewCost cost = layer_view_cost(c.settings, view->state.cloud_quality);
  if (c.settings.layer) {
    if (update_clipmap(&c, frame.eye_in_clouds_m))
      ctx->services.log(ATMO_LOG_DEBUG, pass_log_prefix(ctx, view) + "clouds: clipmap of " +
                                            std::to_string(c.clipmap.levels.size()) + " levels, " +
                                            std::to_string(c.clipmap.memory_bytes() >> 20) + " MiB, built in " +
                                            std::to_string(static_cast<int>(c.clipmap_ms)) + " ms");
    frame.layer = true;
    frame.clipmap = &c.clipmap;
    frame.clipmap_version = c.clipmap_version;
    frame.layer_max_steps = cost.max_steps;
    frame.temporal = cost.temporal;
    frame.view_key = view->serial;
    clouds::TemporalView& tv = frame.temporal_view;
    tv.view_from_enu = glm::transpose(view->eye.enu_from_view);
    tv.clip_from_view = glm::make_mat4(view->state.clip_from_view);  // the host's (the eye frame holds its inverse)
    tv.host_frame_number = ctx->frame_number;
    // What this view's march samples: the field and its light (version) and the
    // clipmap's cell (views in other cells rebuild it between this view's frames).
    tv.content_version = c.clipmap_built_for * 0x9E3779B97F4A7C15ull ^
                         (static_cast<uint64_t>(static_cast<uint32_t>(c.clipmap.cell.x)) << 32 |
                          static_cast<uint32_t>(c.clipmap.cell.y));
  }
  frame.impostors = c.settings.impostors;
  // The impostors are updated once a host frame, by its first cloud pass, from that view's eye: the channels of
  // one vehicle share the eye's position, so whichever draws first makes the same impostors (views of one
  // context with different eyes get the first one's: docs/MULTI_CHANNEL.md).
  frame.host_frame = ctx->frame_clock;
  frame.impostor_eye_in_clouds_m = frame.eye_in_clouds_m;
  frame.impostor_eye_enu_from_clouds = frame.eye_enu_from_clouds;
  frame.octaves = clouds::default_octaves();
  frame.octaves.count = c.settings.octaves;
  frame.divisor = c.settings.layer ? cost.divisor : c.settings.march_divisor;
  frame.step_voxels = c.settings.march_step_voxels;
  bool drawn = false;
  std::string error;
  if (!ctx->cloud_renderer.draw(ctx->renderer, inputs, frame, &drawn, &error))
    return fail(ctx, ATMO_ERROR_GL, "render_pass(ATMO_PASS_CLOUDS)", error);
  const gl::CloudDrawStats& st = ctx->cloud_renderer.last_stats();
  ctx->services.log(ATMO_LOG_DEBUG, pass_log_prefix(ctx, view) + "clouds: " + std::to_string(st.in_view) +
                                        " in view, " + std::to_string(st.impostors_drawn) + " from impostors (" +
                                        std::to_string(st.impostors_created) + " new, " +
                                        std::to_string(st.impostors_updated) + " re-rendered, " +
                                        std::to_string(st.impostors_stale) + " stale left), " +
                                        std::to_string(st.marched) + " marched; impostor atlas " +
                                        std::to_string(ctx->cloud_renderer.impostor_bytes() >> 20) + " MiB");
  return drawn ? ATMO_SUCCESS : ATMO_STATUS_NOTHING_TO_DRAW;
}

AtmoResult get_cloud_shadows(AtmoView view_handle, AtmoCloudShadows* out) {
  return view_output_call(
      view_handle, "get_cloud_shadows", out, ATMO_TYPE_CLOUD_SHADOWS, "AtmoCloudShadows", true,
      [&](AtmoContext_T* ctx, AtmoView_T* view, AtmoCloudShadows& m) -> AtmoResult {
        AtmoResult result = ATMO_STATUS_NOTHING_TO_DRAW;
        ContextClouds& c = ctx->clouds;
        if (!c.empty()) {
          const core::Scene scene = prepare_scene(ctx, *view);
          relight(ctx, cloud_light(ctx, view, scene).direction_enu);
          update_cloud_shadow(&c);
          GLuint texture = 0;
          std::string error;
          if (!ctx->cloud_renderer.shadow_texture(c.shadow, c.field_version, c.shadow_version, &texture, &error))
            return fail(ctx, ATMO_ERROR_GL, "get_cloud_shadows", error);
          if (texture) {
            // The host's world -> ECEF -> the clouds' ENU -> the map's (u, v).
            const glm::dmat4 ecef_from_world =
                ecef_from_world_frame(view->state.world_frame, view->state.world_origin_geodetic);
            glm::dmat4 clouds_from_ecef(glm::transpose(c.ecef_from_enu));
            clouds_from_ecef[3] = glm::dvec4(-(glm::transpose(c.ecef_from_enu) * c.origin_ecef_m), 1.0);
            const glm::dmat4 uv = clouds::cloud_shadow_uv_from_enu(c.shadow) * clouds_from_ecef * ecef_from_world;
            for (int col = 0; col < 4; ++col)
              for (int row = 0; row < 4; ++row) m.uv_from_world[col * 4 + row] = uv[col][row];
            const glm::dvec3 light_world =
                glm::transpose(glm::dmat3(ecef_from_world)) * (c.ecef_from_enu * c.shadow.light_direction_enu);
            for (int i = 0; i < 3; ++i) m.light_direction_world[i] = light_world[i];
            m.texture = texture;
            m.size = static_cast<uint32_t>(c.shadow.size);
            m.texel_m = c.shadow.texel_m;
            result = ATMO_SUCCESS;
          }
        }
        if (result != ATMO_SUCCESS) {
          m.texture = 0;
          m.size = 0;
        }
        return result;
      });
}

bool add_cloud_shadow(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene, gl::PassInputs* inputs,
                      std::string* error) {
  ContextClouds& c = ctx->clouds;
  if (c.empty()) return true;  // no clouds: no cost
  const glm::dvec3 light = cloud_light(ctx, view, scene).direction_enu;
  const glm::dmat3 clouds_from_eye_axes = cloud_enu_from_eye_enu(c, view->eye.ecef_from_enu);
  if (glm::dot(clouds_from_eye_axes * scene.sun_direction_enu, light) < std::cos(0.5 * M_PI / 180.0)) return true;
  relight(ctx, light);
  update_cloud_shadow(&c);
  GLuint texture = 0;
  if (!ctx->cloud_renderer.shadow_texture(c.shadow, c.field_version, c.shadow_version, &texture, error)) return false;
  if (!texture) return true;  // the light is too low for any map
  // A point relative to the eye (its ENU axes) -> the clouds' ENU -> (u, v, height).
  glm::dmat4 clouds_from_eye(clouds_from_eye_axes);
  clouds_from_eye[3] = glm::dvec4(eye_in_cloud_frame(c, view->eye.eye_ecef_m), 1.0);
  inputs->cloud_shadow.texture = texture;
  inputs->cloud_shadow.uv_from_eye_enu = glm::mat4(clouds::cloud_shadow_uvz_from(c.shadow, clouds_from_eye));
  inputs->cloud_shadow.base_m = static_cast<float>(c.lowest_base_m);
  inputs->cloud_shadow.top_m = static_cast<float>(c.highest_top_m);
  inputs->cloud_shadow.version = (c.field_version << 32) ^ c.shadow_version;
  return true;
}

}  // namespace atmo::abi::entry
