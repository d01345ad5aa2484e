// occlusion.cpp — the host's objects as occluders of the sky: set_occluders,
// set_occluder_poses and get_sky_occlusion (atmo_sky_occlusion.glsl's inputs);
// the method is in core/shadows (docs/SKY_OCCLUSION.md).
#include <cstring>
#include <string>
#include <vector>

#include "abi/entry/call.h"
#include "abi/entry/entry_points.h"
#include "abi/entry/passes.h"
#include "abi/scene_inputs.h"
#include "abi/world_frame.h"
#include "core/scene/scene.h"
#include "core/shadows/occlusion_frame.h"

namespace atmo::abi::entry {

AtmoResult set_occluders(AtmoContext context, const AtmoOccludersState* state) {
  if (!state) {
    return with_context(context, "set_occluders", [&](AtmoContext_T* ctx) -> AtmoResult {
      ctx->occluders.objects.clear();
      ctx->occluders.world_from_object.clear();
      ++ctx->occluders.version;
      return ATMO_SUCCESS;
    });
  }
  return context_call(context, "set_occluders", state, ATMO_TYPE_OCCLUDERS_STATE, "AtmoOccludersState",
                      [&](AtmoContext_T* ctx, const AtmoOccludersState& s) -> AtmoResult {
                        Verdict v = set_occluders_state(s, &ctx->occluders);
                        if (!v.ok()) return fail(ctx, v.code, "set_occluders", v.message);
                        return ATMO_SUCCESS;
                      });
}

AtmoResult set_occluder_poses(AtmoContext context, const AtmoOccluderPoses* poses) {
  return context_call(context, "set_occluder_poses", poses, ATMO_TYPE_OCCLUDER_POSES, "AtmoOccluderPoses",
                      [&](AtmoContext_T* ctx, const AtmoOccluderPoses& p) -> AtmoResult {
                        Verdict v = set_occluder_poses_state(p, &ctx->occluders);
                        if (!v.ok()) return fail(ctx, v.code, "set_occluder_poses", v.message);
                        return ATMO_SUCCESS;
                      });
}

namespace {

// The view's occluders this frame, relative to its eye (core/shadows/occlusion_frame.h).
shadows::OcclusionFrame view_occlusion_frame(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene) {
  const ContextOccluders& occ = ctx->occluders;
  const core::SkyLighting& sky = view_sky_lighting(ctx, view, scene);
  const core::BodyIlluminance lit = core::body_illuminance(scene, ctx->transmittance, scene.eye_altitude_m);
  const double sun_clouds = cloud_transmittance_from_eye(ctx->clouds, view->eye.eye_ecef_m, view->eye.ecef_from_enu,
                                                         scene.sun_direction_enu);
  const glm::dvec3 sun_lux = lit.sun_lux * sun_clouds;
  // Each object's frame to ENU at the eye, relative to the eye (double: ECEF is millions of metres).
  const glm::dmat3 enu_from_ecef = glm::transpose(view->eye.ecef_from_enu);
  glm::dmat4 enu_rel_from_ecef(enu_from_ecef);
  enu_rel_from_ecef[3] = glm::dvec4(-(enu_from_ecef * view->eye.eye_ecef_m), 1.0);
  std::vector<const shadows::OccluderObject*> objects;
  std::vector<glm::dmat4> poses;
  for (size_t i = 0; i < occ.objects.size(); ++i) {
    objects.push_back(&occ.objects[i]);
    poses.push_back(enu_rel_from_ecef * occ.ecef_from_world * occ.world_from_object[i]);
  }
  // The view's world axes: the host's positions relative to the eye are in them.
  const glm::dmat3 world_from_ecef =
      glm::transpose(glm::dmat3(ecef_from_world_frame(view->state.world_frame, view->state.world_origin_geodetic)));
  const glm::dmat3 world_from_enu = world_from_ecef * view->eye.ecef_from_enu;
  const glm::dmat3 enu_from_world = glm::transpose(world_from_enu);
  const glm::dmat4 clip_from_enu =
      glm::inverse(view->eye.view_from_clip) * glm::dmat4(glm::transpose(view->eye.enu_from_view));
  const glm::dmat4 clip_from_world = clip_from_enu * glm::dmat4(enu_from_world);
  const std::vector<glm::dvec3> radiance(sky.radiance_sh16.begin(), sky.radiance_sh16.end());
  shadows::OcclusionLimits limits;
  limits.bounce = !(occ.flags & ATMO_OCCLUSION_NO_BOUNCE);
  limits.hybrid = !(occ.flags & ATMO_OCCLUSION_OPTIMAL_LINEAR);
  return shadows::make_occlusion_frame(objects, poses, clip_from_world, enu_from_world, view->state.viewport[2],
                                       view->state.viewport[3],
                                       shadows::make_sky_transfer(radiance, scene.sun_direction_enu, sun_lux),
                                       scene.sun_direction_enu, sun_lux, limits);
}

}  // namespace

AtmoResult get_sky_occlusion(AtmoView view_handle, AtmoSkyOcclusion* out) {
  return view_output_call(
      view_handle, "get_sky_occlusion", out, ATMO_TYPE_SKY_OCCLUSION, "AtmoSkyOcclusion", true,
      [&](AtmoContext_T* ctx, AtmoView_T* view, AtmoSkyOcclusion& o) -> AtmoResult {
        std::memset(reinterpret_cast<char*>(&o) + sizeof(o.header), 0, sizeof(o) - sizeof(o.header));
        if (ctx->occluders.objects.empty()) return ATMO_STATUS_NOTHING_TO_DRAW;
        const shadows::OcclusionFrame frame = view_occlusion_frame(ctx, view, prepare_scene(ctx, *view));
        std::string error;
        if (!ctx->occlusion_renderer.upload(frame, &error)) return fail(ctx, ATMO_ERROR_GL, "get_sky_occlusion", error);
        o.object_count = static_cast<uint32_t>(ctx->occluders.objects.size());
        o.tables = ctx->occlusion_renderer.tables();
        o.spheres = ctx->occlusion_renderer.spheres();
        o.objects = ctx->occlusion_renderer.objects();
        o.tiles = ctx->occlusion_renderer.tiles();
        o.tile_objects = ctx->occlusion_renderer.tile_objects();
        for (int c = 0; c < 4; ++c)
          for (int r = 0; r < 4; ++r) o.tile_from_position[c * 4 + r] = frame.tile_from_position[c][r];
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r) o.enu_from_world[c * 3 + r] = frame.enu_from_world[c][r];
        for (int i = 0; i < 4; ++i) {
          o.grid[i] = frame.grid[i];
          o.limits[i] = frame.limits[i];
          o.sun[i] = frame.sun[i];
        }
        for (int i = 0; i < 3; ++i) o.sun_lux[i] = frame.sun_lux[i];
        o.longest_tile_list = frame.longest_tile_list;
        std::memcpy(o.sky_sh9, frame.sky.sky_sh9.data(), sizeof(o.sky_sh9));
        std::memcpy(o.sun_sh9, frame.sky.sun_sh9.data(), sizeof(o.sun_sh9));
        std::memcpy(o.transfer, frame.sky.transfer.data(), sizeof(o.transfer));
        const gl::OcclusionRenderer::Image* image = ctx->occlusion_renderer.image(view->serial);
        if (image && view->occlusion_image_state_serial == view->state_serial) {
          for (int k = 0; k < 3; ++k) o.image[k] = image->textures[k];
          o.image_reduction = static_cast<uint32_t>(view->occlusion_image_reduction);
          for (int k = 0; k < 4; ++k) o.image_map[k] = image->map[k];
        }
        return ATMO_SUCCESS;
      });
}

