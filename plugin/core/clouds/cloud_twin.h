// cloud_twin.h — compiles shaders/clouds/cloud_functions.glsl as C++ over GLM,
// in float like the GPU: the CPU lighting reference, the path tracer's phase
// function and the GLSL passes evaluate one text (as core/shader_twin.h does
// for the atmosphere).
#pragma once

#include <glm/glm.hpp>

namespace atmo::clouds::twin {

using namespace glm;

#define ATMO_FN inline
#define IN(T) const T&
#include "clouds/cloud_functions.glsl"
#undef ATMO_FN
#undef IN

}  // namespace atmo::clouds::twin
