// gl_state_guard.h — saves every piece of GL state the plugin's passes and
// uploads touch or rely on, sets the baseline they draw with, and restores it
// on scope exit: the ABI's GL state contract (docs/ABI.md, "GL state
// contract", lists what is set). The cost is a few dozen glGet calls per pass.
//
// Every plugin function that calls GL opens a guard before its first GL call
// (lazy object creation included), so nothing it binds outlives the call. The
// outermost guard on a thread also keeps the host's GL error flags: it takes
// them at entry (so check_gl sees only the plugin's errors) and raises the
// same flags again on exit (GL_OUT_OF_MEMORY and GL_STACK_OVERFLOW cannot be
// raised on purpose and are lost; docs/ABI.md).
#pragma once

#include <glad/gl.h>

namespace atmo::gl {

// Sets the blend function and equation of draw buffer 0 (of every draw
// buffer on GL 3.3, where they are one state).
void set_blend_of_buffer0(GLenum src_rgb, GLenum dst_rgb, GLenum src_alpha, GLenum dst_alpha, GLenum eq_rgb,
                          GLenum eq_alpha);

// True in a compatibility-profile context (or a pre-3.2 one), where the
// fixed-function state exists.
bool is_compatibility_context();

class GlStateGuard {
 public:
  // units: how many texture units (from 0) the caller will bind textures/samplers on.
  explicit GlStateGuard(int units);
  ~GlStateGuard();
  GlStateGuard(const GlStateGuard&) = delete;
  GlStateGuard& operator=(const GlStateGuard&) = delete;

  static constexpr int kMaxUnits = 16;  // the most units a guard saves (GL 3.3 guarantees 16 to a fragment shader)

 private:
  static constexpr int kMaxDrawBuffers = 8;
  static constexpr int kMaxHostErrors = 8;
  static constexpr int kPixelStores = 8;
  bool outermost_, compatibility_;
  GLenum host_errors_[kMaxHostErrors];
  int host_error_count_;
  int units_;
  GLint program_, vao_, array_buffer_, unpack_buffer_, active_texture_;
  GLint textures_[kMaxUnits], textures_3d_[kMaxUnits], textures_2d_array_[kMaxUnits], samplers_[kMaxUnits];
  GLint pixel_stores_[kPixelStores];
  GLint viewport_[4];
  GLboolean depth_test_, blend0_, blend1_, blend2_, cull_, stencil_, scissor_, rasterizer_discard_;
  GLboolean logic_op_, polygon_smooth_, alpha_to_coverage_, alpha_to_one_, sample_coverage_, sample_mask_;
  GLboolean alpha_test_, polygon_stipple_;  // compatibility only
  GLint clamp_fragment_color_, clamp_vertex_color_;  // compatibility only
  GLboolean clip_distance_[8];
  GLboolean depth_mask_, color_mask_[4], color_mask1_[4], color_mask2_[4];  // draw buffers 0..2 (the most a pass writes)
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