AtmoResult sky_occlusion_pass(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene,
                              const gl::PassInputs& inputs, uint32_t flags) {
  const shadows::OcclusionFrame frame = view_occlusion_frame(ctx, view, scene);
  std::string error;
  const int reduction = (flags & ATMO_PASS_SKY_OCCLUSION_SIXTEENTH_RES) ? 16
                        : (flags & ATMO_PASS_SKY_OCCLUSION_EIGHTH_RES)  ? 8
                        : (flags & ATMO_PASS_SKY_OCCLUSION_QUARTER_RES) ? 4
                                                                         : 1;
  if (flags & ATMO_PASS_SKY_OCCLUSION_IMAGE) {
    const int image_reduction = reduction > 1 ? reduction : 8;  // the image's default: 8 x 8
    if (!ctx->occlusion_renderer.draw_image(inputs, frame, view->serial,
                                            (flags & ATMO_PASS_SKY_OCCLUSION_NORMAL_UP) != 0, image_reduction,
                                            (flags & ATMO_PASS_SKY_OCCLUSION_NO_SUN) != 0, &error))
      return fail(ctx, ATMO_ERROR_GL, "render_pass(ATMO_PASS_SKY_OCCLUSION, IMAGE)", error);
    view->occlusion_image_state_serial = view->state_serial;
    view->occlusion_image_reduction = image_reduction;
    return ATMO_SUCCESS;
  }
  if (!ctx->occlusion_renderer.draw(inputs, frame, (flags & ATMO_PASS_SKY_OCCLUSION_NORMAL_UP) != 0, reduction,
                                    (flags & ATMO_PASS_SKY_OCCLUSION_NO_SUN) != 0, &error))
    return fail(ctx, ATMO_ERROR_GL, "render_pass(ATMO_PASS_SKY_OCCLUSION)", error);
  return ATMO_SUCCESS;
}

}  // namespace atmo::abi::entry
