// An offscreen framebuffer for rendering tests and the CLI: RGBA32F colour and
// DEPTH_COMPONENT32F depth, both GL_TEXTURE_2D with NEAREST filtering.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "atmo_support/image.h"

namespace atmo::support {

class OffscreenTarget {
 public:
  // Needs a current GL context (which must stay current while the target
  // lives). Returns nullptr with *error set if the FBO is incomplete or GL fails.
  static std::unique_ptr<OffscreenTarget> create(int width, int height, std::string* error = nullptr);
  ~OffscreenTarget();
  OffscreenTarget(const OffscreenTarget&) = delete;
  OffscreenTarget& operator=(const OffscreenTarget&) = delete;

  unsigned fbo() const { return fbo_; }
  unsigned color_texture() const { return color_; }
  unsigned depth_texture() const { return depth_; }
  int width() const { return width_; }
  int height() const { return height_; }

  // Binds the FBO to GL_FRAMEBUFFER and sets the viewport to the whole target.
  void bind();
  // bind(), then clears colour and depth with glClearBuffer* (the clear values
  // of the GL state are untouched; scissor and write masks apply as usual).
  void clear(float r, float g, float b, float a, float depth = 1.0f);

  // Reads back the colour/depth attachment; row 0 is the TOP of the image.
  // Read framebuffer, pack buffer and pack pixel-store state are restored.
  Image read_color() const;
  std::vector<float> read_depth() const;  // width*height floats, row 0 = top

 private:
  OffscreenTarget() = default;
  void read(unsigned format, int components, float* out) const;

  unsigned fbo_ = 0, color_ = 0, depth_ = 0;
  int width_ = 0, height_ = 0;
};

}  // namespace atmo::support
