// Version-1 struct layouts are frozen: a host built against them must keep
// working. Each size equals the plugin's V1Size, and each field a later
// version might move is pinned by offset.
#include <gtest/gtest.h>

#include <cstddef>

#include "abi/struct_io.h"

using atmo::abi::V1Size;

TEST(StructLayout, Version1SizesAreFrozen) {
  EXPECT_EQ(sizeof(AtmoStructHeader), 16u);
  EXPECT_EQ(sizeof(AtmoNegotiateInfo), V1Size<AtmoNegotiateInfo>::value);
  // The function table grew at its end (set_clouds); 144-byte hosts get no clouds.
  EXPECT_EQ(V1Size<AtmoPluginApi>::value, 144u);
  // 160 with get_cloud_shadows, 184 with set_fog, set_lights, get_fog_lighting, 200 with the light groups' two;
  // then sky occlusion's three (set_occluders, set_occluder_poses, get_sky_occlusion): 224; get_state_hash: 232
  EXPECT_EQ(sizeof(AtmoPluginApi), 232u);
  EXPECT_EQ(sizeof(AtmoFogState), V1Size<AtmoFogState>::value);
  // AtmoLightsState grew at its end (group, visual_threshold_lux); 72-byte hosts replace group 0.
  EXPECT_EQ(V1Size<AtmoLightsState>::value, 72u);
  EXPECT_EQ(sizeof(AtmoLightsState), 88u);
  // The array's stride is AtmoLightsState.light_size: 96-byte lights read flags 0.
  EXPECT_EQ(V1Size<AtmoLightPoint>::value, 96u);
  EXPECT_EQ(sizeof(AtmoLightPoint), 104u);
  EXPECT_EQ(sizeof(AtmoLightGroupPose), V1Size<AtmoLightGroupPose>::value);
  EXPECT_EQ(sizeof(AtmoLightsUpdate), V1Size<AtmoLightsUpdate>::value);
  // Sky occlusion by the host's objects (sphere sets).
  EXPECT_EQ(sizeof(AtmoOccluderSphere), V1Size<AtmoOccluderSphere>::value);
  EXPECT_EQ(sizeof(AtmoOccluderSphere), 32u);
  EXPECT_EQ(sizeof(AtmoOccluderObject), V1Size<AtmoOccluderObject>::value);
  EXPECT_EQ(sizeof(AtmoOccluderObject), 168u);
  EXPECT_EQ(sizeof(AtmoOccludersState), V1Size<AtmoOccludersState>::value);
  EXPECT_EQ(sizeof(AtmoOccludersState), 64u);
  EXPECT_EQ(sizeof(AtmoOccluderPoses), V1Size<AtmoOccluderPoses>::value);
  EXPECT_EQ(sizeof(AtmoOccluderPoses), 32u);
  // AtmoSkyOcclusion grew at its end (the image); a 2312-byte host gets the rest.
  EXPECT_EQ(V1Size<AtmoSkyOcclusion>::value, 2312u);
  EXPECT_EQ(offsetof(AtmoSkyOcclusion, image), 2312u);
  EXPECT_EQ(sizeof(AtmoSkyOcclusion), 2360u);
  EXPECT_EQ(sizeof(AtmoStateHash), V1Size<AtmoStateHash>::value);
  EXPECT_EQ(sizeof(AtmoStateHash), 96u);
  // AtmoFogLighting grew at its end (the clusters); a 136-byte host gets light_count 0 (its include predates them).
  EXPECT_EQ(V1Size<AtmoFogLighting>::value, 136u);
  // ... then again (the translucent surfaces' fields): a 400-byte host keeps its surfaces' lights.
  EXPECT_EQ(offsetof(AtmoFogLighting, airlight_table), 400u);
  EXPECT_EQ(sizeof(AtmoFogLighting), 568u);
  EXPECT_EQ(sizeof(AtmoCloudShadows), V1Size<AtmoCloudShadows>::value);
  EXPECT_EQ(sizeof(AtmoCloudLayer), V1Size<AtmoCloudLayer>::value);
  // AtmoCloudsState grew at its end (impostor settings); 80-byte hosts get the defaults.
  EXPECT_EQ(V1Size<AtmoCloudsState>::value, 80u);
  EXPECT_EQ(sizeof(AtmoCloudsState), 128u);  // 120 before setup
  EXPECT_EQ(sizeof(AtmoHostServices), V1Size<AtmoHostServices>::value);
  EXPECT_EQ(sizeof(AtmoContextCreateInfo), V1Size<AtmoContextCreateInfo>::value);
  EXPECT_EQ(sizeof(AtmoViewCreateInfo), V1Size<AtmoViewCreateInfo>::value);
  EXPECT_EQ(sizeof(AtmoAtmosphereState), V1Size<AtmoAtmosphereState>::value);
  // AtmoFrameState grew at its end (deferred_frames); 40-byte hosts get ATMO_DEFERRED_FRAMES.
  EXPECT_EQ(V1Size<AtmoFrameState>::value, 40u);
  EXPECT_EQ(sizeof(AtmoFrameState), 48u);
  // AtmoViewState grew at its end (sky_method); 408-byte hosts read it as AUTO.
  EXPECT_EQ(V1Size<AtmoViewState>::value, 408u);
  EXPECT_EQ(sizeof(AtmoViewState), 464u);  // 440 before depth_origin and aerial_range_m, 456 before cloud_quality
  EXPECT_EQ(sizeof(AtmoPassInfo), V1Size<AtmoPassInfo>::value);
  // AtmoLighting grew at its end (sky light); hosts with the 104-byte layout keep working.
  EXPECT_EQ(V1Size<AtmoLighting>::value, 104u);
  EXPECT_EQ(sizeof(AtmoLighting), 496u);  // 392 before the Moon's fields
}

