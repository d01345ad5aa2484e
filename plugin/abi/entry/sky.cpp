// sky.cpp — the air, the time and the view, and the light they give the host.
#include <cmath>
#include <string>

#include "abi/cloud_inputs.h"
#include "abi/entry/call.h"
#include "abi/entry/entry_points.h"
#include "abi/entry/passes.h"
#include "abi/pass_inputs.h"
#include "abi/scene_inputs.h"
#include "abi/state_hash.h"
#include "abi/validation.h"
#include "core/geo/geodesy.h"

namespace atmo::abi::entry {

AtmoResult set_atmosphere(AtmoContext context, const AtmoAtmosphereState* state) {
  return context_call(context, "set_atmosphere", state, ATMO_TYPE_ATMOSPHERE_STATE, "AtmoAtmosphereState",
                      [&](AtmoContext_T* ctx, AtmoAtmosphereState& s) -> AtmoResult {
                        core::AtmosphereSettings settings;
                        Verdict v = validate_atmosphere(s, &settings);
                        if (!v.ok()) return fail(ctx, v.code, "set_atmosphere", v.message);
                        ctx->atmosphere = settings;
                        air_changed(ctx);  // starts building the new air's tables now (worker thread)
                        return ATMO_SUCCESS;
                      });
}

AtmoResult set_frame(AtmoContext context, const AtmoFrameState* state) {
  return context_call(context, "set_frame", state, ATMO_TYPE_FRAME_STATE, "AtmoFrameState",
                      [&](AtmoContext_T* ctx, AtmoFrameState& s) -> AtmoResult {
                        Verdict v = validate_frame(s);
                        if (!v.ok()) return fail(ctx, v.code, "set_frame", v.message);
                        ctx->utc_posix_s = s.utc_posix_s;
                        ctx->dut1_s = s.dut1_s;
                        ctx->frame_number = s.host_frame_number;
                        ++ctx->set_frame_calls;
                        ctx->host_numbers_frames = ctx->host_numbers_frames || s.host_frame_number != 0;
                        ctx->frame_clock = ctx->host_numbers_frames ? s.host_frame_number : ctx->set_frame_calls - 1;
                        ctx->deferred_frames = s.deferred_frames ? s.deferred_frames : ATMO_DEFERRED_FRAMES;
                        ctx->clouds.frame = ctx->frame_clock;  // when the clouds' jobs are due
                        ctx->clouds.deferred_frames = ctx->deferred_frames;
                        ctx->have_frame = true;
                        return ATMO_SUCCESS;
                      });
}

AtmoResult set_view(AtmoView view_handle, const AtmoViewState* state) {
  return view_call(view_handle, "set_view", state, ATMO_TYPE_VIEW_STATE, "AtmoViewState",
                   [&](AtmoContext_T* ctx, AtmoView_T* view, AtmoViewState& s) -> AtmoResult {
                     core::EyeFrame eye;
                     Verdict v = validate_view(s, &eye);
                     if (!v.ok()) return fail(ctx, v.code, "set_view", v.message);
                     s.header.next = nullptr;  // the host's chain need not outlive the call
                     view->state = s;
                     view->eye = eye;
                     view->have_state = true;
                     ++view->state_serial;
                     return ATMO_SUCCESS;
                   });
}

AtmoResult get_lighting(AtmoView view_handle, AtmoLighting* out) {
  return view_output_call(
      view_handle, "get_lighting", out, ATMO_TYPE_LIGHTING, "AtmoLighting", false,
      [&](AtmoContext_T* ctx, AtmoView_T* view, AtmoLighting& l) -> AtmoResult {
        core::Scene scene = prepare_scene(ctx, *view);
        const glm::dvec3& enu = scene.sun_direction_enu;
        for (int i = 0; i < 3; ++i) {
          l.sun_direction_ecef[i] = scene.sun_direction_ecef[i];
          l.sun_direction_enu[i] = enu[i];
        }
        const core::HorizontalAngles sun_angles = core::horizontal_angles(enu);
        l.sun_elevation_rad = sun_angles.elevation_rad;
        l.sun_azimuth_rad = sun_angles.azimuth_rad;
        const core::BodyIlluminance lit = core::body_illuminance(scene, ctx->transmittance, scene.eye_altitude_m);
        const core::SkyBodies& bodies = scene.bodies;
        const glm::dvec3 moon_ecef = view->eye.ecef_from_enu * bodies.moon_enu;
        // The clouds between the eye and each light dim it (direct transmittance).
        const double sun_clouds =
            cloud_transmittance_from_eye(ctx->clouds, view->eye.eye_ecef_m, view->eye.ecef_from_enu, enu);
        const double moon_clouds =
            cloud_transmittance_from_eye(ctx->clouds, view->eye.eye_ecef_m, view->eye.ecef_from_enu, bodies.moon_enu);
        for (int i = 0; i < 3; ++i) {
          l.sun_illuminance_lux[i] = lit.sun_lux[i] * sun_clouds;
          l.moon_direction_ecef[i] = moon_ecef[i];
          l.moon_direction_enu[i] = bodies.moon_enu[i];
          l.moon_illuminance_lux[i] = lit.moon_lux[i] * moon_clouds;
        }
        const core::HorizontalAngles moon_angles = core::horizontal_angles(bodies.moon_enu);
        l.moon_elevation_rad = moon_angles.elevation_rad;
        l.moon_azimuth_rad = moon_angles.azimuth_rad;
        const auto& atm = scene.atmosphere;
        l.moon_illuminated_fraction = bodies.moon_illuminated_fraction;
        l.moon_phase_angle_rad = bodies.moon_phase_angle_rad;
        const core::SkyLighting& sky = view_sky_lighting(ctx, view, scene);
        for (int i = 0; i < 3; ++i) {
          for (int k = 0; k < 9; ++k) l.sky_irradiance_sh9[k][i] = sky.irradiance_sh9[k][i];
          l.sky_illuminance_horizontal_lux[i] = sky.horizontal_illuminance_lux[i];
          l.sky_average_radiance[i] = sky.average_radiance[i];
        }
        if (ctx->gl_alive) {
          const double thickness_m = static_cast<double>(atm.top_radius_m - atm.bottom_radius_m);
          if (resolve_sky_method(view->state.sky_method, scene.eye_altitude_m, thickness_m) != gl::SkyMethod::kMarch) {
            l.aerial_inscatter_texture = ctx->renderer.aerial_inscatter_texture();
            l.aerial_transmittance_texture = ctx->renderer.aerial_transmittance_texture();
          }
          l.aerial_range_m = aerial_volume_range_m(scene, view->state, view->eye.view_from_clip);
          l.aerial_slices = static_cast<uint32_t>(ctx->renderer.table_sizes().aerial_slices);
        }
        return ATMO_SUCCESS;
      });
}

AtmoResult get_state_hash(AtmoView view_handle, AtmoStateHash* out) {
  return view_output_call(view_handle, "get_state_hash", out, ATMO_TYPE_STATE_HASH, "AtmoStateHash", false,
                          [&](AtmoContext_T* ctx, AtmoView_T* view, AtmoStateHash& o) -> AtmoResult {
                            // What this frame's passes draw from: the tables and the clouds' work due now.
                            const core::Scene scene = prepare_scene(ctx, *view);
                            settle_clouds(ctx, view, scene);
                            uint64_t parts[ATMO_STATE_HASH_PART_COUNT] = {};
                            state_hash_parts(ctx, *view, parts);
                            o.host_frame_number = ctx->frame_number;
                            o.hash = combined_state_hash(parts);
                            for (int k = 0; k < 8; ++k) o.parts[k] = k < ATMO_STATE_HASH_PART_COUNT ? parts[k] : 0;
                            return ATMO_SUCCESS;
                          });
}

}  // namespace atmo::abi::entry
