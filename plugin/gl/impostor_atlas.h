// impostor_atlas.h — where the clouds' impostors live on the GPU: square
// tiles in 2D array textures (RGBA16F radiance and coverage, R16F depth
// offset), in chunks of kLayersPerChunk layers allocated as clouds need them,
// up to a cap. A slot is a tile; slots are never moved, so an impostor stays
// where it was rendered until the field changes (reset).
#pragma once

#include <glad/gl.h>

#include <string>
#include <vector>

namespace atmo::gl {

class ImpostorAtlas {
 public:
  static constexpr int kLayersPerChunk = 64;
  static constexpr int kMaxSlots = 1024;  // 160 MB at 128 texels: the memory budget (docs/CLOUDS.md)

  // Forgets every slot and sets the tile size (GL objects kept until destroy).
  void reset(int tile_texels);
  // A new slot, or -1 when the cap (or GL memory) is reached.
  int allocate(std::string* error);
  void destroy();
  void forget() { *this = ImpostorAtlas{}; }

  int tile_texels() const { return tile_; }
  GLuint colour(int slot) const { return chunks_[static_cast<size_t>(slot / kLayersPerChunk)].colour; }
  GLuint depth(int slot) const { return chunks_[static_cast<size_t>(slot / kLayersPerChunk)].depth; }
  static int layer(int slot) { return slot % kLayersPerChunk; }
  static int chunk(int slot) { return slot / kLayersPerChunk; }
  int slots_used() const { return used_; }
  size_t bytes() const;

 private:
  struct Chunk {
    GLuint colour = 0, depth = 0;
    int tile = 0;
  };
  std::vector<Chunk> chunks_;
  int tile_ = 128;
  int used_ = 0;
};

}  // namespace atmo::gl
