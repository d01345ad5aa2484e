// occlusion_renderer.h — the GL side of sky occlusion by the host's objects:
// a view's occluders (core/shadows OcclusionFrame) as the textures
// atmo_sky_occlusion.glsl reads (get_sky_occlusion), its tables (made once),
// and ATMO_PASS_SKY_OCCLUSION (one full-screen triangle multiplying the host's
// colour by the objects' shading of its surfaces). The program is built on
// the first pass, so a host that shades with the include never pays for it.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <glad/gl.h>

#include "core/shadows/occlusion_frame.h"
#include "gl/renderer.h"

namespace atmo::gl {

class OcclusionRenderer {
 public:
  // Uploads the frame (and the tables the first time). GL current.
  bool upload(const shadows::OcclusionFrame& frame, std::string* error);
  // ATMO_PASS_SKY_OCCLUSION over the bound framebuffer (uploads the frame first). normal_up: every surface
  // faces up (terrain), else its normal comes from the depth. reduction 1: every pixel; 4 or 8: one
  // evaluation a reduction x reduction block, spread over the block by depth.
  // no_sun: the Sun's visibility left to the host (ATMO_PASS_SKY_OCCLUSION_NO_SUN).
  bool draw(const PassInputs& in, const shadows::OcclusionFrame& frame, bool normal_up, int reduction, bool no_sun,
            std::string* error);
  // ATMO_PASS_SKY_OCCLUSION_IMAGE: the view's image for the include with ATMO_OCC_IMAGE (one AtmoOccFit a
  // reduction x reduction block, at the block's middle pixel), drawn into the plugin's own textures; the host's
  // framebuffer is untouched.
  struct Image {
    GLuint fbo = 0;
    GLuint textures[3] = {0, 0, 0};  // atmo_occ_image0..2
    int width = 0, height = 0;
    float map[4] = {0.0f, 0.0f, 0.0f, 0.0f};  // atmo_occ_image_map
  };
  // no_sun: the image holds no Sun visibility (1: ATMO_PASS_SKY_OCCLUSION_NO_SUN; the sun's part compiled out).
  bool draw_image(const PassInputs& in, const shadows::OcclusionFrame& frame, uint64_t view_key, bool normal_up,
                  int reduction, bool no_sun, std::string* error);
  const Image* image(uint64_t view_key) const;
  // The view is gone: its image is freed by the next draw_image (GL current then).
  void retire_view(uint64_t view_key) { retired_.push_back(view_key); }
  GLuint tables() const { return tables_; }
  GLuint spheres() const { return spheres_; }
  GLuint objects() const { return objects_; }
  GLuint tiles() const { return tiles_; }
  GLuint tile_objects() const { return tile_objects_; }
  void destroy();  // GL current
  void forget();   // the GL context is gone

 private:
  enum Mode { kEveryPixel = 0, kReduced = 1, kImage = 2 };
  bool build_program(bool bounce, Mode mode, std::string* error, bool no_sun = false);
  void bind_inputs(const PassInputs& in, const shadows::OcclusionFrame& frame, bool normal_up, bool no_sun);
  bool ensure_image(Image* image, int width, int height, std::string* error);
  bool ensure_reduced_target(int width, int height, std::string* error);
  GLuint tables_ = 0, spheres_ = 0, objects_ = 0, tiles_ = 0, tile_objects_ = 0;
  // The programs: [Mode][bounce] (the bounce compiled out for ATMO_OCCLUSION_NO_BOUNCE), and the upsampling.
  GLuint programs_[3][2] = {{0, 0}, {0, 0}, {0, 0}};
  GLuint image_no_sun_programs_[2] = {0, 0};  // kImage with ATMO_OCC_NO_SUN, [bounce]
  std::map<uint64_t, Image> images_;  // by view
  std::vector<uint64_t> retired_;
  GLuint upsample_program_ = 0, reduced_fbo_ = 0, reduced_texture_ = 0;
  int reduced_width_ = 0, reduced_height_ = 0;
  PassUniforms upsample_pass_;
  GLint u_reduction_ = -1, u_upsample_reduced_ = -1, u_upsample_reduction_ = -1;
  GLuint program_ = 0, vao_ = 0, linear_sampler_ = 0, nearest_sampler_ = 0;
  PassUniforms pass_;
  GLint u_tables_ = -1, u_spheres_ = -1, u_objects_ = -1, u_tiles_ = -1, u_tile_objects_ = -1;
  GLint u_tile_from_position_ = -1, u_enu_from_world_ = -1, u_grid_ = -1, u_limits_ = -1, u_sun_ = -1,
        u_sun_lux_ = -1, u_sky_sh9_ = -1, u_sun_sh9_ = -1, u_transfer_ = -1, u_normal_up_ = -1, u_no_sun_ = -1;
};

}  // namespace atmo::gl
