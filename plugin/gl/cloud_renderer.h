// cloud_renderer.h — the clouds' GL objects and draw: every prototype's
// density and light grids in one 3D atlas (RGBA16F), the march at reduced
// resolution into an offscreen image, and its composite over the host's
// frame. No physics here: the march is shaders/clouds/cloud_march.glsl, its
// inputs come from abi/cloud_inputs on the CPU.
#pragma once

#include <glad/gl.h>

#include <string>
#include <vector>

#include "core/clouds/cloud_field.h"
#include "core/clouds/cloud_lighting.h"
#include "core/clouds/cloud_twin.h"
#include "gl/pass_uniforms.h"

namespace atmo::gl {

struct PassInputs;
class Renderer;

// One frame of clouds, in the view's ENU axes at the eye.
struct CloudFrameInputs {
  const clouds::CloudField* field = nullptr;
  const std::vector<clouds::LightDepths>* depths = nullptr;
  uint64_t version = 0;               // re-upload when it changes
  glm::dvec3 eye_in_clouds_m{0.0};    // the eye in the clouds' frame
  glm::dmat3 eye_enu_from_clouds{1.0};
  clouds::CloudLight light;           // in the clouds' frame
  clouds::twin::CloudPhase phase{};
  clouds::twin::CloudOctaves octaves{};
  int divisor = 2;
  float step_voxels = 1.0f;
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

  // For benchmarks and logs.
  size_t atlas_bytes() const { return atlas_bytes_; }
  int last_instances_drawn() const { return last_drawn_; }

 private:
  struct MarchProgram {
    GLuint program = 0;
    PassUniforms pass;
    GLint atlas = -1, atlas_size = -1, instances = -1, instance_count = -1, light_illuminance = -1,
          sky_radiance = -1, ground_radiance = -1, step_voxels = -1, max_steps = -1, divisor = -1,
          full_viewport = -1;
    GLint phase[4] = {-1, -1, -1, -1};
    GLint octaves[5] = {-1, -1, -1, -1, -1};
  };
  bool upload_atlas(const CloudFrameInputs& frame, std::string* error);
  bool ensure_target(int width, int height, std::string* error);

  MarchProgram march_;
  GLuint composite_ = 0;
  GLint composite_clouds_ = -1, composite_viewport_ = -1;
  GLuint vao_ = 0, fbo_ = 0, target_ = 0, atlas_ = 0, linear_sampler_ = 0, border_sampler_ = 0;
  int target_w_ = 0, target_h_ = 0;
  glm::vec3 atlas_size_{1.0f};
  std::vector<glm::vec3> atlas_offsets_;  // per prototype, voxels
  uint64_t uploaded_version_ = 0;
  size_t atlas_bytes_ = 0;
  int last_drawn_ = 0;
};

}  // namespace atmo::gl
