// fog.cpp — set_fog, the lights (set_lights, update_lights,
// set_light_group_pose), the glow pass and the host's lit surfaces
// (get_fog_lighting); the physics is in core/fog and core/lights (docs/FOG.md).
#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

#include "abi/entry/call.h"
#include "abi/entry/entry_points.h"
#include "abi/entry/passes.h"
#include "abi/scene_inputs.h"
#include "abi/validation.h"
#include "abi/world_frame.h"

namespace atmo::abi::entry {

// The glow threshold of a frame (core/fog/fog_frame.h), from the view's exposure.
namespace {

double glow_threshold(const AtmoContext_T* ctx, const AtmoView_T* view) {
  const double exposure = view->state.exposure_scale > 0.0 ? view->state.exposure_scale : kDefaultExposureScale;
  return fog::glow_threshold_cd_m2(ctx->lights.glow_threshold_cd_m2, exposure);
}

// The view's lights in the fog and their tree, made once per set_view / set_fog / set_lights.
const fog::FogFrame& view_fog_frame(AtmoContext_T* ctx, AtmoView_T* view) {
  if (!view->fog_frame || view->fog_frame_context_serial != ctx->fog_serial ||
      view->fog_frame_view_serial != view->state_serial) {
    // Both reuse the last frame's storage (65 536 lights: megabytes).
    if (!view->fog_frame) view->fog_frame.emplace();
    fog::make_fog_frame(ctx->fog, ctx->lights, view->eye, glow_threshold(ctx, view), &*view->fog_frame);
    if (!view->light_tree) view->light_tree.emplace();
    lights::build_light_tree(view->fog_frame->lights, &*view->light_tree);
    view->fog_frame_context_serial = ctx->fog_serial;
    view->fog_frame_view_serial = view->state_serial;
  }
  return *view->fog_frame;
}

// The clip position of an ENU direction at the eye: the host's projection times its view rotation.
glm::dmat4 clip_from_enu(const AtmoView_T* view) {
  return glm::inverse(view->eye.view_from_clip) * glm::dmat4(glm::transpose(view->eye.enu_from_view));
}

// The view's clusters for the host's surfaces, made once per set_view / fog or light change.
const lights::LightClusters& view_light_clusters(AtmoContext_T* ctx, AtmoView_T* view) {
  const fog::FogFrame& frame = view_fog_frame(ctx, view);
  if (!view->light_clusters || view->light_clusters_context_serial != ctx->fog_serial ||
      view->light_clusters_view_serial != view->state_serial) {
    const lights::ClusterGrid grid =
        lights::ClusterGrid::for_view(clip_from_enu(view), view->state.viewport[2], view->state.viewport[3],
                                      lights::ClusterGrid::kSurfaceTilePx);
    view->light_clusters = lights::cluster_lights(frame, *view->light_tree, grid,
                                                  static_cast<float>(ctx->fog.optics.albedo),
                                                  glow_threshold(ctx, view));
    view->light_clusters_context_serial = ctx->fog_serial;
    view->light_clusters_view_serial = view->state_serial;
  }
  return *view->light_clusters;
}

// The pixel's floor of sin gamma for the view's glows (fog::glow_min_sin).
double view_glow_min_sin(const AtmoView_T* view) {
  const double tan_half = 1.0 / std::max(std::abs(view->state.clip_from_view[5]), 1e-12);
  return fog::glow_min_sin(tan_half, view->state.viewport[3]);
}

// Tables for the include when there is no fog (it still samples them; the terms they scale are 0).
const fog::FogTable& no_fog_table() {
  static const fog::FogTable t = [] {
    fog::FogTable table;
    table.width = 2;
    table.height = 2 * fog::kSurfaceLayers;
    table.texels.assign(static_cast<size_t>(table.width) * table.height, 0.0f);
    return table;
  }();
  return t;
}

}  // namespace

AtmoResult fog_pass(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene, const gl::PassInputs& inputs) {
  const fog::FogFrame& frame = view_fog_frame(ctx, view);
  gl::FogDrawInputs in;
  in.frame = &frame;
  in.extinction_per_m = static_cast<float>(ctx->fog.optics.extinction_per_m);
  in.albedo = static_cast<float>(ctx->fog.optics.albedo);
  const core::SkyLighting& sky = view_sky_lighting(ctx, view, scene);
  in.ambient_cd_m2 = glm::vec3(fog::ambient_radiance_cd_m2(ctx->fog.optics, sky, scene, ctx->atmosphere.ground_albedo));
  in.min_sin = static_cast<float>(view_glow_min_sin(view));
  const lights::GlowTiles glows = lights::bin_glows(frame, *view->light_tree, ctx->fog.airlight, clip_from_enu(view),
                                                    view->state.viewport[2], view->state.viewport[3], in.min_sin);
  in.glows = &glows;
  std::string error;
  if (!ctx->fog_renderer.upload_tables(ctx->fog.airlight, ctx->fog.surface, ctx->fog.version, &error) ||
      !ctx->fog_renderer.draw(ctx->renderer, inputs, in, &error))
    return fail(ctx, ATMO_ERROR_GL, "render_pass(ATMO_PASS_LIGHT_GLOWS)", error);
  const gl::FogDrawStats& st = ctx->fog_renderer.last_stats();
  ctx->services.log(ATMO_LOG_DEBUG, pass_log_prefix(ctx, view) + "fog: " + std::to_string(st.lights) + " lights, " +
                                        std::to_string(st.glows_drawn) + " glow cores over " +
                                        std::to_string(static_cast<long long>(st.covered_pixels)) + " pixels, " +
                                        std::to_string(glows.lists.size()) + " tile glows (" +
                                        std::to_string(glows.merged.size()) + " merged, longest list " +
                                        std::to_string(glows.longest_list) + "; " + std::to_string(glows.weighed) +
                                        " tree entries weighed, " + std::to_string(glows.merged_entries) + " merged)");
  return ATMO_SUCCESS;
}

// The eye's threshold illuminance for the light points: the host's, else
// Allard's for the sky behind the lights (the view's mean sky luminance;
// at night a few mcd/m^2: 8e-7 lx).
static double visual_threshold_lux(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene) {
  if (ctx->lights.visual_threshold_lux > 0.0) return ctx->lights.visual_threshold_lux;
  return lights::allard_threshold_lux(lights::luminance(view_sky_lighting(ctx, view, scene).average_radiance));
}

AtmoResult light_points_pass(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene,
                             const gl::PassInputs& inputs) {
  const fog::FogFrame& frame = view_fog_frame(ctx, view);
  lights::PointCamera camera;
  const glm::dmat4 clip_from_view = glm::inverse(glm::dmat4(inputs.view_from_clip));
  camera.clip_from_enu = clip_from_view * glm::dmat4(glm::transpose(glm::dmat3(inputs.enu_from_view)));
  camera.viewport_width = inputs.viewport[2];
  camera.viewport_height = inputs.viewport[3];
  camera.margin_px = gl::LightPointRenderer::kMarginPx;
  view->light_points = lights::visible_light_points(frame, scene.atmosphere, inputs.eye_altitude_m, camera,
                                                    visual_threshold_lux(ctx, view, scene), &view->light_point_stats);
  const lights::LightPointStats& st = view->light_point_stats;
  ctx->services.log(ATMO_LOG_DEBUG, pass_log_prefix(ctx, view) + "light points: " + std::to_string(st.lights) +
                                        " lights, " + std::to_string(st.drawn) + " drawn, " +
                                        std::to_string(st.below_threshold) + " under the eye's threshold, " +
                                        std::to_string(st.off_screen) + " off screen");
  if (view->light_points.empty()) return ATMO_STATUS_NOTHING_TO_DRAW;
  std::string error;
  if (!ctx->light_point_renderer.draw(inputs, view->light_points, &error))
    return fail(ctx, ATMO_ERROR_GL, "render_pass(ATMO_PASS_LIGHT_POINTS)", error);
  return ATMO_SUCCESS;
}

// set_fog and set_lights: null clears (no fog, no lights); either way, on
// success, every view's fog frame is made again.
template <typename State, typename Clear, typename Apply>
AtmoResult set_fog_input(AtmoContext context, const char* function, const State* state, AtmoStructType type,
                         const char* type_name, Clear clear, Apply apply) {
  if (!state)
    return with_context(context, function, [&](AtmoContext_T* ctx) -> AtmoResult {
      clear(ctx);
      ++ctx->fog_serial;
      return ATMO_SUCCESS;
    });
  return context_call(context, function, state, type, type_name,
                      [&](AtmoContext_T* ctx, const State& s) -> AtmoResult {
                        Verdict v = apply(s, ctx);
                        if (!v.ok()) return fail(ctx, v.code, function, v.message);
                        ++ctx->fog_serial;
                        return ATMO_SUCCESS;
                      });
}

AtmoResult set_fog(AtmoContext context, const AtmoFogState* state) {
  return set_fog_input(
      context, "set_fog", state, ATMO_TYPE_FOG_STATE, "AtmoFogState",
      [](AtmoContext_T* ctx) {
        ctx->fog.optics = fog::FogOptics{};
        ctx->fog.optics.extinction_per_m = 0.0;
      },
      [](const AtmoFogState& s, AtmoContext_T* ctx) { return set_fog_state(s, &ctx->fog); });
}

AtmoResult set_lights(AtmoContext context, const AtmoLightsState* state) {
  return set_fog_input(
      context, "set_lights", state, ATMO_TYPE_LIGHTS_STATE, "AtmoLightsState",
      [](AtmoContext_T* ctx) {
        const uint64_t version = ctx->lights.version;
        ctx->lights = lights::LightSet{};
        ctx->lights.version = version + 1;
      },
      [](const AtmoLightsState& s, AtmoContext_T* ctx) { return set_lights_state(s, &ctx->lights); });
}

AtmoResult update_lights(AtmoContext context, const AtmoLightsUpdate* update) {
  return context_call(context, "update_lights", update, ATMO_TYPE_LIGHTS_UPDATE, "AtmoLightsUpdate",
                      [&](AtmoContext_T* ctx, const AtmoLightsUpdate& u) -> AtmoResult {
                        Verdict v = update_lights_state(u, &ctx->lights);
                        if (!v.ok()) return fail(ctx, v.code, "update_lights", v.message);
                        ++ctx->fog_serial;
                        return ATMO_SUCCESS;
                      });
}

AtmoResult set_light_group_pose(AtmoContext context, const AtmoLightGroupPose* pose) {
  return context_call(context, "set_light_group_pose", pose, ATMO_TYPE_LIGHT_GROUP_POSE, "AtmoLightGroupPose",
                      [&](AtmoContext_T* ctx, const AtmoLightGroupPose& p) -> AtmoResult {
                        Verdict v = set_light_group_pose_state(p, &ctx->lights);
                        if (!v.ok()) return fail(ctx, v.code, "set_light_group_pose", v.message);
                        ++ctx->fog_serial;
                        return ATMO_SUCCESS;
                      });
}

// The fields for the host's translucent surfaces (atmo_fog_translucent): the fog's medium and light, and the
// glows its view's glow pass last drew (with or without lights: a translucent surface in fog is fogged).
bool fill_translucent_fields(AtmoContext_T* ctx, AtmoView_T* view, AtmoFogLighting* f, std::string* error) {
  if (!ctx->fog.enabled()) return true;
  const core::Scene scene = prepare_scene(ctx, *view);
  const core::SkyLighting& sky = view_sky_lighting(ctx, view, scene);
  const glm::dvec3 ambient = fog::ambient_radiance_cd_m2(ctx->fog.optics, sky, scene, ctx->atmosphere.ground_albedo);
  const fog::FogFrame& frame = view_fog_frame(ctx, view);
  if (!ctx->fog_renderer.upload_tables(ctx->fog.airlight, ctx->fog.surface, ctx->fog.version, error)) return false;
  ctx->fog_renderer.ensure_glow_textures();
  f->medium[0] = ctx->fog.optics.extinction_per_m;
  f->medium[1] = ctx->fog.optics.albedo;
  f->medium[2] = frame.top_above_eye_m;
  f->airlight_table = ctx->fog_renderer.airlight_table();
  f->glow_tiles = ctx->fog_renderer.glow_tiles();
  f->glow_lists = ctx->fog_renderer.glow_lists();
  f->glow_entries = ctx->fog_renderer.glow_entries();
  const lights::ClusterGrid grid = lights::ClusterGrid::for_view(clip_from_enu(view), view->state.viewport[2],
                                                                 view->state.viewport[3],
                                                                 lights::ClusterGrid::kGlowTilePx);
  const bool glows = !frame.lights.empty();
  f->glow_grid[0] = glows ? grid.tiles_x : 0;
  f->glow_grid[1] = glows ? grid.tiles_y : 0;
  f->glow_grid[2] = ctx->fog.airlight.width;
  f->glow_grid[3] = view_glow_min_sin(view);
  for (int i = 0; i < 3; ++i) {
    f->ambient[i] = ambient[i];
    f->fluence[i] = frame.fluence[i];
  }
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) f->flux[c * 3 + r] = frame.flux_towards_lights[c][r];
  return true;
}

