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
// The layer march's clipmap on the CPU (cloud_clipmap.h).
struct CpuCloudLayer;
glm::vec4 fetch_cloud_layer_a(const CpuCloudLayer& v, int level, const glm::vec3& index_point);
glm::vec2 fetch_cloud_layer_b(const CpuCloudLayer& v, int level, const glm::vec3& index_point);
// Brick `brick` (clamped into the level) of the level's clear distances.
float fetch_cloud_layer_clear(const CpuCloudLayer& v, int level, const glm::ivec3& brick);
}  // namespace atmo::clouds

namespace atmo::clouds::twin {

using namespace glm;

#include "core/twin/glsl_begin.h"
#define CLOUD_VOLUME CpuCloudVolume
inline vec4 cloud_fetch(const CpuCloudVolume& v, const vec3& p) { return fetch_cloud_volume(v, p); }
#include "clouds/cloud_functions.glsl"
#include "clouds/cloud_march.glsl"
#undef CLOUD_VOLUME
#define CLOUD_LAYER CpuCloudLayer
inline vec4 cloud_layer_fetch_a(const CpuCloudLayer& v, int level, const vec3& q) {
  return fetch_cloud_layer_a(v, level, q);
}
inline vec2 cloud_layer_fetch_b(const CpuCloudLayer& v, int level, const vec3& q) {
  return fetch_cloud_layer_b(v, level, q);
}
inline float cloud_layer_fetch_clear(const CpuCloudLayer& v, int level, const ivec3& brick) {
  return fetch_cloud_layer_clear(v, level, brick);
}
// No air on the CPU: the twin's radiance is the clouds' own.
inline void cloud_layer_air(float, vec3& inscatter, vec3& transmittance) {
  inscatter = vec3(0.0f);
  transmittance = vec3(1.0f);
}
#include "clouds/cloud_layer_march.glsl"
#undef CLOUD_LAYER
#include "core/twin/glsl_end.h"

}  // namespace atmo::clouds::twin
