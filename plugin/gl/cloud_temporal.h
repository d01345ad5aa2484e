// cloud_temporal.h — the layer march's temporal upsampling, GL half: the
// quarter-size target a frame's fresh pixels are traced into (colour and the
// clouds' depth), each view's image history (two RGBA16F images, ping-pong),
// and the resolve draw (shaders/clouds_resolve.frag). The choices (which
// pixels, when a history is kept, the reprojection) are
// core/clouds/cloud_temporal; nothing here depends on another view.
#pragma once

#include <glad/gl.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/clouds/cloud_temporal.h"

namespace atmo::gl {

class CloudTemporal {
 public:
  // This frame of a view: which pixel of each 2x2 block is traced, into a
  // trace_w x trace_h target, and whether its last image is reprojected.
  struct Plan {
    uint64_t view_key = 0;
    bool use_history = false;
    glm::ivec2 offset{0};
    int w = 0, h = 0;              // the clouds' image
    int trace_w = 0, trace_h = 0;  // ceil(w / 2), ceil(h / 2)
  };

  bool init(std::string* error);
  void destroy();
  // Decides the frame (core/clouds/cloud_temporal.h) and frees the histories
  // of retired views. [gl-current]
  Plan plan(uint64_t view_key, const clouds::TemporalView& now);
  // Attaches the trace target (colour 0, depth 1) to `fbo` and binds it (the
  // trace writes every texel). [gl-current]
  bool begin_trace(GLuint fbo, const Plan& plan, std::string* error);
  // Draws the view's new image into its history from the trace; *image is it.
  // Units first_unit .. first_unit + 2. [gl-current]
  bool resolve(GLuint fbo, const Plan& plan, const clouds::TemporalView& now, const glm::mat4& view_from_clip,
               const glm::mat3& enu_from_view, int depth_convention, GLuint first_unit, GLuint linear_sampler,
               GLuint* image, std::string* error);
  // The view is gone: its history is freed at the next plan (no GL here).
  void retire(uint64_t view_key) { retired_.push_back(view_key); }
  size_t bytes() const;

 private:
  struct History {
    GLuint image[2] = {0, 0};
    int current = 0;
    int w = 0, h = 0;
    bool valid = false;
    uint64_t passes = 0;  // since the last reset: keys the traced pixel
    clouds::TemporalView last;
  };
  static void free_history(History& h);

  GLuint program_ = 0;
  GLint trace_ = -1, trace_depth_ = -1, history_ = -1, has_history_ = -1, offset_ = -1, size_ = -1,
        view_from_clip_ = -1, enu_from_view_ = -1, depth_convention_ = -1, last_clip_from_enu_ = -1;
  GLuint trace_colour_ = 0, trace_depth_texture_ = 0;
  int trace_w_ = 0, trace_h_ = 0;
  std::map<uint64_t, History> histories_;
  std::vector<uint64_t> retired_;
};

}  // namespace atmo::gl
