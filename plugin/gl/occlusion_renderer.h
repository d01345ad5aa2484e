// occlusion_renderer.h — the GL side of sky occlusion by the host's objects:
// a view's occluders (core/shadows OcclusionFrame) as the textures
// atmo_sky_occlusion.glsl reads (get_sky_occlusion), its tables (made once),
// and ATMO_PASS_SKY_OCCLUSION (one full-screen triangle multiplying the host's
// colour by the objects' shading of its surfaces). The program is built on
// the first pass, so a host that shades with the include never pays for it.
#pragma once

#include <string>

#include <glad/gl.h>

#include "core/shadows/occlusion_frame.h"
#include "gl/renderer.h"

namespace atmo::gl {

class OcclusionRenderer {
 public:
  // Uploads the frame (and the tables the first time). GL current.
  bool upload(const shadows::OcclusionFrame& frame, std::string* error);
  // ATMO_PASS_SKY_OCCLUSION over the bound framebuffer (uploads the frame first). normal_up: every surface
  // faces up (terrain), else its normal comes from the depth.
  bool draw(const PassInputs& in, const shadows::OcclusionFrame& frame, bool normal_up, std::string* error);
  GLuint tables() const { return tables_; }
  GLuint spheres() const { return spheres_; }
  GLuint objects() const { return objects_; }
  GLuint tiles() const { return tiles_; }
  GLuint tile_objects() const { return tile_objects_; }
  void destroy();  // GL current
  void forget();   // the GL context is gone

 private:
  bool build_program(bool bounce, std::string* error);
  GLuint tables_ = 0, spheres_ = 0, objects_ = 0, tiles_ = 0, tile_objects_ = 0;
  // Two programs: with the bounce, and without it compiled out (ATMO_OCCLUSION_NO_BOUNCE).
  GLuint programs_[2] = {0, 0};
  GLuint program_ = 0, vao_ = 0, linear_sampler_ = 0, nearest_sampler_ = 0;
  PassUniforms pass_;
  GLint u_tables_ = -1, u_spheres_ = -1, u_objects_ = -1, u_tiles_ = -1, u_tile_objects_ = -1;
  GLint u_tile_from_position_ = -1, u_enu_from_world_ = -1, u_grid_ = -1, u_limits_ = -1, u_sun_ = -1,
        u_sun_lux_ = -1, u_sky_sh9_ = -1, u_sun_sh9_ = -1, u_transfer_ = -1, u_normal_up_ = -1;
};

}  // namespace atmo::gl