AtmoResult get_fog_lighting(AtmoView view_handle, AtmoFogLighting* out) {
  return view_output_call(
      view_handle, "get_fog_lighting", out, ATMO_TYPE_FOG_LIGHTING, "AtmoFogLighting", true,
      [&](AtmoContext_T* ctx, AtmoView_T* view, AtmoFogLighting& f) -> AtmoResult {
        std::memset(reinterpret_cast<char*>(&f) + sizeof(f.header), 0, sizeof(f) - sizeof(f.header));
        std::string error;
        if (!fill_translucent_fields(ctx, view, &f, &error)) return fail(ctx, ATMO_ERROR_GL, "get_fog_lighting", error);
        if (ctx->lights.empty()) return ATMO_STATUS_NOTHING_TO_DRAW;
        if (out->header.struct_size < offsetof(AtmoFogLighting, cluster_grid) + sizeof(f.cluster_grid)) {
          // An include from before the clusters reads the lights in another layout: give it none.
          if (!ctx->warned_old_fog_lighting)
            ctx->services.log(ATMO_LOG_WARNING, "get_fog_lighting: the host's AtmoFogLighting (" +
                                                    std::to_string(out->header.struct_size) +
                                                    " bytes) predates the light clusters; its lights are left out "
                                                    "(update atmo_fog_lights.glsl and atmo.h)");
          ctx->warned_old_fog_lighting = true;
          return ATMO_STATUS_NOTHING_TO_DRAW;
        }
        const fog::FogFrame& frame = view_fog_frame(ctx, view);
        const lights::LightClusters& clusters = view_light_clusters(ctx, view);
        // The view's world axes from the eye's ENU.
        const glm::dmat3 world_from_ecef = glm::transpose(
            glm::dmat3(ecef_from_world_frame(view->state.world_frame, view->state.world_origin_geodetic)));
        const glm::dmat3 world_from_enu = world_from_ecef * view->eye.ecef_from_enu;
        const bool fogged = ctx->fog.enabled();
        const fog::FogTable& airlight = fogged ? ctx->fog.airlight : no_fog_table();
        const fog::FogTable& surface = fogged ? ctx->fog.surface : no_fog_table();
        if (!ctx->fog_renderer.upload_tables(airlight, surface, fogged ? ctx->fog.version : ~uint64_t(0), &error) ||
            !ctx->fog_renderer.upload_host_lights(frame, clusters, world_from_enu, &error))
          return fail(ctx, ATMO_ERROR_GL, "get_fog_lighting", error);
        f.light_count = static_cast<uint32_t>(frame.lights.size());
        f.light_texture = ctx->fog_renderer.light_texture();
        f.surface_table = ctx->fog_renderer.surface_table();
        f.surface_table_size[0] = surface.width;
        f.surface_table_size[1] = surface.height / fog::kSurfaceLayers;
        f.medium[0] = fogged ? ctx->fog.optics.extinction_per_m : 0.0;
        f.medium[1] = ctx->fog.optics.albedo;
        f.medium[2] = frame.top_above_eye_m;
        for (int i = 0; i < 4; ++i) f.diffusion[i] = frame.diffusion[i];
        const glm::dvec3 up = world_from_enu * glm::dvec3(0.0, 0.0, 1.0);
        for (int i = 0; i < 3; ++i) f.up_world[i] = up[i];
        f.cluster_grid = ctx->fog_renderer.cluster_grid();
        f.far_field = ctx->fog_renderer.far_field();
        const glm::dmat4 clip_from_world = clusters.grid.clip_from_enu * glm::dmat4(glm::transpose(world_from_enu));
        for (int c = 0; c < 4; ++c)
          for (int r = 0; r < 4; ++r) f.cluster_from_position[c * 4 + r] = clip_from_world[c][r];
        f.cluster_grid_size[0] = clusters.grid.tiles_x;
        f.cluster_grid_size[1] = clusters.grid.tiles_y;
        f.cluster_grid_size[2] = lights::ClusterGrid::kSlices;
        f.cluster_range[0] = clusters.grid.near_m;
        f.cluster_range[1] = std::log(clusters.grid.far_m / clusters.grid.near_m);
        const glm::dmat3 enu_from_world = glm::transpose(world_from_enu);
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r) f.enu_from_world[c * 3 + r] = enu_from_world[c][r];
        ctx->services.log(ATMO_LOG_DEBUG, pass_log_prefix(ctx, view) + "light clusters: " +
                                              std::to_string(frame.lights.size()) + " lights, " +
                                              std::to_string(clusters.opened) + " tree nodes opened, " +
                                              std::to_string(clusters.lists.size()) + " listed (longest " +
                                              std::to_string(clusters.longest_list) + ", " +
                                              std::to_string(clusters.merged.size()) + " of them nodes of " +
                                              std::to_string(clusters.merged_lights) + " lights)");
        return ATMO_SUCCESS;
      });
}

}  // namespace atmo::abi::entry
