// fog_lighting_binding.h — what a host does with an AtmoFogLighting before
// drawing surfaces whose shader includes atmo_fog_lights.glsl: its eight
// textures on eight texture units and its uniforms, as the include's header
// says. Scoped: the units' earlier bindings and the active unit come back on
// destruction. The terrain, the tests and the benchmarks share it.
#ifndef ATMO_HOST_SCENE_FOG_LIGHTING_BINDING_H
#define ATMO_HOST_SCENE_FOG_LIGHTING_BINDING_H

#include <glad/gl.h>

#include "atmo/atmo.h"

namespace atmo::host_scene {

class FogLightingBinding {
 public:
  // `program` must be in use; units first_unit .. first_unit + kUnits - 1 are taken.
  FogLightingBinding(GLuint program, const AtmoFogLighting& fog, int first_unit);
  ~FogLightingBinding();
  FogLightingBinding(const FogLightingBinding&) = delete;
  FogLightingBinding& operator=(const FogLightingBinding&) = delete;

  static constexpr int kUnits = 8;

 private:
  int first_unit_;
  GLint active_ = 0;
  GLint previous_[kUnits] = {};
};

}  // namespace atmo::host_scene

#endif  // ATMO_HOST_SCENE_FOG_LIGHTING_BINDING_H
