// point_sprites.h — what the point passes share (the night sky's stars and
// planets, the host's lights): a streamed vertex buffer of two vec3
// attributes per point, and the draw as GL_POINTS with the host's viewport
// grown by a margin and scissored back to it (GL discards a point whose
// centre is outside the viewport, which would drop the light a point just
// outside the edge puts on the edge pixels), program point size on, and in a
// compatibility context smooth points off (they would cut the footprint's
// corners). The state a GlStateGuard does not cover is restored here.
#pragma once

#include <glad/gl.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace atmo::gl {

class PointSprites {
 public:
  // Creates the vertex array and buffer: attributes 0 and 1 are 3 floats at
  // offset0 and offset1 of a `stride`-byte vertex. GL loaded and current.
  bool init(GLsizei stride, std::size_t offset0, std::size_t offset1, std::string* error);
  void destroy();  // deletes GL objects (context current)
  void forget();   // drops GL names without GL calls (context lost)
  bool initialised() const { return vao_ != 0; }
  float max_point_size() const { return max_point_size_; }

  // Streams `count` vertices (the buffer is orphaned every draw) and draws
  // them as points with the bound program, blend and textures, into
  // `viewport` grown by margin_px on every side. Under the caller's GlStateGuard.
  void draw(const void* vertices, std::size_t count, const int viewport[4], int margin_px);

  uint64_t buffer_reallocations() const { return reallocations_; }

 private:
  GLuint vao_ = 0, vbo_ = 0;
  GLsizei stride_ = 0;
  std::size_t capacity_ = 0;  // vertices
  float max_point_size_ = 0.0f;
  bool compatibility_ = false;
  uint64_t reallocations_ = 0;
};

}  // namespace atmo::gl
