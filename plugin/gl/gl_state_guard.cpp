#include "gl/gl_state_guard.h"

namespace atmo::gl {

namespace {
GLint get_int(GLenum name) {
  GLint v = 0;
  glGetIntegerv(name, &v);
  return v;
}
void set_enabled(GLenum cap, GLboolean on) {
  if (on) glEnable(cap); else glDisable(cap);
}
// Saves a capability and switches it off (the baseline).
[[maybe_unused]] GLboolean take_disabled(GLenum cap) {  // unused in a test fault build
  const GLboolean on = glIsEnabled(cap);
  glDisable(cap);
  return on;
}

// Compatibility-profile state, absent from the core header (and GL_INVALID_ENUM in a core context).
constexpr GLenum kAlphaTest = 0x0BC0, kPolygonStipple = 0x0B42;
constexpr GLenum kClampVertexColor = 0x891A, kClampFragmentColor = 0x891B;

// Unpacking: every pixel-store value uploads depend on, and the baseline (tight rows, no skips).
constexpr GLenum kPixelStoreNames[] = {GL_UNPACK_ALIGNMENT,   GL_UNPACK_ROW_LENGTH,   GL_UNPACK_IMAGE_HEIGHT,
                                       GL_UNPACK_SKIP_PIXELS, GL_UNPACK_SKIP_ROWS,    GL_UNPACK_SKIP_IMAGES,
                                       GL_UNPACK_SWAP_BYTES,  GL_UNPACK_LSB_FIRST};
constexpr GLint kPixelStoreBaseline[] = {4, 0, 0, 0, 0, 0, GL_FALSE, GL_FALSE};

// The guards open on this thread: only the outermost keeps the host's GL errors.
thread_local int t_guard_depth = 0;

// Raises `e` again with a call that changes no state; false for flags no call can raise safely.
[[maybe_unused]] bool raise_gl_error(GLenum e) {  // unused in a test fault build
  switch (e) {
    case GL_INVALID_ENUM: glEnable(GL_NONE); return true;
    case GL_INVALID_VALUE: glViewport(0, 0, -1, -1); return true;
    case GL_INVALID_OPERATION: {
      // No program in use: setting a uniform is an invalid operation (the guard restores the program next).
      glUseProgram(0);
      glUniform1i(0, 0);
      return true;
    }
    case GL_INVALID_FRAMEBUFFER_OPERATION: {
      // A framebuffer without attachments is incomplete: clearing it is refused (the guard rebinds the host's).
      GLuint fbo = 0;
      glGenFramebuffers(1, &fbo);
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
      glClear(GL_COLOR_BUFFER_BIT);
      glDeleteFramebuffers(1, &fbo);
      return true;
    }
    case GL_STACK_UNDERFLOW: {
      // Popping the debug group stack at its bottom (GL 4.3 / KHR_debug); not when the host has pushed groups.
      if (!(GLAD_GL_VERSION_4_3 || GLAD_GL_KHR_debug)) return false;
      if (get_int(GL_DEBUG_GROUP_STACK_DEPTH) != 1) return false;
      glPopDebugGroup();
      return true;
    }
    default: return false;  // GL_OUT_OF_MEMORY, GL_STACK_OVERFLOW, GL_CONTEXT_LOST
  }
}
}  // namespace

bool is_compatibility_context() {
  GLint profile = 0;
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  if (profile & GL_CONTEXT_COMPATIBILITY_PROFILE_BIT) return true;
  // GL 3.0/3.1 contexts have no profile mask; a core profile sets its bit.
  return (profile & GL_CONTEXT_CORE_PROFILE_BIT) == 0;
}

// Per-draw-buffer blend functions exist from GL 4.0; on 3.3 the blend
// function is one state for every draw buffer.
bool has_indexed_blend() { return GLAD_GL_VERSION_4_0 != 0; }

void set_blend_of_buffer0(GLenum src_rgb, GLenum dst_rgb, GLenum src_alpha, GLenum dst_alpha, GLenum eq_rgb,
                          GLenum eq_alpha) {
  if (has_indexed_blend()) {
    glBlendFuncSeparatei(0, src_rgb, dst_rgb, src_alpha, dst_alpha);
    glBlendEquationSeparatei(0, eq_rgb, eq_alpha);
  } else {
    glBlendFuncSeparate(src_rgb, dst_rgb, src_alpha, dst_alpha);
    glBlendEquationSeparate(eq_rgb, eq_alpha);
  }
}

GlStateGuard::GlStateGuard(int units)
    : outermost_(t_guard_depth++ == 0), host_error_count_(0), units_(units < kMaxUnits ? units : kMaxUnits) {
  // The host's pending errors, kept for the exit (each flag once; glGetError returns NO_ERROR when none is left).
  if (outermost_) {
    for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
      if (host_error_count_ == kMaxHostErrors) continue;  // draining a lost context's endless GL_CONTEXT_LOST
      host_errors_[host_error_count_++] = e;
      if (e == GL_CONTEXT_LOST) break;
    }
  }
  compatibility_ = is_compatibility_context();
  program_ = get_int(GL_CURRENT_PROGRAM);
  vao_ = get_int(GL_VERTEX_ARRAY_BINDING);
  array_buffer_ = get_int(GL_ARRAY_BUFFER_BINDING);
  unpack_buffer_ = get_int(GL_PIXEL_UNPACK_BUFFER_BINDING);
  for (int i = 0; i < kPixelStores; ++i) pixel_stores_[i] = get_int(kPixelStoreNames[i]);
  active_texture_ = get_int(GL_ACTIVE_TEXTURE);
  for (int u = 0; u < units_; ++u) {
    glActiveTexture(GL_TEXTURE0 + u);
    textures_[u] = get_int(GL_TEXTURE_BINDING_2D);
    textures_3d_[u] = get_int(GL_TEXTURE_BINDING_3D);
    textures_2d_array_[u] = get_int(GL_TEXTURE_BINDING_2D_ARRAY);
    samplers_[u] = get_int(GL_SAMPLER_BINDING);
  }
  glActiveTexture(static_cast<GLenum>(active_texture_));
  glGetIntegerv(GL_VIEWPORT, viewport_);
  depth_test_ = glIsEnabled(GL_DEPTH_TEST);
  blend0_ = glIsEnabledi(GL_BLEND, 0);
  blend1_ = glIsEnabledi(GL_BLEND, 1);
  blend2_ = glIsEnabledi(GL_BLEND, 2);
  cull_ = glIsEnabled(GL_CULL_FACE);
  stencil_ = glIsEnabled(GL_STENCIL_TEST);
  scissor_ = glIsEnabled(GL_SCISSOR_TEST);
  rasterizer_discard_ = glIsEnabled(GL_RASTERIZER_DISCARD);
  for (int i = 0; i < 8; ++i) clip_distance_[i] = glIsEnabled(GL_CLIP_DISTANCE0 + i);
  glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask_);
  glGetBooleani_v(GL_COLOR_WRITEMASK, 0, color_mask_);
  glGetBooleani_v(GL_COLOR_WRITEMASK, 1, color_mask1_);
  glGetBooleani_v(GL_COLOR_WRITEMASK, 2, color_mask2_);
  const GLenum blend_names[6] = {GL_BLEND_SRC_RGB, GL_BLEND_DST_RGB, GL_BLEND_SRC_ALPHA,
                                 GL_BLEND_DST_ALPHA, GL_BLEND_EQUATION_RGB, GL_BLEND_EQUATION_ALPHA};
  GLint* blend_values[6] = {&blend_src_rgb_, &blend_dst_rgb_, &blend_src_alpha_,
                            &blend_dst_alpha_, &blend_eq_rgb_, &blend_eq_alpha_};
  for (int i = 0; i < 6; ++i) {
    if (has_indexed_blend()) glGetIntegeri_v(blend_names[i], 0, blend_values[i]);
    else glGetIntegerv(blend_names[i], blend_values[i]);
  }
  polygon_mode_[0] = polygon_mode_[1] = GL_FILL;
  glGetIntegerv(GL_POLYGON_MODE, polygon_mode_);  // core returns one value, compatibility two
  draw_fbo_ = get_int(GL_DRAW_FRAMEBUFFER_BINDING);
  draw_buffer_count_ = 0;
  draw_buffers_changed_ = false;

  // State that changes a fragment's output, which no pass wants: saved and switched off.
