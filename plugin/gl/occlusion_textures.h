// occlusion_textures.h — a view's occluders (core/shadows OcclusionFrame) as
// the textures atmo_sky_occlusion.glsl reads, and its tables (made once).
#pragma once

#include <string>

#include <glad/gl.h>

#include "core/shadows/occlusion_frame.h"

namespace atmo::gl {

class OcclusionTextures {
 public:
  // Uploads the frame (and the tables the first time). GL current.
  bool upload(const shadows::OcclusionFrame& frame, std::string* error);
  GLuint tables() const { return tables_; }
  GLuint spheres() const { return spheres_; }
  GLuint objects() const { return objects_; }
  GLuint tiles() const { return tiles_; }
  GLuint tile_objects() const { return tile_objects_; }
  void destroy();  // GL current
  void forget();   // the GL context is gone

 private:
  GLuint tables_ = 0, spheres_ = 0, objects_ = 0, tiles_ = 0, tile_objects_ = 0;
};

}  // namespace atmo::gl
