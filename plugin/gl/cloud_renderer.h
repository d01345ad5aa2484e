// cloud_renderer.h — the clouds' GL objects and draw: every prototype's
// density and light grids in one 3D atlas (RGBA16F); far clouds drawn from
// impostors (Harris & Lastra 2001: billboards rendered from the volume, kept
// while the view of them changes less than a threshold, re-rendered within a
// per-frame budget); near clouds and the one the eye is in by the direct
// march, cross-faded with their impostors over a band; both at reduced
// resolution into one offscreen image, composited over the host's frame.
// No physics here: the march is shaders/clouds/cloud_march.glsl, the choices
// core/clouds/impostor_policy, the inputs abi/cloud_inputs.
#pragma once

#include <glad/gl.h>

#include <array>
#include <string>
#include <vector>

#include "core/clouds/cloud_field.h"
#include "core/clouds/cloud_lighting.h"
#include "core/clouds/cloud_optics.h"
#include "core/clouds/cloud_shadow.h"
#include "core/clouds/cloud_twin.h"
#include "core/clouds/impostor_policy.h"
#include "core/scene/state_hash.h"
#include "gl/cloud_layer_renderer.h"
#include "gl/cloud_octave_uniforms.h"
#include "gl/cloud_temporal.h"
#include "gl/impostor_atlas.h"
#include "gl/pass_uniforms.h"

namespace atmo::gl {

struct PassInputs;
class Renderer;
class GlStateGuard;

// One frame of clouds, in the view's ENU axes at the eye.
struct CloudFrameInputs {
  const clouds::CloudField* field = nullptr;
  const std::vector<clouds::LightDepths>* depths = nullptr;
  uint64_t version = 0;               // the field or its light changed: re-upload, impostors stale
  uint64_t field_version = 0;         // the field changed: impostors start over
  glm::dvec3 eye_in_clouds_m{0.0};    // the eye in the clouds' frame
  glm::dmat3 eye_enu_from_clouds{1.0};
  clouds::CloudLight light;           // in the clouds' frame
  clouds::twin::CloudOctaves octaves{};
  int divisor = 2;
  float step_voxels = 1.0f;
  bool direct_only = false;           // the reference: every cloud by the direct march
  bool layer = false;                 // the layer march over `clipmap` (ATMO_CLOUD_DRAW_LAYER)
  const clouds::CloudClipmap* clipmap = nullptr;
  uint64_t clipmap_version = 0;       // changes with the clipmap's content (re-upload)
  int layer_max_steps = 192;          // the layer march's step budget per pixel
  bool temporal = false;              // layer: trace a quarter of the pixels, reproject the rest (gl/cloud_temporal)
  uint64_t view_key = 0;              // temporal: whose history
  clouds::TemporalView temporal_view; // temporal: the view's camera (the renderer adds the eye and image)
  clouds::ImpostorSettings impostors;
  // Impostors are the context's, not a view's: made once a host frame (or when this eye or the clouds' light
  // change) for every cloud, from one eye (the first view's of the frame), so every view and every channel of
  // any process layout draws the same impostors (docs/MULTI_CHANNEL.md).
  uint64_t host_frame = 0;
  glm::dvec3 impostor_eye_in_clouds_m{0.0};
  glm::dmat3 impostor_eye_enu_from_clouds{1.0};
};

// What the last draw did, for tests, benchmarks and logs.
struct CloudDrawStats {
  int in_view = 0;           // clouds in the view frustum
  int impostors_drawn = 0;   // drawn from an impostor (weight > 0)
  int marched = 0;           // drawn by the direct march (weight > 0)
  // The impostors' update, when this draw made it (the first of its host frame; else 0):
  int impostors_created = 0; // rendered for the first time
  int impostors_updated = 0; // re-rendered (stale, within the budget)
  int impostors_stale = 0;   // past a threshold and left for later frames
};

class CloudRenderer {
 public:
  bool initialised() const { return march_.program != 0; }
  // Builds the programs on first use (a host without clouds never pays).
  bool init(std::string* error);
  void destroy();
  void forget();
  // Draws the clouds over the bound framebuffer. *drawn = false when no cloud was in view.
  bool draw(Renderer& renderer, const PassInputs& in, const CloudFrameInputs& frame, bool* drawn, std::string* error);

  // The clouds' shadow map as a GL texture (R16F, linear, clamped), uploaded
  // when (field_version, shadow_version) changes. [gl-current]
  bool shadow_texture(const clouds::CloudShadowMap& map, uint64_t field_version, uint64_t shadow_version,
                      GLuint* texture, std::string* error);