TEST(StructLayout, Version1OffsetsAreFrozen) {
  EXPECT_EQ(offsetof(AtmoPluginApi, result_string), 32u);
  EXPECT_EQ(offsetof(AtmoPluginApi, get_lighting), 136u);
  EXPECT_EQ(offsetof(AtmoPluginApi, set_clouds), 144u);
  EXPECT_EQ(offsetof(AtmoPluginApi, get_cloud_shadows), 152u);
  EXPECT_EQ(offsetof(AtmoCloudsState, light_update_threshold_deg), 72u);
  EXPECT_EQ(offsetof(AtmoCloudsState, draw_mode), 80u);
  EXPECT_EQ(offsetof(AtmoCloudsState, setup), 120u);
  EXPECT_EQ(offsetof(AtmoCloudsState, layer_size), 68u);  // the version-1 `reserved` (0: the version-1 stride)
  EXPECT_EQ(offsetof(AtmoLightsState, light_size), 20u);
  EXPECT_EQ(offsetof(AtmoLightsState, group), 72u);
  EXPECT_EQ(offsetof(AtmoLightPoint, flags), 96u);
  EXPECT_EQ(offsetof(AtmoPluginApi, set_light_group_pose), 184u);
  EXPECT_EQ(offsetof(AtmoPluginApi, update_lights), 192u);
  EXPECT_EQ(offsetof(AtmoPluginApi, set_occluders), 200u);
  EXPECT_EQ(offsetof(AtmoPluginApi, set_occluder_poses), 208u);
  EXPECT_EQ(offsetof(AtmoPluginApi, get_sky_occlusion), 216u);
  EXPECT_EQ(offsetof(AtmoOccluderObject, sphere_count), 8u);
  EXPECT_EQ(offsetof(AtmoOccluderObject, sphere_size), 12u);
  EXPECT_EQ(offsetof(AtmoOccluderObject, albedo), 16u);
  EXPECT_EQ(offsetof(AtmoOccluderObject, world_from_object), 40u);
  EXPECT_EQ(offsetof(AtmoOccludersState, world_frame), 16u);
  EXPECT_EQ(offsetof(AtmoOccludersState, object_size), 20u);
  EXPECT_EQ(offsetof(AtmoOccludersState, world_origin_geodetic), 24u);
  EXPECT_EQ(offsetof(AtmoOccludersState, objects), 48u);
  EXPECT_EQ(offsetof(AtmoOccludersState, object_count), 56u);
  EXPECT_EQ(offsetof(AtmoOccludersState, flags), 60u);
  EXPECT_EQ(offsetof(AtmoOccluderPoses, first), 16u);
  EXPECT_EQ(offsetof(AtmoOccluderPoses, count), 20u);
  EXPECT_EQ(offsetof(AtmoOccluderPoses, world_from_object), 24u);
  EXPECT_EQ(offsetof(AtmoSkyOcclusion, object_count), 16u);
  EXPECT_EQ(offsetof(AtmoSkyOcclusion, tile_objects), 36u);
  EXPECT_EQ(offsetof(AtmoSkyOcclusion, tile_from_position), 40u);
  EXPECT_EQ(offsetof(AtmoSkyOcclusion, enu_from_world), 168u);
  EXPECT_EQ(offsetof(AtmoSkyOcclusion, grid), 240u);
  EXPECT_EQ(offsetof(AtmoSkyOcclusion, limits), 272u);
  EXPECT_EQ(offsetof(AtmoSkyOcclusion, sun), 304u);
  EXPECT_EQ(offsetof(AtmoSkyOcclusion, sun_lux), 336u);
  EXPECT_EQ(offsetof(AtmoSkyOcclusion, longest_tile_list), 360u);
  EXPECT_EQ(offsetof(AtmoSkyOcclusion, sky_sh9), 368u);
  EXPECT_EQ(offsetof(AtmoSkyOcclusion, sun_sh9), 476u);
  EXPECT_EQ(offsetof(AtmoSkyOcclusion, transfer), 584u);
  EXPECT_EQ(offsetof(AtmoHostServices, gl_get_proc_address), 72u);
  EXPECT_EQ(offsetof(AtmoFrameState, utc_posix_s), 24u);
  EXPECT_EQ(offsetof(AtmoViewState, eye_ecef_m), 24u);
  EXPECT_EQ(offsetof(AtmoViewState, view_from_world), 96u);
  EXPECT_EQ(offsetof(AtmoViewState, clip_from_view), 224u);
  EXPECT_EQ(offsetof(AtmoViewState, viewport), 352u);
  EXPECT_EQ(offsetof(AtmoViewState, depth_texture), 368u);
  EXPECT_EQ(offsetof(AtmoViewState, exposure_scale), 400u);
  EXPECT_EQ(offsetof(AtmoViewState, sky_method), 408u);
  EXPECT_EQ(offsetof(AtmoLighting, sun_illuminance_lux), 80u);
  EXPECT_EQ(offsetof(AtmoLighting, sky_irradiance_sh9), 104u);
  EXPECT_EQ(offsetof(AtmoLighting, sky_average_radiance), 344u);
  EXPECT_EQ(offsetof(AtmoLighting, aerial_inscatter_texture), 368u);
  EXPECT_EQ(offsetof(AtmoLighting, moon_direction_ecef), 392u);
  EXPECT_EQ(offsetof(AtmoLighting, moon_illuminance_lux), 456u);
  EXPECT_EQ(offsetof(AtmoLighting, moon_phase_angle_rad), 488u);
  EXPECT_EQ(offsetof(AtmoViewState, sky_view_table_size), 416u);
  EXPECT_EQ(offsetof(AtmoViewState, depth_origin), 440u);
  EXPECT_EQ(offsetof(AtmoViewState, cloud_quality), 456u);
  EXPECT_EQ(offsetof(AtmoViewState, aerial_range_m), 448u);
}
