// cloud_twin.h — compiles shaders/clouds/cloud_functions.glsl and
// cloud_march.glsl as C++ over GLM, in float like the GPU: the CPU lighting
// reference, the path tracer's phase function and the GLSL passes evaluate
// one text (as core/atmosphere/shader_twin.h does for the atmosphere).
#pragma once

#include <glm/glm.hpp>

namespace atmo::clouds {
// The march's volume on the CPU (cloud_lighting.h): the GL passes' RGBA 3D
// texture (density, tau_light, tau_up, tau_down) as dense grids.
struct CpuCloudVolume;
glm::vec4 fetch_cloud_volume(const CpuCloudVolume& v, const glm::vec3& index_point);
}  // namespace atmo::clouds

namespace atmo::clouds::twin {

using namespace glm;

#include "core/twin/glsl_begin.h"
#define CLOUD_VOLUME CpuCloudVolume
inline vec4 cloud_fetch(const CpuCloudVolume& v, const vec3& p) { return fetch_cloud_volume(v, p); }
#include "clouds/cloud_functions.glsl"
#include "clouds/cloud_march.glsl"
#undef CLOUD_VOLUME
#include "core/twin/glsl_end.h"

}  // namespace atmo::clouds::twin
