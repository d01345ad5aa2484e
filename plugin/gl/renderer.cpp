#include "gl/renderer.h"

#include <glm/gtc/type_ptr.hpp>

#include "gl/gl_state_guard.h"
#include "gl/shader_program.h"

namespace atmo::gl {

namespace {
constexpr int kSkySteps = 32;
constexpr int kAerialSteps = 16;
constexpr GLuint kTransmittanceUnit = 0;
constexpr GLuint kDepthUnit = 1;
constexpr GLuint kMultipleScatteringUnit = 2;
constexpr int kUnitsUsed = 3;

std::string gl_error_string(GLenum e) {
  switch (e) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    default: return "GL error " + std::to_string(e);
  }
}
}  // namespace

bool Renderer::init(ProcLoader loader, void* user, std::string* error) {
  if (initialised()) return true;
  int version = gladLoadGLUserPtr(loader, user);
  if (version == 0) {
    if (error) *error = "gl_init: could not load GL entry points through the host's proc-address function";
    return false;
  }
  if (GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 33) {
    if (error) *error = "gl_init: OpenGL 3.3 or later is required, the current context is " +
                        std::to_string(GLAD_VERSION_MAJOR(version)) + "." + std::to_string(GLAD_VERSION_MINOR(version));
    return false;
  }
  while (glGetError() != GL_NO_ERROR) {}  // the host's errors are not ours

  GlStateGuard guard(kUnitsUsed);
  if (!build(&sky_, "sky.frag", error) || !build(&aerial_, "aerial_perspective.frag", error)) {
    destroy();
    return false;
  }
  glGenVertexArrays(1, &vao_);
  glGenSamplers(1, &linear_sampler_);
  glSamplerParameteri(linear_sampler_, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glSamplerParameteri(linear_sampler_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glSamplerParameteri(linear_sampler_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(linear_sampler_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glGenSamplers(1, &nearest_sampler_);
  glSamplerParameteri(nearest_sampler_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glSamplerParameteri(nearest_sampler_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glSamplerParameteri(nearest_sampler_, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  glGenTextures(1, &transmittance_texture_);
  glGenTextures(1, &multiple_scattering_texture_);
  GLenum e = glGetError();
  if (e != GL_NO_ERROR) {
    if (error) *error = "gl_init: " + gl_error_string(e) + " while creating objects";
    destroy();
    return false;
  }
  return true;
}

bool Renderer::build(Program* p, const char* fragment_path, std::string* error) {
  p->program = build_program("fullscreen.vert", fragment_path, error);
  if (!p->program) return false;
  auto loc = [&](const char* name) { return glGetUniformLocation(p->program, name); };
  p->bottom_radius = loc("u_atmosphere.bottom_radius_m");
  p->top_radius = loc("u_atmosphere.top_radius_m");
  p->rayleigh_scattering = loc("u_atmosphere.rayleigh_scattering");
  p->rayleigh_scale_height = loc("u_atmosphere.rayleigh_scale_height_m");
  p->mie_scattering = loc("u_atmosphere.mie_scattering");
  p->mie_extinction = loc("u_atmosphere.mie_extinction");
  p->mie_scale_height = loc("u_atmosphere.mie_scale_height_m");
  p->mie_g = loc("u_atmosphere.mie_g");
  p->ozone_absorption = loc("u_atmosphere.ozone_absorption");
  p->ozone_center = loc("u_atmosphere.ozone_center_m");
  p->ozone_half_width = loc("u_atmosphere.ozone_half_width_m");
  p->sun_illuminance = loc("u_atmosphere.sun_illuminance_lux");
  p->sun_angular_radius = loc("u_atmosphere.sun_angular_radius");
  p->ground_albedo = loc("u_atmosphere.ground_albedo");
  p->transmittance = loc("u_transmittance");
  p->transmittance_size = loc("u_transmittance_size");
  p->multiple_scattering = loc("u_multiple_scattering");
  p->multiple_scattering_size = loc("u_multiple_scattering_size");
  p->depth = loc("u_depth");
  p->has_depth = loc("u_has_depth");
  p->depth_convention = loc("u_depth_convention");
  p->log_far = loc("u_log_far_m");
  p->log_coefficient = loc("u_log_coefficient");
  p->view_from_clip = loc("u_view_from_clip");
  p->enu_from_view = loc("u_enu_from_view");
  p->viewport = loc("u_viewport");
  p->eye_altitude = loc("u_eye_altitude_m");
  p->sun_direction = loc("u_sun_direction_enu");
  p->exposure = loc("u_exposure");
  p->output_encoding = loc("u_output_encoding");
  p->steps = loc("u_steps");
  return true;
}

void Renderer::destroy() {
  if (sky_.program) glDeleteProgram(sky_.program);
  if (aerial_.program) glDeleteProgram(aerial_.program);
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (transmittance_texture_) glDeleteTextures(1, &transmittance_texture_);
  if (multiple_scattering_texture_) glDeleteTextures(1, &multiple_scattering_texture_);
  if (linear_sampler_) glDeleteSamplers(1, &linear_sampler_);
  if (nearest_sampler_) glDeleteSamplers(1, &nearest_sampler_);
  forget();
}

void Renderer::forget() {
  sky_ = Program{};
  aerial_ = Program{};
  vao_ = transmittance_texture_ = multiple_scattering_texture_ = linear_sampler_ = nearest_sampler_ = 0;
}

void Renderer::upload_tables(const twin::Lut2D& transmittance, const twin::Lut2D& multiple_scattering) {
  GlStateGuard guard(1);
  glActiveTexture(GL_TEXTURE0);
  for (auto [texture, table] : {std::pair{transmittance_texture_, &transmittance},
                                std::pair{multiple_scattering_texture_, &multiple_scattering}}) {
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, table->width, table->height, 0, GL_RGB, GL_FLOAT, table->texels.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  }
  transmittance_size_ = glm::vec2(transmittance.width, transmittance.height);
  multiple_scattering_size_ = glm::vec2(multiple_scattering.width, multiple_scattering.height);
}

void Renderer::set_uniforms(const Program& p, const PassInputs& in, int steps) const {
  const auto& a = in.atmosphere;
  glUniform1f(p.bottom_radius, a.bottom_radius_m);
  glUniform1f(p.top_radius, a.top_radius_m);
  glUniform3fv(p.rayleigh_scattering, 1, glm::value_ptr(a.rayleigh_scattering));
  glUniform1f(p.rayleigh_scale_height, a.rayleigh_scale_height_m);
  glUniform3fv(p.mie_scattering, 1, glm::value_ptr(a.mie_scattering));
  glUniform3fv(p.mie_extinction, 1, glm::value_ptr(a.mie_extinction));
  glUniform1f(p.mie_scale_height, a.mie_scale_height_m);
  glUniform1f(p.mie_g, a.mie_g);
  glUniform3fv(p.ozone_absorption, 1, glm::value_ptr(a.ozone_absorption));
  glUniform1f(p.ozone_center, a.ozone_center_m);
  glUniform1f(p.ozone_half_width, a.ozone_half_width_m);
  glUniform3fv(p.sun_illuminance, 1, glm::value_ptr(a.sun_illuminance_lux));
  glUniform1f(p.sun_angular_radius, a.sun_angular_radius);
  glUniform3fv(p.ground_albedo, 1, glm::value_ptr(a.ground_albedo));
  glUniform1i(p.transmittance, static_cast<GLint>(kTransmittanceUnit));
  glUniform2fv(p.transmittance_size, 1, glm::value_ptr(transmittance_size_));
  glUniform1i(p.multiple_scattering, static_cast<GLint>(kMultipleScatteringUnit));
  glUniform2fv(p.multiple_scattering_size, 1, glm::value_ptr(multiple_scattering_size_));
  glUniform1i(p.depth, static_cast<GLint>(kDepthUnit));
  glUniform1i(p.has_depth, in.depth_texture != 0 ? 1 : 0);
  glUniform1i(p.depth_convention, in.depth_convention);
  glUniform1f(p.log_far, in.log_far_m);
  glUniform1f(p.log_coefficient, in.log_coefficient);
  glUniformMatrix4fv(p.view_from_clip, 1, GL_FALSE, glm::value_ptr(in.view_from_clip));
  glUniformMatrix3fv(p.enu_from_view, 1, GL_FALSE, glm::value_ptr(in.enu_from_view));
  glUniform4f(p.viewport, static_cast<float>(in.viewport[0]), static_cast<float>(in.viewport[1]),
              static_cast<float>(in.viewport[2]), static_cast<float>(in.viewport[3]));
  glUniform1f(p.eye_altitude, in.eye_altitude_m);
  glUniform3fv(p.sun_direction, 1, glm::value_ptr(in.sun_direction_enu));
  glUniform1f(p.exposure, in.exposure);
  glUniform1i(p.output_encoding, in.output_encoding);
  glUniform1i(p.steps, steps);
}

bool Renderer::draw(const Program& p, const PassInputs& in, int steps, bool dual_source_blend, std::string* error) {
  while (glGetError() != GL_NO_ERROR) {}  // errors the host left are not ours
  {
    GlStateGuard guard(kUnitsUsed);
    guard.use_single_draw_buffer();
    glUseProgram(p.program);
    set_uniforms(p, in, steps);
    glActiveTexture(GL_TEXTURE0 + kTransmittanceUnit);
    glBindTexture(GL_TEXTURE_2D, transmittance_texture_);
    glBindSampler(kTransmittanceUnit, linear_sampler_);
    glActiveTexture(GL_TEXTURE0 + kDepthUnit);
    glBindTexture(GL_TEXTURE_2D, in.depth_texture);
    glBindSampler(kDepthUnit, nearest_sampler_);
    glActiveTexture(GL_TEXTURE0 + kMultipleScatteringUnit);
    glBindTexture(GL_TEXTURE_2D, multiple_scattering_texture_);
    glBindSampler(kMultipleScatteringUnit, linear_sampler_);
    glViewport(in.viewport[0], in.viewport[1], in.viewport[2], in.viewport[3]);
    if (dual_source_blend) {
      glEnablei(GL_BLEND, 0);
      set_blend_of_buffer0(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE, GL_FUNC_ADD, GL_FUNC_ADD);
    } else {
      glDisablei(GL_BLEND, 0);
    }
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  GLenum e = glGetError();
  if (e != GL_NO_ERROR) {
    if (error) *error = gl_error_string(e) + " while drawing";
    return false;
  }
  return true;
}

bool Renderer::draw_sky(const PassInputs& in, std::string* error) {
  return draw(sky_, in, kSkySteps, false, error);
}

bool Renderer::draw_aerial_perspective(const PassInputs& in, std::string* error) {
  return draw(aerial_, in, kAerialSteps, true, error);
}

}  // namespace atmo::gl
