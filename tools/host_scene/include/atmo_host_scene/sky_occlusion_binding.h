// sky_occlusion_binding.h — what a host does with an AtmoSkyOcclusion
// (get_sky_occlusion) before drawing surfaces whose shader includes
// atmo_sky_occlusion.glsl: its five textures on five texture units and its
// uniforms, as the include's header says (compiled with ATMO_OCC_IMAGE: the
// image's three textures and its few uniforms). Scoped: the units' earlier bindings
// and the active unit come back on destruction.
#ifndef ATMO_HOST_SCENE_SKY_OCCLUSION_BINDING_H
#define ATMO_HOST_SCENE_SKY_OCCLUSION_BINDING_H

#include <glad/gl.h>

#include "atmo/atmo.h"

namespace atmo::host_scene {

class SkyOcclusionBinding {
 public:
  // `program` must be in use; units first_unit .. first_unit + kUnits - 1 are taken.
  SkyOcclusionBinding(GLuint program, const AtmoSkyOcclusion& occlusion, int first_unit);
  ~SkyOcclusionBinding();
  SkyOcclusionBinding(const SkyOcclusionBinding&) = delete;
  SkyOcclusionBinding& operator=(const SkyOcclusionBinding&) = delete;

  static constexpr int kUnits = 5;

 private:
  int first_unit_;
  GLint active_ = 0;
  GLint previous_[kUnits] = {};
};

}  // namespace atmo::host_scene

#endif  // ATMO_HOST_SCENE_SKY_OCCLUSION_BINDING_H
