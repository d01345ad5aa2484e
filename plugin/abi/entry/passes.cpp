// passes.cpp — render_pass: checks the order of calls and the host's depth
// texture, prepares what every pass needs and dispatches to the pass.
#include "abi/entry/passes.h"

#include <string>

#include "abi/entry/call.h"
#include "abi/entry/entry_points.h"
#include "abi/night_sky_inputs.h"
#include "abi/pass_inputs.h"
#include "abi/scene_inputs.h"

namespace atmo::abi::entry {

// The night sky's stars and planets (the Moon, the moonlit sky and the faint
// background are drawn by the sky pass). The plan already said something can show.
namespace {

AtmoResult night_sky_pass(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene,
                          const gl::PassInputs& inputs) {
  std::string error;
  if (!collect_night_points(ctx, *view, scene, &error)) {
    return fail(ctx, ATMO_ERROR_INVALID_ARGUMENT, "render_pass(ATMO_PASS_NIGHT_SKY)", "astrometry: " + error);
  }
  if (view->night_points.empty()) return ATMO_STATUS_NOTHING_TO_DRAW;
  if (!ctx->night_renderer.initialised() && !ctx->night_renderer.init(&error)) {
    return fail(ctx, ATMO_ERROR_GL, "render_pass(ATMO_PASS_NIGHT_SKY)", error);
  }
  gl::NightSkyTextures textures;
  if (!ctx->renderer.night_sky_textures(inputs, &textures, &error) ||
      !ctx->night_renderer.draw_points(inputs, textures, view->night_points, &error)) {
    return fail(ctx, ATMO_ERROR_GL, "render_pass(ATMO_PASS_NIGHT_SKY)", error);
  }
  return ATMO_SUCCESS;
}

}  // namespace

AtmoResult render_pass(AtmoView view_handle, const AtmoPassInfo* pass_in) {
  return view_call(view_handle, "render_pass", pass_in, ATMO_TYPE_PASS_INFO, "AtmoPassInfo",
                   [&](AtmoContext_T* ctx, AtmoView_T* view, AtmoPassInfo& pass) -> AtmoResult {
                     if (pass.pass >= ATMO_PASS_COUNT) {
                       return fail(ctx, ATMO_ERROR_INVALID_ARGUMENT, "render_pass",
                                   "AtmoPassInfo.pass = " + std::to_string(pass.pass) + " is not an AtmoPassKind");
                     }
                     const uint32_t takes = pass.pass == ATMO_PASS_SKY_OCCLUSION
                                                ? uint32_t(ATMO_PASS_SKY_OCCLUSION_NORMAL_UP |
                                                           ATMO_PASS_SKY_OCCLUSION_QUARTER_RES |
                                                           ATMO_PASS_SKY_OCCLUSION_EIGHTH_RES |
                                                           ATMO_PASS_SKY_OCCLUSION_NO_SUN |
                                                           ATMO_PASS_SKY_OCCLUSION_IMAGE |
                                                           ATMO_PASS_SKY_OCCLUSION_SIXTEENTH_RES)
                                                : 0u;
                     const uint32_t resolutions = pass.flags & (ATMO_PASS_SKY_OCCLUSION_QUARTER_RES |
                                                                ATMO_PASS_SKY_OCCLUSION_EIGHTH_RES |
                                                                ATMO_PASS_SKY_OCCLUSION_SIXTEENTH_RES);
                     const bool two_resolutions = (resolutions & (resolutions - 1)) != 0;
                     if ((pass.flags & ~takes) || two_resolutions) {
                       return fail(ctx, ATMO_ERROR_INVALID_ARGUMENT, "render_pass",
                                   "AtmoPassInfo.flags = " + std::to_string(pass.flags) +
                                       ((pass.flags & ~takes) ? " holds bits this pass does not take"
                                                               : " asks for two resolutions"));
                     }
                     if (AtmoResult r = require_frame_and_view(ctx, *view, "render_pass", true)) return r;

                     switch (pass.pass) {
                       case ATMO_PASS_CLOUDS:
                         if (ctx->clouds.empty()) return ATMO_STATUS_NOTHING_TO_DRAW;  // no clouds: no cost
                         break;
                       case ATMO_PASS_LIGHT_GLOWS:
                         if (!ctx->fog.enabled()) return ATMO_STATUS_NOTHING_TO_DRAW;  // no fog: no cost
                         break;
                       case ATMO_PASS_LIGHT_POINTS:
                         if (ctx->lights.empty()) return ATMO_STATUS_NOTHING_TO_DRAW;  // no lights: no cost
                         break;
                       case ATMO_PASS_AERIAL_PERSPECTIVE:
                         if (view->state.depth_texture == 0) return ATMO_STATUS_NOTHING_TO_DRAW;
                         break;
                       case ATMO_PASS_SKY_OCCLUSION:
                         // No objects, or no surfaces to shade: no cost.
                         if (ctx->occluders.objects.empty() || view->state.depth_texture == 0)
                           return ATMO_STATUS_NOTHING_TO_DRAW;
                         break;
                       default:
                         break;
                     }
                     core::Scene scene = prepare_scene(ctx, *view);
                     gl::PassInputs inputs =
                         make_pass_inputs(scene, *view, ctx->transmittance, ctx->multiple_scattering);
                     if (pass.pass == ATMO_PASS_AERIAL_PERSPECTIVE || pass.pass == ATMO_PASS_CLOUDS) {
                       // At night the haze over the geometry is lit by the Moon (the plan of this view's last sky or
                       // night pass).
                       light_haze_by_the_moon(*view, scene, &inputs);
                     }
                     if (pass.pass == ATMO_PASS_SKY || pass.pass == ATMO_PASS_NIGHT_SKY) {
                       const core::night::NightPlan& night = plan_night_sky(ctx, *view, scene, inputs);
                       // Daylight: no star or planet can change a pixel, so the night pass does no work at all (no GL
                       // call).
                       if (pass.pass == ATMO_PASS_NIGHT_SKY && night_points_invisible(ctx, night)) {
                         return ATMO_STATUS_NOTHING_TO_DRAW;
                       }
                       add_night_terms(ctx, *view, scene, &inputs);
                     }
                     if (view->state.depth_texture != 0 && !glIsTexture(view->state.depth_texture)) {
                       return fail(ctx, ATMO_ERROR_INVALID_ARGUMENT, "render_pass",
                                   "AtmoViewState.depth_texture = " + std::to_string(view->state.depth_texture) +
                                       " is not a texture in the current GL context");
                     }
                     if (ctx->uploaded_tables_version != ctx->tables_version) {
                       ctx->renderer.upload_tables(ctx->transmittance, ctx->multiple_scattering);
                       ctx->uploaded_tables_version = ctx->tables_version;
                     }
                     std::string error;
                     if ((pass.pass == ATMO_PASS_SKY || pass.pass == ATMO_PASS_AERIAL_PERSPECTIVE ||
                          pass.pass == ATMO_PASS_CLOUDS) &&
                         !add_cloud_shadow(ctx, view, scene, &inputs, &error))
                       return fail(ctx, ATMO_ERROR_GL, "render_pass", error);
                     if (pass.pass == ATMO_PASS_NIGHT_SKY) return night_sky_pass(ctx, view, scene, inputs);
                     if (pass.pass == ATMO_PASS_LIGHT_GLOWS) return fog_pass(ctx, view, scene, inputs);
                     if (pass.pass == ATMO_PASS_LIGHT_POINTS) return light_points_pass(ctx, view, scene, inputs);
                     if (pass.pass == ATMO_PASS_CLOUDS) return clouds_pass(ctx, view, scene, inputs);
                     if (pass.pass == ATMO_PASS_SKY_OCCLUSION)
                       return sky_occlusion_pass(ctx, view, scene, inputs, pass.flags);
                     bool ok = pass.pass == ATMO_PASS_SKY ? ctx->renderer.draw_sky(inputs, &error)
                                                          : ctx->renderer.draw_aerial_perspective(inputs, &error);
                     if (!ok) return fail(ctx, ATMO_ERROR_GL, "render_pass", error);
                     return ATMO_SUCCESS;
                   });
}

}  // namespace atmo::abi::entry
