// passes.h — the passes render_pass (passes.cpp) dispatches to, each in its
// feature's file, and the clouds' shadow that the sky passes add.
#pragma once

#include <string>

#include "abi/objects.h"
#include "core/scene/scene.h"
#include "gl/renderer.h"

namespace atmo::abi::entry {

// clouds.cpp
AtmoResult clouds_pass(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene, const gl::PassInputs& inputs);
// The clouds' shadow on the sunlit air for the sky and aerial-perspective
// passes (functions.glsl CloudShadowing): the map of get_cloud_shadows, made
// on the first such pass and kept by the relights, when there are clouds and
// the Sun lights them (under the Moon the map is the Moon's; the sky's Sun
// term is left alone). False and *error on a GL failure.
bool add_cloud_shadow(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene, gl::PassInputs* inputs,
                      std::string* error);

// The clouds' deferred work due this frame taken, and their light checked, as the cloud pass does first
// (get_state_hash hashes what the passes will draw from).
void settle_clouds(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene);

// fog.cpp
AtmoResult fog_pass(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene, const gl::PassInputs& inputs);
AtmoResult light_points_pass(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene,
                             const gl::PassInputs& inputs);

// occlusion.cpp: ATMO_PASS_SKY_OCCLUSION (flags: AtmoPassInfo.flags).
AtmoResult sky_occlusion_pass(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene,
                              const gl::PassInputs& inputs, uint32_t flags);

}  // namespace atmo::abi::entry
