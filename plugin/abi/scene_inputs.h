// scene_inputs.h — the context's cached transmittance table (rebuilt on the
// CPU only when the air or the model sphere changes) and the PassInputs a GL
// pass draws with. No GL.
#pragma once

#include "abi/objects.h"
#include "core/scene.h"
#include "gl/renderer.h"

namespace atmo::abi {

// The scene of a view, with the context's table brought up to date for it.
// Needs context->have_frame and view.have_state.
core::Scene prepare_scene(AtmoContext_T* context, const AtmoView_T& view);

gl::PassInputs make_pass_inputs(const core::Scene& scene, const AtmoView_T& view);

}  // namespace atmo::abi
