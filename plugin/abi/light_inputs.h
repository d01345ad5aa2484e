// light_inputs.h — set_lights, update_lights and set_light_group_pose:
// validation of the host's light arrays and poses into the context's light
// set (core/lights/light_set.h). Each call is checked whole before anything
// changes; an error names the struct, the light's index and the field.
#pragma once

#include "abi/validation.h"
#include "atmo/atmo.h"
#include "core/lights/light_set.h"

namespace atmo::abi {

// Replaces group s.group (the lights read with light_size strides).
Verdict set_lights_state(const AtmoLightsState& s, lights::LightSet* set);
// Replaces lights [first, first + count) of a group.
Verdict update_lights_state(const AtmoLightsUpdate& u, lights::LightSet* set);
// Moves a group.
Verdict set_light_group_pose_state(const AtmoLightGroupPose& p, lights::LightSet* set);

}  // namespace atmo::abi