#ifdef ATMO_FAULT_IGNORE_FIXED_FUNCTION  // test-only fault: a plugin that relies on the host's defaults
  compatibility_ = false;
  auto take_disabled = [](GLenum cap) { return glIsEnabled(cap); };
#endif
  logic_op_ = take_disabled(GL_COLOR_LOGIC_OP);  // on, it also disables blending
  polygon_smooth_ = take_disabled(GL_POLYGON_SMOOTH);
  alpha_to_coverage_ = take_disabled(GL_SAMPLE_ALPHA_TO_COVERAGE);
  alpha_to_one_ = take_disabled(GL_SAMPLE_ALPHA_TO_ONE);
  sample_coverage_ = take_disabled(GL_SAMPLE_COVERAGE);
  sample_mask_ = take_disabled(GL_SAMPLE_MASK);
  if (compatibility_) {
    alpha_test_ = take_disabled(kAlphaTest);
    polygon_stipple_ = take_disabled(kPolygonStipple);
    clamp_fragment_color_ = get_int(kClampFragmentColor);
    clamp_vertex_color_ = get_int(kClampVertexColor);
    glClampColor(kClampFragmentColor, GL_FALSE);  // HDR output: no clamping to [0, 1]
    glClampColor(kClampVertexColor, GL_FALSE);
  }

  // The baseline every pass draws with.
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glDisable(GL_CULL_FACE);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_RASTERIZER_DISCARD);
  for (int i = 0; i < 8; ++i) glDisable(GL_CLIP_DISTANCE0 + i);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
  for (int i = 0; i < kPixelStores; ++i) glPixelStorei(kPixelStoreNames[i], kPixelStoreBaseline[i]);
}

