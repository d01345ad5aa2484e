#include "atmo_support/offscreen_target.h"

#include <glad/gl.h>

#include <cstdio>
#include <cstring>

namespace atmo::support {

std::unique_ptr<OffscreenTarget> OffscreenTarget::create(int width, int height, std::string* error) {
  auto fail = [error](const std::string& msg) {
    if (error) *error = "OffscreenTarget: " + msg;
    return nullptr;
  };
  if (width <= 0 || height <= 0) return fail("width and height must be positive");
  if (!glGenFramebuffers) return fail("GL is not loaded (no current HeadlessGl?)");
  while (glGetError() != GL_NO_ERROR) {
  }

  std::unique_ptr<OffscreenTarget> t(new OffscreenTarget());
  t->width_ = width;
  t->height_ = height;

  // Keep the caller's bindings: creating a target is not a state change.
  GLint prev_tex = 0, prev_draw = 0, prev_read = 0, prev_unpack = 0;
  glGetIntegerv(GL_TEXTURE_BINDING_2D, &prev_tex);
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prev_draw);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &prev_read);
  glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &prev_unpack);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);

  auto make_texture = [&](GLenum internal, GLenum format) {
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(internal), width, height, 0, format, GL_FLOAT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    return tex;
  };
  t->color_ = make_texture(GL_RGBA32F, GL_RGBA);
  t->depth_ = make_texture(GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT);

  glGenFramebuffers(1, &t->fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, t->fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->color_, 0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, t->depth_, 0);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  const GLenum gl_error = glGetError();

  glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(prev_tex));
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(prev_draw));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(prev_read));
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(prev_unpack));

  char buf[128];
  if (gl_error != GL_NO_ERROR) {
    std::snprintf(buf, sizeof buf, "GL error 0x%04X while creating a %dx%d target", gl_error, width, height);
    return fail(buf);
  }
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    std::snprintf(buf, sizeof buf, "framebuffer incomplete (status 0x%04X)", status);
    return fail(buf);
  }
  return t;
}

OffscreenTarget::~OffscreenTarget() {
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  const GLuint textures[2] = {color_, depth_};
  glDeleteTextures(2, textures);  // zero names are ignored
}

void OffscreenTarget::bind() {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, width_, height_);
}

void OffscreenTarget::clear(float r, float g, float b, float a, float depth) {
  bind();
  const GLfloat color[4] = {r, g, b, a};
  glClearBufferfv(GL_COLOR, 0, color);
  glClearBufferfv(GL_DEPTH, 0, &depth);
}

void OffscreenTarget::read(unsigned format, int components, float* out) const {
  GLint prev_read = 0, prev_pack = 0;
  GLint pack[4] = {};
  const GLenum pack_names[4] = {GL_PACK_ALIGNMENT, GL_PACK_ROW_LENGTH, GL_PACK_SKIP_ROWS, GL_PACK_SKIP_PIXELS};
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &prev_read);
  glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &prev_pack);
  for (int i = 0; i < 4; ++i) glGetIntegerv(pack_names[i], &pack[i]);

  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  glPixelStorei(GL_PACK_SKIP_ROWS, 0);
  glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
  glReadPixels(0, 0, width_, height_, format, GL_FLOAT, out);

  glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(prev_read));
  glBindBuffer(GL_PIXEL_PACK_BUFFER, static_cast<GLuint>(prev_pack));
  for (int i = 0; i < 4; ++i) glPixelStorei(pack_names[i], pack[i]);

  // GL's row 0 is the bottom; flip so row 0 is the top.
  const size_t row = static_cast<size_t>(width_) * components;
  std::vector<float> tmp(row);
  for (int y = 0; y < height_ / 2; ++y) {
    float* a = out + static_cast<size_t>(y) * row;
    float* b = out + static_cast<size_t>(height_ - 1 - y) * row;
    std::memcpy(tmp.data(), a, row * sizeof(float));
    std::memcpy(a, b, row * sizeof(float));
    std::memcpy(b, tmp.data(), row * sizeof(float));
  }
}

Image OffscreenTarget::read_color() const {
  Image img;
  img.width = width_;
  img.height = height_;
  img.rgba.assign(img.pixel_count() * 4, 0.0f);
  read(GL_RGBA, 4, img.rgba.data());
  return img;
}

std::vector<float> OffscreenTarget::read_depth() const {
  std::vector<float> depth(static_cast<size_t>(width_) * height_, 0.0f);
  read(GL_DEPTH_COMPONENT, 1, depth.data());
  return depth;
}

}  // namespace atmo::support
