#include "gl/pass_uniforms.h"

#include <glm/gtc/type_ptr.hpp>

#include "gl/renderer.h"

namespace atmo::gl {

PassUniforms locate_pass_uniforms(GLuint program) {
  auto loc = [&](const char* name) { return glGetUniformLocation(program, name); };
  PassUniforms u;
  u.atmosphere = locate_atmosphere_uniforms(program);
  u.transmittance = loc("u_transmittance");
  u.transmittance_size = loc("u_transmittance_size");
  u.multiple_scattering = loc("u_multiple_scattering");
  u.multiple_scattering_size = loc("u_multiple_scattering_size");
  u.depth = loc("u_depth");
  u.has_depth = loc("u_has_depth");
  u.depth_origin = loc("u_depth_origin");
  u.depth_convention = loc("u_depth_convention");
  u.log_far = loc("u_log_far_m");
  u.log_coefficient = loc("u_log_coefficient");
  u.view_from_clip = loc("u_view_from_clip");
  u.enu_from_view = loc("u_enu_from_view");
  u.viewport = loc("u_viewport");
  u.eye_altitude = loc("u_eye_altitude_m");
  u.sun_direction = loc("u_sun_direction_enu");
  u.exposure = loc("u_exposure");
  u.output_encoding = loc("u_output_encoding");
  u.steps = loc("u_steps");
  u.sky_view = loc("u_sky_view");
  u.sky_view_size = loc("u_sky_view_size");
  u.aerial_inscatter = loc("u_aerial_inscatter");
  u.aerial_transmittance = loc("u_aerial_transmittance");
  u.aerial_range = loc("u_aerial_range_m");
  u.aerial_slices = loc("u_aerial_slices");
  u.analytic_weight = loc("u_analytic_weight");
  const char* preetham_names[6] = {"u_preetham.A", "u_preetham.B", "u_preetham.C",
                                   "u_preetham.D", "u_preetham.E", "u_preetham.zenith_Yxy"};
  for (int i = 0; i < 6; ++i) u.preetham[i] = loc(preetham_names[i]);
  u.cloud_shadow = loc("u_cloud_shadow");
  u.cloud_uv_from_eye = loc("u_cloud_shadowing.uv_from_eye_enu");
  u.cloud_base = loc("u_cloud_shadowing.base_m");
  u.cloud_top = loc("u_cloud_shadowing.top_m");
  u.cloud_enabled = loc("u_cloud_shadowing.enabled");
  u.night = locate_night_term_uniforms(program);
  return u;
}

void set_pass_uniforms(const PassUniforms& u, const PassInputs& in, const PassTableSizes& sizes, int steps,
                       const NightTerms& night) {
  set_atmosphere_uniforms(u.atmosphere, in.atmosphere);
  glUniform1i(u.transmittance, static_cast<GLint>(kTransmittanceUnit));
  glUniform2fv(u.transmittance_size, 1, glm::value_ptr(sizes.transmittance));
  glUniform1i(u.multiple_scattering, static_cast<GLint>(kMultipleScatteringUnit));
  glUniform2fv(u.multiple_scattering_size, 1, glm::value_ptr(sizes.multiple_scattering));
  glUniform1i(u.depth, static_cast<GLint>(kDepthUnit));
  glUniform1i(u.has_depth, in.depth_texture != 0 ? 1 : 0);
  glUniform2i(u.depth_origin, in.depth_origin[0], in.depth_origin[1]);
  glUniform1i(u.depth_convention, in.depth_convention);
  glUniform1f(u.log_far, in.log_far_m);
  glUniform1f(u.log_coefficient, in.log_coefficient);
  glUniformMatrix4fv(u.view_from_clip, 1, GL_FALSE, glm::value_ptr(in.view_from_clip));
  glUniformMatrix3fv(u.enu_from_view, 1, GL_FALSE, glm::value_ptr(in.enu_from_view));
  glUniform4f(u.viewport, static_cast<float>(in.viewport[0]), static_cast<float>(in.viewport[1]),
              static_cast<float>(in.viewport[2]), static_cast<float>(in.viewport[3]));
  glUniform1f(u.eye_altitude, in.eye_altitude_m);
  glUniform3fv(u.sun_direction, 1, glm::value_ptr(in.sun_direction_enu));
  glUniform1f(u.exposure, in.exposure);
  glUniform1i(u.output_encoding, in.output_encoding);
  glUniform1i(u.steps, steps);
  glUniform1i(u.sky_view, static_cast<GLint>(kSkyViewUnit));
  glUniform2fv(u.sky_view_size, 1, glm::value_ptr(sizes.sky_view));
  glUniform1i(u.aerial_inscatter, static_cast<GLint>(kAerialInscatterUnit));
  glUniform1i(u.aerial_transmittance, static_cast<GLint>(kAerialTransmittanceUnit));
  glUniform1f(u.aerial_range, in.aerial_range_m);
  glUniform1i(u.aerial_slices, in.table_sizes.aerial_slices);
  glUniform1f(u.analytic_weight, in.analytic_weight);
  const glm::vec3* c[6] = {&in.preetham.A, &in.preetham.B, &in.preetham.C,
                           &in.preetham.D, &in.preetham.E, &in.preetham.zenith_Yxy};
  for (int i = 0; i < 6; ++i) glUniform3fv(u.preetham[i], 1, glm::value_ptr(*c[i]));
  set_night_term_uniforms(u.night, night, sizes.moon_sky_scale);
  glUniform1i(u.cloud_shadow, static_cast<GLint>(kCloudShadowUnit));
  glUniformMatrix4fv(u.cloud_uv_from_eye, 1, GL_FALSE, glm::value_ptr(in.cloud_shadow.uv_from_eye_enu));
  glUniform1f(u.cloud_base, in.cloud_shadow.base_m);
  glUniform1f(u.cloud_top, in.cloud_shadow.top_m);
  glUniform1i(u.cloud_enabled, in.cloud_shadow.texture != 0 ? 1 : 0);
}

void create_pass_samplers(GLuint* linear, GLuint* nearest) {
  glGenSamplers(1, linear);
  glSamplerParameteri(*linear, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glSamplerParameteri(*linear, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glSamplerParameteri(*linear, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(*linear, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glSamplerParameteri(*linear, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  glGenSamplers(1, nearest);
  glSamplerParameteri(*nearest, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glSamplerParameteri(*nearest, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glSamplerParameteri(*nearest, GL_TEXTURE_COMPARE_MODE, GL_NONE);
}

}  // namespace atmo::gl
