// scene_inputs.h — the context's CPU lookup tables (rebuilt only when the air
// or the model sphere changes, after the first time on a worker thread:
// abi/table_builder.h) and the scene a view is drawn with. No GL.
#pragma once

#include "abi/objects.h"
#include "core/scene/scene.h"

namespace atmo::abi {

// The scene of a view, with the context's tables brought up to date for it.
// Needs context->have_frame and view.have_state. Never waits for a table build
// after the first: the first use builds the tables on this thread (progress to
// the host's log); when the key changes later the worker builds the new ones
// and, until they are ready, the scene keeps the air of the tables in use (so
// the passes and get_lighting stay consistent with them). A finished build is
// swapped in here, on the host's thread (bumping tables_version), and the
// worker's progress lines are logged here.
core::Scene prepare_scene(AtmoContext_T* context, AtmoView_T& view);

// The sky as a light at the view's eye (SH irradiance, mean radiance): ~2 ms
// of CPU, so cached per view and recomputed only when the sun moved by 0.1°,
// the altitude by 1 % + 10 m, or the air's tables changed.
const core::SkyLighting& view_sky_lighting(AtmoContext_T* context, AtmoView_T* view, const core::Scene& scene);

// set_atmosphere changed context->atmosphere: start building its tables now
// (at the sphere of the last view), before the next frame asks. No-op before
// the first frame (which builds synchronously). Never throws.
void air_changed(AtmoContext_T* context) noexcept;

// For tests and offline rendering that need the new air in the very next frame
// (internal: not in the C ABI). Waits until the worker has no build running
// or waiting, swaps in what it built and logs its lines. With a view (that has
// a state, on a context with a frame), first asks for the tables of that view's
// sphere, as its next render would; without one, waits for the tables asked for
// last (set_atmosphere or the last render / get_lighting).
void wait_for_tables(AtmoContext_T* context, AtmoView_T* view = nullptr);

// destroy_context: cancels the running build (checked per table row), joins the
// worker and logs its last lines. The context's destructor also joins.
void stop_table_builds(AtmoContext_T* context) noexcept;

}  // namespace atmo::abi
