// fog_inputs.h — set_fog and set_lights: validation of the host's structs
// into the context's fog medium and lights (core/fog/fog_frame.h, which also
// makes one view's frame from them; docs/FOG.md).
#pragma once

#include "abi/validation.h"
#include "atmo/atmo.h"
#include "core/fog/fog_frame.h"

namespace atmo::abi {

// Validates and applies; on error nothing changes. Builds tables when the phase changes.
Verdict set_fog_state(const AtmoFogState& s, fog::FogMedium* fog);
// The lights array is read with light_size strides.
Verdict set_lights_state(const AtmoLightsState& s, fog::FogLights* lights);

}  // namespace atmo::abi
