// renderer.h — the thin GL layer: owns the plugin's GL objects for one
// context and draws what the core computed. No physics here: every number a
// pass needs arrives in PassInputs, computed on the CPU in double precision.
#pragma once

#include <glad/gl.h>
#include <glm/glm.hpp>

#include <string>

#include "core/shader_twin.h"

namespace atmo::gl {

struct PassInputs {
  twin::AtmosphereParameters atmosphere;
  glm::vec3 sun_direction_enu{0.0f, 0.0f, 1.0f};
  float eye_altitude_m = 0.0f;
  glm::mat3 enu_from_view{1.0f};
  glm::mat4 view_from_clip{1.0f};
  int viewport[4] = {0, 0, 1, 1};
  GLuint depth_texture = 0;
  int depth_convention = 0;
  float log_far_m = 1.0f;
  float log_coefficient = 1.0f;
  float exposure = 1.0f;
  int output_encoding = 0;
};

class Renderer {
 public:
  using ProcLoader = GLADapiproc (*)(void* user, const char* name);

  // Loads GL through `loader` and creates programs and objects. Needs GL 3.3.
  bool init(ProcLoader loader, void* user, std::string* error);
  // Deletes GL objects (context current).
  void destroy();
  // Drops GL object names without calling GL (context lost).
  void forget();
  bool initialised() const { return sky_.program != 0; }

  // Uploads the transmittance and multiple-scattering tables (RGB32F).
  void upload_tables(const twin::Lut2D& transmittance, const twin::Lut2D& multiple_scattering);
  // Each returns false and sets *error on a GL error; state is restored either way.
  bool draw_sky(const PassInputs& in, std::string* error);
  bool draw_aerial_perspective(const PassInputs& in, std::string* error);

 private:
  struct Program {
    GLuint program = 0;
    // Uniform locations, looked up once after linking.
    GLint bottom_radius, top_radius, rayleigh_scattering, rayleigh_scale_height, mie_scattering,
        mie_extinction, mie_scale_height, mie_g, ozone_absorption, ozone_center, ozone_half_width,
        sun_illuminance, sun_angular_radius, ground_albedo;
    GLint transmittance, transmittance_size, multiple_scattering, multiple_scattering_size, depth, has_depth, depth_convention, log_far, log_coefficient,
        view_from_clip, enu_from_view, viewport, eye_altitude, sun_direction, exposure, output_encoding, steps;
  };
  bool build(Program* p, const char* fragment_path, std::string* error);
  void set_uniforms(const Program& p, const PassInputs& in, int steps) const;
  bool draw(const Program& p, const PassInputs& in, int steps, bool dual_source_blend, std::string* error);

  Program sky_, aerial_;
  GLuint vao_ = 0;
  GLuint transmittance_texture_ = 0, multiple_scattering_texture_ = 0;
  GLuint linear_sampler_ = 0, nearest_sampler_ = 0;
  glm::vec2 transmittance_size_{1.0f}, multiple_scattering_size_{1.0f};
};

}  // namespace atmo::gl
