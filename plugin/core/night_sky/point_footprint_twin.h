// point_footprint_twin.h — compiles shaders/night_sky/point_footprint.glsl as
// C++ over GLM, so the CPU evaluates exactly the footprint the night-sky pass
// draws with (in float, like the GPU). The core's star_footprint_weight
// (star_photometry.h) is the same formula in double; tests check they agree.
#pragma once

#include <glm/glm.hpp>

namespace atmo::twin {

using namespace glm;

#include "core/twin/glsl_begin.h"
#include "night_sky/point_footprint.glsl"
#include "core/twin/glsl_end.h"

}  // namespace atmo::twin
