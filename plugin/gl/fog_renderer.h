// fog_renderer.h — the GL side of ATMO_PASS_LIGHT_GLOWS and get_fog_lighting:
// the fog's tables as textures, the fog pass (one full-screen triangle:
// transmittance, ambient and diffusion light), the glows (core/lights/
// glow_tiles.h: their smooth part on an image a quarter across, per tile,
// upsampled by depth; their cores as one instanced rectangle per light), and
// the host's light and cluster textures. Programs are built on the first
// pass with fog, so a host without fog never pays for them.
#pragma once

#include <glad/gl.h>

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/fog/fog_frame.h"
#include "core/lights/glow_tiles.h"
#include "core/lights/light_clusters.h"
#include "gl/renderer.h"

namespace atmo::gl {

struct FogDrawInputs {
  const fog::FogFrame* frame = nullptr;
  const lights::GlowTiles* glows = nullptr;
  float extinction_per_m = 0.0f;
  float albedo = 1.0f;
  glm::vec3 ambient_cd_m2{0.0f};  // the fog's isotropic light from the sky, Sun and Moon
  float min_sin = 0.0f;           // floor of sin(gamma): 0.2836 of a pixel's angle (core/fog/fog_frame.h glow_min_sin)
  glm::mat4 clip_from_enu{1.0f};  // host projection * (view from the eye's ENU): the glows' rectangles
};

struct FogDrawStats {
  int lights = 0;        // lights in the frame
  int glows_drawn = 0;   // core rectangles drawn
  double covered_pixels = 0.0;  // their summed area
  double smooth_evaluations = 0.0;  // glows evaluated on the reduced image (its pixels x their tiles' lists)
};

class FogRenderer {
 public:
  FogRenderer() = default;
  FogRenderer(const FogRenderer&) = delete;
  FogRenderer& operator=(const FogRenderer&) = delete;

  // [gl-current] Deletes everything; idempotent. forget(): the context is gone (no GL call).
  void destroy();
  void forget();

  // Uploads the tables when `version` differs from the last upload.
  bool upload_tables(const fog::FogTable& airlight, const fog::FogTable& surface, uint64_t version, std::string* error);
  // The fog pass and the glows into the bound framebuffer (state restored).
  bool draw(const Renderer& renderer, const PassInputs& in, const FogDrawInputs& fog, std::string* error);
  // What the host include reads (atmo_fog_lights.glsl): the clusters' lights (each cluster's list in turn,
  // 3 RGBA32F texels a light, positions relative to the eye in the view's world axes; `world_from_enu`
  // rotates the eye's ENU into them), each cluster's first light and count, and their far fields (ENU faces).
  bool upload_host_lights(const fog::FogFrame& frame, const lights::LightClusters& clusters,
                          const glm::dmat3& world_from_enu, std::string* error);
  GLuint surface_table() const { return surface_table_; }
  GLuint light_texture() const { return light_texture_; }
  GLuint cluster_grid() const { return cluster_grid_; }
  GLuint far_field() const { return far_field_; }
  // What the translucent surfaces' include reads (atmo_fog_translucent): the airlight table and the glows of
  // the last draw (made, empty, when none was drawn yet: a host may bind them before).
  GLuint airlight_table() const { return airlight_table_; }
  void ensure_glow_textures();
  GLuint glow_tiles() const { return glow_tiles_; }
  GLuint glow_lists() const { return glow_lists_; }
  GLuint glow_entries() const { return glow_entries_; }
  const FogDrawStats& last_stats() const { return stats_; }

 private:
  bool build_programs(std::string* error);

  bool upload_glows(const fog::FogFrame& frame, const lights::GlowTiles& glows, float albedo, std::string* error);
  bool ensure_smooth_target(int width, int height, std::string* error);

  GLuint medium_program_ = 0, glow_program_ = 0, smooth_program_ = 0, composite_program_ = 0, seams_program_ = 0;
  GLint seams_near_ = -1, seams_far_ = -1, seams_tile_ = -1, seams_axis_ = -1, seams_tiles_ = -1,
        seams_tile_count_ = -1;
  PassUniforms smooth_pass_, composite_pass_;
  GLint smooth_table_ = -1, smooth_table_size_ = -1, smooth_top_ = -1, smooth_core_ = -1, smooth_tiles_ = -1,
        smooth_lists_ = -1, smooth_glows_ = -1, smooth_tile_count_ = -1, smooth_divisor_ = -1;
  GLint composite_near_ = -1, composite_far_ = -1, composite_divisor_ = -1, glow_core_ = -1;
  GLuint glow_tiles_ = 0, glow_lists_ = 0, glow_entries_ = 0;
  GLuint smooth_fbo_ = 0, smooth_near_ = 0, smooth_far_ = 0;
  GLuint seams_fbo_ = 0, seams_near_texture_ = 0, seams_far_texture_ = 0;  // the seams pass's first half
  int smooth_width_ = 0, smooth_height_ = 0;
  GLuint airlight_table_ = 0, surface_table_ = 0, light_texture_ = 0;
  GLuint cluster_grid_ = 0, far_field_ = 0;
  GLuint vao_ = 0, instance_buffer_ = 0;
  GLuint linear_sampler_ = 0, nearest_sampler_ = 0;
  uint64_t tables_version_ = 0;
  float airlight_size_ = 0.0f;
  PassUniforms medium_pass_, glow_pass_;
  GLint medium_fog_ = -1, medium_ambient_ = -1, medium_fluence_ = -1, medium_flux_ = -1;
  GLint glow_table_ = -1, glow_table_size_ = -1, glow_top_ = -1, glow_min_sin_ = -1;
  std::vector<float> instances_;
  FogDrawStats stats_;
};

}  // namespace atmo::gl