void GlStateGuard::use_single_draw_buffer() {
  if (draw_fbo_ == 0) return;
  GLint max_buffers = get_int(GL_MAX_DRAW_BUFFERS);
  draw_buffer_count_ = max_buffers < kMaxDrawBuffers ? max_buffers : kMaxDrawBuffers;
  bool more_than_one = false;
  for (int i = 0; i < draw_buffer_count_; ++i) {
    draw_buffers_[i] = get_int(GL_DRAW_BUFFER0 + i);
    if (i > 0 && draw_buffers_[i] != GL_NONE) more_than_one = true;
  }
  if (!more_than_one) return;
  GLenum first = static_cast<GLenum>(draw_buffers_[0]);
  glDrawBuffers(1, &first);
  draw_buffers_changed_ = true;
}

GlStateGuard::~GlStateGuard() {
  --t_guard_depth;
  if (outermost_) {
    while (glGetError() != GL_NO_ERROR) {}  // the plugin's own errors were reported (check_gl) or are not the host's
#ifndef ATMO_FAULT_DROP_HOST_GL_ERRORS  // test-only fault: a plugin that clears the host's GL errors
    for (int i = 0; i < host_error_count_; ++i) raise_gl_error(host_errors_[i]);
#endif
  }
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw_fbo_));  // first: draw buffers are its state
  if (draw_buffers_changed_) {
    GLenum buffers[kMaxDrawBuffers];
    for (int i = 0; i < draw_buffer_count_; ++i) buffers[i] = static_cast<GLenum>(draw_buffers_[i]);
    glDrawBuffers(draw_buffer_count_, buffers);
  }
#ifndef ATMO_FAULT_LEAK_GL_STATE  // test-only fault: a plugin that forgets to restore
  glUseProgram(static_cast<GLuint>(program_));