  size_t atlas_bytes() const { return atlas_bytes_; }
  size_t impostor_bytes() const { return impostors_.bytes(); }
  size_t layer_bytes() const { return layer_.texture_bytes() + temporal_.bytes(); }
  // The view is gone: its cloud history is freed on the next draw. [no-gl]
  void retire_view(uint64_t view_key) { temporal_.retire(view_key); }
  const CloudDrawStats& last_stats() const { return stats_; }
  // What the impostors hold (which are made, from which eye) at the start of host frame `frame`, for the state
  // hash: before that frame's update, whichever view's pass made it.
  void hash_state(uint64_t frame, core::StateHasher* h) const;

 private:
  // The uniforms of cloud_instance.glsl, in each program that includes it.
  struct InstanceUniforms {
    GLint atlas = -1, atlas_size = -1, instances = -1, instance_count = -1, light_illuminance = -1,
          sky_radiance = -1, ground_radiance = -1, step_voxels = -1, max_steps = -1;
    OctaveUniforms octaves;
  };
  struct MarchProgram {
    GLuint program = 0;
    PassUniforms pass;
    InstanceUniforms cloud;
    GLint divisor = -1, full_viewport = -1;
  };
  struct BakeProgram {
    GLuint program = 0;
    InstanceUniforms cloud;
    GLint board_centre = -1, board_right = -1, board_up = -1, radiance_scale = -1, tile_texels = -1;
  };
  struct BoardProgram {
    GLuint program = 0;
    PassUniforms pass;
    GLint boards = -1, clip_from_enu = -1, ndc_scale = -1, colour = -1, depth = -1, divisor = -1,
          full_viewport = -1;
  };
  // Per instance of the field: its impostor.
  struct Impostor {
    int slot = -1;
    bool baked = false;
    uint64_t version = 0;              // CloudFrameInputs::version it was rendered with
    glm::dvec3 baked_eye_m{0.0};       // clouds' frame
    clouds::Billboard board;           // clouds' frame
  };
  struct Item;

  bool upload_atlas(const CloudFrameInputs& frame, std::string* error);
  // Every cloud's impostor brought up to date from the reference eye, once a host frame (or eye, or light).
  bool update_impostors(const CloudFrameInputs& frame, std::string* error);
  void set_draw_state() const;
  // Binds and clears the low-resolution image as the draw target.
  bool begin_image(int w, int h, std::string* error);
  bool use_pass_program(Renderer& renderer, const PassInputs& in, GLuint program, const PassUniforms& pass,
                        GLint divisor, GLint full_viewport, int w, int h, int d, std::string* error);
  // Puts `image` (the low-resolution w x h image) over the host's frame.
  void composite(const PassInputs& in, GlStateGuard& guard, GLuint image, int w, int h, int d);
  bool ensure_target(int width, int height, std::string* error);
  void set_cloud_uniforms(const InstanceUniforms& u, const CloudFrameInputs& frame) const;
  // Appends instance `index`'s kVec4PerInstance vec4s (cloud_instance.glsl).
  void pack_instance(const CloudFrameInputs& frame, size_t index, float weight, std::vector<glm::vec4>* out) const;
  bool bake(const CloudFrameInputs& frame, size_t index, std::string* error);
  void draw_boards(const PassInputs& in, const CloudFrameInputs& frame, const std::vector<Item>& far, int d);
  void march(const CloudFrameInputs& frame, const std::vector<Item>& near);

  MarchProgram march_;
  BakeProgram bake_;
  BoardProgram board_;
  GLuint composite_ = 0;
  GLint composite_clouds_ = -1, composite_viewport_ = -1, composite_encoding_ = -1;
  GLuint vao_ = 0, fbo_ = 0, bake_fbo_ = 0, target_ = 0, atlas_ = 0, linear_sampler_ = 0, border_sampler_ = 0;
  int target_w_ = 0, target_h_ = 0;
  glm::vec3 atlas_size_{1.0f};
  std::vector<glm::vec3> atlas_offsets_;  // per prototype, voxels
  std::vector<clouds::twin::CloudPhase> phases_;  // per prototype
  uint64_t uploaded_version_ = 0;
  size_t atlas_bytes_ = 0;
  ImpostorAtlas impostors_;
  CloudLayerRenderer layer_;
  CloudTemporal temporal_;
  GLuint shadow_ = 0;
  uint64_t shadow_field_version_ = 0, shadow_version_ = 0;
  std::vector<Impostor> impostor_of_;     // per instance
  bool impostors_updated_once_ = false;
  uint64_t impostor_frame_ = 0, impostor_light_version_ = 0;  // what the last update was made for
  glm::dvec3 impostor_eye_m_{0.0};
  CloudDrawStats impostor_stats_;          // its counts
  // impostor_hash() as the first draw of host frame before_frame_ found it (before it changed anything).
  bool have_before_ = false;
  uint64_t before_frame_ = 0, impostors_before_update_ = 0;
  uint64_t impostor_hash() const;
  uint64_t impostor_field_version_ = 0;
  CloudDrawStats stats_;
};

}  // namespace atmo::gl
