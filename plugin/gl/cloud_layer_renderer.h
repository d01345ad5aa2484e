// cloud_layer_renderer.h — the layer march's GL objects and draw: the
// clipmap's levels stacked along z in two 3D textures (RGBA16F + RG16F,
// 12 bytes a voxel) and their clear bricks in a third (R8UI), uploaded when the clipmap changes, and one full-screen
// draw of clouds_layer.frag into the clouds' low-resolution image (which
// CloudRenderer owns and composites). No physics here: the march is
// shaders/clouds/cloud_layer_march.glsl, the clipmap core/clouds/cloud_clipmap.
#pragma once

#include <glad/gl.h>

#include <array>
#include <string>

#include "core/clouds/cloud_clipmap.h"
#include "core/clouds/cloud_optics.h"
#include "gl/cloud_octave_uniforms.h"
#include "gl/pass_uniforms.h"

namespace atmo::gl {

class CloudLayerRenderer {
 public:
  bool initialised() const { return program_ != 0; }
  bool init(std::string* error);
  void destroy();
  // Uploads the clipmap when clipmap_version changed. [gl-current]
  bool upload(const clouds::CloudClipmap& clipmap, uint64_t clipmap_version, std::string* error);
  // The program, with the march's uniforms set (the caller sets pass_common's
  // and draws): textures on units `unit_a` to `unit_a + 2`. trace_stride 2
  // traces pixel 2 * fragment + trace_offset of the image (gl/cloud_temporal).
  void use(const clouds::twin::CloudLayerMarch& march, const clouds::twin::CloudOctaves& octaves,
           const glm::mat3& clouds_from_enu, int trace_stride, glm::ivec2 trace_offset, GLuint unit_a,
           GLuint sampler) const;
  GLuint program() const { return program_; }
  const PassUniforms& pass() const { return pass_; }
  GLint divisor_uniform() const { return divisor_; }
  GLint full_viewport_uniform() const { return full_viewport_; }
  size_t texture_bytes() const { return bytes_; }

 private:
  GLuint program_ = 0;
  PassUniforms pass_;
  GLint divisor_ = -1, full_viewport_ = -1, tex_a_ = -1, tex_b_ = -1, tex_clear_ = -1, size_ = -1,
        clouds_from_enu_ = -1, trace_stride_ = -1, trace_offset_ = -1;
  GLint level_count_ = -1, level_origin_ = -1, level_dims_ = -1, level_bricks_ = -1, phases_ = -1, phase_um_ = -1,
        phase_count_ = -1, bottom_ = -1, top_ = -1, step_voxels_ = -1, max_steps_ = -1, albedo_ = -1,
        light_illuminance_ = -1, light_dir_ = -1, sky_radiance_ = -1, ground_radiance_ = -1;
  OctaveUniforms octaves_;
  GLuint tex_a = 0, tex_b = 0, tex_clear = 0;
  glm::vec3 texture_size_{1.0f};
  glm::ivec3 brick_size_{0};
  uint64_t uploaded_version_ = 0;
  size_t bytes_ = 0;
};

}  // namespace atmo::gl
