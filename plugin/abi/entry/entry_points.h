// entry_points.h — the functions of the AtmoPluginApi table, one file per
// concern: lifecycle.cpp (contexts, GL, views), sky.cpp (air, time, view,
// passes, lighting), clouds.cpp, fog.cpp. negotiate.cpp fills the table.
// Their thread rules and units are in host_sdk/include/atmo/atmo.h.
#pragma once

#include "atmo/atmo.h"

namespace atmo::abi::entry {

// lifecycle.cpp
AtmoResult create_context(const AtmoContextCreateInfo* info, AtmoContext* out);
void destroy_context(AtmoContext context);
AtmoResult gl_init(AtmoContext context);
AtmoResult gl_shutdown(AtmoContext context);
AtmoResult gl_context_lost(AtmoContext context);
AtmoResult create_view(AtmoContext context, const AtmoViewCreateInfo* info, AtmoView* out);
void destroy_view(AtmoView view);

// sky.cpp
AtmoResult set_atmosphere(AtmoContext context, const AtmoAtmosphereState* state);
AtmoResult set_frame(AtmoContext context, const AtmoFrameState* state);
AtmoResult set_view(AtmoView view, const AtmoViewState* state);
AtmoResult render_pass(AtmoView view, const AtmoPassInfo* pass);
AtmoResult get_lighting(AtmoView view, AtmoLighting* out);

// clouds.cpp
AtmoResult set_clouds(AtmoContext context, const AtmoCloudsState* state);
AtmoResult get_cloud_shadows(AtmoView view, AtmoCloudShadows* out);

// fog.cpp
AtmoResult set_fog(AtmoContext context, const AtmoFogState* state);
AtmoResult set_lights(AtmoContext context, const AtmoLightsState* state);
AtmoResult get_fog_lighting(AtmoView view, AtmoFogLighting* out);
AtmoResult set_occluders(AtmoContext context, const AtmoOccludersState* state);
AtmoResult set_occluder_poses(AtmoContext context, const AtmoOccluderPoses* poses);
AtmoResult get_sky_occlusion(AtmoView view, AtmoSkyOcclusion* out);
AtmoResult set_light_group_pose(AtmoContext context, const AtmoLightGroupPose* pose);
AtmoResult update_lights(AtmoContext context, const AtmoLightsUpdate* update);

// sky.cpp
AtmoResult get_state_hash(AtmoView view, AtmoStateHash* out);

}  // namespace atmo::abi::entry
