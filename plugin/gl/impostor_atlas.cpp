#include "gl/impostor_atlas.h"

#include "gl/shader_program.h"

namespace atmo::gl {

void ImpostorAtlas::reset(int tile_texels) {
  // Chunks of another tile size cannot be reused.
  if (tile_texels != tile_) destroy();
  tile_ = tile_texels;
  used_ = 0;
}

int ImpostorAtlas::allocate(std::string* error) {
  if (used_ >= kMaxSlots) return -1;
  const size_t chunk = static_cast<size_t>(used_ / kLayersPerChunk);
  if (chunk >= chunks_.size()) {
    Chunk c;
    c.tile = tile_;
    glGenTextures(1, &c.colour);
    glGenTextures(1, &c.depth);
    glBindTexture(GL_TEXTURE_2D_ARRAY, c.colour);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAX_LEVEL, 0);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA16F, tile_, tile_, kLayersPerChunk, 0, GL_RGBA, GL_FLOAT, nullptr);
    glBindTexture(GL_TEXTURE_2D_ARRAY, c.depth);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAX_LEVEL, 0);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_R16F, tile_, tile_, kLayersPerChunk, 0, GL_RED, GL_FLOAT, nullptr);
    chunks_.push_back(c);
    if (!check_gl("allocating impostor tiles", error)) return -1;
  }
  return used_++;
}

size_t ImpostorAtlas::bytes() const {
  size_t b = 0;
  for (const Chunk& c : chunks_) b += static_cast<size_t>(c.tile) * c.tile * kLayersPerChunk * (8 + 2);
  return b;
}

void ImpostorAtlas::destroy() {
  for (const Chunk& c : chunks_) {
    glDeleteTextures(1, &c.colour);
    glDeleteTextures(1, &c.depth);
  }
  chunks_.clear();
  used_ = 0;
}

}  // namespace atmo::gl