#endif
  glBindVertexArray(static_cast<GLuint>(vao_));
  glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(array_buffer_));
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(unpack_buffer_));
  for (int i = 0; i < kPixelStores; ++i) glPixelStorei(kPixelStoreNames[i], pixel_stores_[i]);
  for (int u = 0; u < units_; ++u) {
    glActiveTexture(GL_TEXTURE0 + u);
    glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(textures_[u]));
    glBindTexture(GL_TEXTURE_3D, static_cast<GLuint>(textures_3d_[u]));
    glBindTexture(GL_TEXTURE_2D_ARRAY, static_cast<GLuint>(textures_2d_array_[u]));
    glBindSampler(static_cast<GLuint>(u), static_cast<GLuint>(samplers_[u]));
  }
  glActiveTexture(static_cast<GLenum>(active_texture_));
  glViewport(viewport_[0], viewport_[1], viewport_[2], viewport_[3]);
  set_enabled(GL_DEPTH_TEST, depth_test_);
  if (blend0_) glEnablei(GL_BLEND, 0); else glDisablei(GL_BLEND, 0);
  if (blend1_) glEnablei(GL_BLEND, 1); else glDisablei(GL_BLEND, 1);
  if (blend2_) glEnablei(GL_BLEND, 2); else glDisablei(GL_BLEND, 2);
  set_enabled(GL_CULL_FACE, cull_);
  set_enabled(GL_STENCIL_TEST, stencil_);
  set_enabled(GL_SCISSOR_TEST, scissor_);
  set_enabled(GL_RASTERIZER_DISCARD, rasterizer_discard_);
  for (int i = 0; i < 8; ++i) set_enabled(GL_CLIP_DISTANCE0 + i, clip_distance_[i]);
  set_enabled(GL_COLOR_LOGIC_OP, logic_op_);
  set_enabled(GL_POLYGON_SMOOTH, polygon_smooth_);
  set_enabled(GL_SAMPLE_ALPHA_TO_COVERAGE, alpha_to_coverage_);
  set_enabled(GL_SAMPLE_ALPHA_TO_ONE, alpha_to_one_);
  set_enabled(GL_SAMPLE_COVERAGE, sample_coverage_);
  set_enabled(GL_SAMPLE_MASK, sample_mask_);
  if (compatibility_) {
    set_enabled(kAlphaTest, alpha_test_);
    set_enabled(kPolygonStipple, polygon_stipple_);
    glClampColor(kClampFragmentColor, static_cast<GLenum>(clamp_fragment_color_));
    glClampColor(kClampVertexColor, static_cast<GLenum>(clamp_vertex_color_));
  }
  glDepthMask(depth_mask_);
  glColorMaski(0, color_mask_[0], color_mask_[1], color_mask_[2], color_mask_[3]);
  glColorMaski(1, color_mask1_[0], color_mask1_[1], color_mask1_[2], color_mask1_[3]);
  glColorMaski(2, color_mask2_[0], color_mask2_[1], color_mask2_[2], color_mask2_[3]);
  set_blend_of_buffer0(static_cast<GLenum>(blend_src_rgb_), static_cast<GLenum>(blend_dst_rgb_),
                       static_cast<GLenum>(blend_src_alpha_), static_cast<GLenum>(blend_dst_alpha_),
                       static_cast<GLenum>(blend_eq_rgb_), static_cast<GLenum>(blend_eq_alpha_));
  if (polygon_mode_[0] == polygon_mode_[1]) {
    glPolygonMode(GL_FRONT_AND_BACK, static_cast<GLenum>(polygon_mode_[0]));
  } else {  // compatibility profile with different front/back modes
    glPolygonMode(GL_FRONT, static_cast<GLenum>(polygon_mode_[0]));
    glPolygonMode(GL_BACK, static_cast<GLenum>(polygon_mode_[1]));
  }
}

}  // namespace atmo::gl
