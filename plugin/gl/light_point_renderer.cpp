#include "gl/light_point_renderer.h"

#include <glm/gtc/type_ptr.hpp>

#include <cstddef>

#include "gl/gl_state_guard.h"
#include "gl/shader_program.h"

namespace atmo::gl {

void LightPointRenderer::forget() {
  program_ = linear_sampler_ = nearest_sampler_ = 0;
  sprites_.forget();
}

void LightPointRenderer::destroy() {
  if (program_) glDeleteProgram(program_);
  for (GLuint s : {linear_sampler_, nearest_sampler_})
    if (s) glDeleteSamplers(1, &s);
  sprites_.destroy();
  forget();
}

bool LightPointRenderer::build(std::string* error) {
  if (program_) return true;
  program_ = build_program("light_points.vert", "light_points.frag", "", error);
  if (!program_) return false;
  pass_ = locate_pass_uniforms(program_);
  clip_from_view_ = glGetUniformLocation(program_, "u_clip_from_view");
  view_from_enu_ = glGetUniformLocation(program_, "u_view_from_enu");
  draw_viewport_ = glGetUniformLocation(program_, "u_draw_viewport");
  sigma_ = glGetUniformLocation(program_, "u_sigma_px");
  sigma_max_ = glGetUniformLocation(program_, "u_sigma_max_px");
  create_pass_samplers(&linear_sampler_, &nearest_sampler_);
  return sprites_.init(sizeof(lights::LightPoint), offsetof(lights::LightPoint, position_enu_m),
                       offsetof(lights::LightPoint, illuminance_lux), error);
}

bool LightPointRenderer::draw(const PassInputs& in, const std::vector<lights::LightPoint>& points,
                              std::string* error) {
  if (points.empty()) return true;
  GlStateGuard guard(kPassUnitsUsed);  // first: building binds the vertex array and buffer
  if (!build(error)) return false;
  guard.use_single_draw_buffer();
  glUseProgram(program_);
  set_pass_uniforms(pass_, in, PassTableSizes{}, 1, NightTerms{});
  const glm::mat3 view_from_enu = glm::transpose(in.enu_from_view);
  const glm::mat4 clip_from_view = glm::mat4(glm::inverse(glm::dmat4(in.view_from_clip)));
  const int m = kMarginPx;
  const float draw_viewport[4] = {static_cast<float>(in.viewport[0] - m), static_cast<float>(in.viewport[1] - m),
                                  static_cast<float>(in.viewport[2] + 2 * m),
                                  static_cast<float>(in.viewport[3] + 2 * m)};
  glUniformMatrix4fv(clip_from_view_, 1, GL_FALSE, glm::value_ptr(clip_from_view));
  glUniformMatrix3fv(view_from_enu_, 1, GL_FALSE, glm::value_ptr(view_from_enu));
  glUniform4fv(draw_viewport_, 1, draw_viewport);
  glUniform1f(sigma_, kSigmaPx);
  glUniform1f(sigma_max_, kSigmaMaxPx);
  glActiveTexture(GL_TEXTURE0 + kDepthUnit);
  glBindTexture(GL_TEXTURE_2D, in.depth_texture);
  glBindSampler(kDepthUnit, nearest_sampler_);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glEnablei(GL_BLEND, 0);
  if (in.output_encoding == 1) set_blend_of_buffer0(GL_ONE, GL_ONE, GL_ONE, GL_ONE, GL_MAX, GL_MAX);
  else set_blend_of_buffer0(GL_ONE, GL_ONE, GL_ZERO, GL_ONE, GL_FUNC_ADD, GL_FUNC_ADD);
  sprites_.draw(points.data(), points.size(), in.viewport, m);
  return check_gl("drawing the light points", error);
}

}  // namespace atmo::gl
