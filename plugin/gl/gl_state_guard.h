// gl_state_guard.h — saves every piece of GL state the plugin's passes and
// uploads touch, and restores it on scope exit: the ABI's GL state contract.
// It saves exactly what Renderer changes (see the list in the .cpp), so the
// cost is a few dozen glGet calls per pass.
#pragma once

#include <glad/gl.h>

namespace atmo::gl {

// Sets the blend function and equation of draw buffer 0 (of every draw
// buffer on GL 3.3, where they are one state).
void set_blend_of_buffer0(GLenum src_rgb, GLenum dst_rgb, GLenum src_alpha, GLenum dst_alpha, GLenum eq_rgb,
                          GLenum eq_alpha);

class GlStateGuard {
 public:
  // units: how many texture units (from 0) the caller will bind textures/samplers on.
  explicit GlStateGuard(int units);
  ~GlStateGuard();
  GlStateGuard(const GlStateGuard&) = delete;
  GlStateGuard& operator=(const GlStateGuard&) = delete;

 private:
  static constexpr int kMaxUnits = 12;
  static constexpr int kMaxDrawBuffers = 8;
  int units_;
  GLint program_, vao_, array_buffer_, unpack_buffer_, active_texture_;
  GLint textures_[kMaxUnits], textures_3d_[kMaxUnits], textures_2d_array_[kMaxUnits], samplers_[kMaxUnits];
  GLint unpack_alignment_, unpack_row_length_;
  GLint viewport_[4];
  GLboolean depth_test_, blend0_, blend1_, cull_, stencil_, scissor_, rasterizer_discard_;
  GLboolean clip_distance_[8];
  GLboolean depth_mask_, color_mask_[4], color_mask1_[4];
  GLint blend_src_rgb_, blend_dst_rgb_, blend_src_alpha_, blend_dst_alpha_, blend_eq_rgb_, blend_eq_alpha_;
  GLint polygon_mode_[2];
  GLint draw_fbo_;
  GLint draw_buffers_[kMaxDrawBuffers];
  int draw_buffer_count_;
  bool draw_buffers_changed_;

 public:
  // Restricts the bound user framebuffer to draw buffer 0 (dual-source blending
  // allows one); restored on exit. No-op for the default framebuffer.
  void use_single_draw_buffer();
  // Binds the caller's draw framebuffer again (after drawing into the plugin's own).
  void restore_draw_framebuffer() const { glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw_fbo_)); }
};

}  // namespace atmo::gl
