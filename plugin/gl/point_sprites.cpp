#include "gl/point_sprites.h"

#include <algorithm>
#include <cstdint>

#include "gl/shader_program.h"

namespace atmo::gl {

namespace {
constexpr std::size_t kMinCapacity = 1024;
// GL_POINT_SMOOTH: compatibility-profile state, absent from the core header.
constexpr GLenum kPointSmooth = 0x0B10;
}  // namespace

bool PointSprites::init(GLsizei stride, std::size_t offset0, std::size_t offset1, std::string* error) {
  if (initialised()) return true;
  GLfloat range[2] = {0.0f, 0.0f};
  glGetFloatv(GL_POINT_SIZE_RANGE, range);
  max_point_size_ = range[1];
  GLint profile = 0;
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  compatibility_ = (profile & GL_CONTEXT_COMPATIBILITY_PROFILE_BIT) != 0;
  stride_ = stride;
  glGenVertexArrays(1, &vao_);
  glGenBuffers(1, &vbo_);
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offset0));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offset1));
  if (!check_gl("creating a point pass's vertex buffer", error)) {
    destroy();
    return false;
  }
  return true;
}

void PointSprites::destroy() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (vbo_) glDeleteBuffers(1, &vbo_);
  forget();
}

void PointSprites::forget() {
  vao_ = vbo_ = 0;
  capacity_ = 0;
  max_point_size_ = 0.0f;
  compatibility_ = false;
}

void PointSprites::draw(const void* vertices, std::size_t count, const int viewport[4], int margin_px) {
  const GLboolean program_point_size = glIsEnabled(GL_PROGRAM_POINT_SIZE);
  const GLboolean point_smooth = compatibility_ ? glIsEnabled(kPointSmooth) : GL_FALSE;
  GLint scissor_box[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_SCISSOR_BOX, scissor_box);

  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  if (count > capacity_) {
    capacity_ = std::max({count, 2 * capacity_, kMinCapacity});
    ++reallocations_;
  }
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(capacity_ * stride_), nullptr, GL_STREAM_DRAW);
  glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(count * stride_), vertices);

  glEnable(GL_PROGRAM_POINT_SIZE);
  if (point_smooth) glDisable(kPointSmooth);
  const int m = margin_px;
  glViewport(viewport[0] - m, viewport[1] - m, viewport[2] + 2 * m, viewport[3] + 2 * m);
  glEnable(GL_SCISSOR_TEST);
  glScissor(viewport[0], viewport[1], viewport[2], viewport[3]);
  glBindVertexArray(vao_);
  glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(std::min<std::size_t>(count, INT32_MAX)));

  if (!program_point_size) glDisable(GL_PROGRAM_POINT_SIZE);
  if (point_smooth) glEnable(kPointSmooth);
  glScissor(scissor_box[0], scissor_box[1], scissor_box[2], scissor_box[3]);
}

}  // namespace atmo::gl
