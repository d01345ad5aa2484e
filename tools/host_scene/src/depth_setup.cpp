#include "atmo_host_scene/depth_setup.h"

#include <glad/gl.h>

namespace atmo::host_scene {

namespace {
bool has_clip_control() { return GLAD_GL_VERSION_4_5 || GLAD_GL_ARB_clip_control; }
}  // namespace

bool depth_convention_supported(DepthConvention convention) {
  return convention != DepthConvention::Reversed || has_clip_control();
}

double clear_depth_value(DepthConvention convention) {
  return convention == DepthConvention::Reversed ? 0.0 : 1.0;
}

DepthSetup::DepthSetup(DepthConvention convention) {
  has_clip_control_ = has_clip_control();
  if (!depth_convention_supported(convention)) return;

  if (has_clip_control_) {
    glGetIntegerv(GL_CLIP_ORIGIN, &clip_origin_);
    glGetIntegerv(GL_CLIP_DEPTH_MODE, &clip_depth_mode_);
  }
  glGetIntegerv(GL_DEPTH_FUNC, &depth_func_);
  glGetDoublev(GL_DEPTH_CLEAR_VALUE, &clear_depth_);
  depth_test_ = glIsEnabled(GL_DEPTH_TEST);
  GLboolean mask = GL_FALSE;
  glGetBooleanv(GL_DEPTH_WRITEMASK, &mask);
  depth_mask_ = mask;

  const bool reversed = convention == DepthConvention::Reversed;
  if (has_clip_control_) {
    glClipControl(GL_LOWER_LEFT, reversed ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
  }
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glDepthFunc(reversed ? GL_GEQUAL : GL_LEQUAL);
  glClearDepth(clear_depth_value(convention));
  ok_ = true;
}

DepthSetup::~DepthSetup() {
  if (!ok_) return;
  if (has_clip_control_) glClipControl(static_cast<GLenum>(clip_origin_), static_cast<GLenum>(clip_depth_mode_));
  glDepthFunc(static_cast<GLenum>(depth_func_));
  glClearDepth(clear_depth_);
  if (depth_test_) {
    glEnable(GL_DEPTH_TEST);
  } else {
    glDisable(GL_DEPTH_TEST);
  }
  glDepthMask(depth_mask_ ? GL_TRUE : GL_FALSE);
}

}  // namespace atmo::host_scene
