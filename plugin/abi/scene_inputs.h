// scene_inputs.h — turns the host's state (context + view) into the numbers a
// pass or the lighting query needs: atmosphere parameters on the sphere under
// the eye, the sun in ENU at the eye, and the transmittance table (rebuilt on
// the CPU only when the air or the sphere radius changes). No GL.
#pragma once

#include "abi/objects.h"
#include "gl/renderer.h"

namespace atmo::abi {

struct SceneInputs {
  twin::AtmosphereParameters atmosphere;
  glm::dvec3 sun_direction_ecef{0.0, 0.0, 1.0};
  glm::dvec3 sun_direction_enu{0.0, 0.0, 1.0};
  double eye_altitude_m = 0.0;  // above the model sphere, clamped to >= 1 m
};

// Needs context->have_frame and view->have_state.
SceneInputs prepare_scene(AtmoContext_T* context, const AtmoView_T& view);

gl::PassInputs make_pass_inputs(const SceneInputs& scene, const AtmoView_T& view);

}  // namespace atmo::abi
