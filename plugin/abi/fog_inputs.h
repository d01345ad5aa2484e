// fog_inputs.h — set_fog: validation of the host's struct into the context's
// fog medium (core/fog/fog_frame.h, which also makes one view's frame of the
// fog and the lights; docs/FOG.md). The lights: light_inputs.h.
#pragma once

#include "abi/validation.h"
#include "atmo/atmo.h"
#include "core/fog/fog_frame.h"

namespace atmo::abi {

// Validates and applies; on error nothing changes. Builds tables when the phase changes.
Verdict set_fog_state(const AtmoFogState& s, fog::FogMedium* fog);

}  // namespace atmo::abi
