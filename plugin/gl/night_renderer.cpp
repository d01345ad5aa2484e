#include "gl/night_renderer.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "core/night_sky/star_photometry.h"
#include "gl/gl_state_guard.h"
#include "gl/pass_uniforms.h"
#include "gl/shader_program.h"

namespace atmo::gl {

namespace {
constexpr int kUnitsUsed = kPassUnitsUsed;
}  // namespace

int NightRenderer::point_size_px() { return 2 * core::night::kStarFootprintRadiusPx + 1; }

bool NightRenderer::init(std::string* error) {
  if (initialised()) return true;
  if (glCreateProgram == nullptr) {
    if (error) *error = "night renderer: GL is not loaded (initialise the Renderer first)";
    return false;
  }
  GlStateGuard guard(kUnitsUsed);
  for (int m = 0; m < kMethods; ++m) {
    if (!build(&programs_[m], static_cast<SkyMethod>(m), error)) {
      destroy();
      return false;
    }
  }
  std::string sprites_error;
  if (!sprites_.init(sizeof(core::night::PointSource), offsetof(core::night::PointSource, direction_enu),
                     offsetof(core::night::PointSource, illuminance_rgb_lux), &sprites_error)) {
    if (error) *error = "night renderer: " + sprites_error;
    destroy();
    return false;
  }
  create_pass_samplers(&linear_sampler_, &nearest_sampler_);
  std::string gl_error;
  if (!check_gl("creating the night renderer's objects", &gl_error)) {
    if (error) *error = "night renderer: " + gl_error;
    destroy();
    return false;
  }
  return true;
}

bool NightRenderer::build(Program* p, SkyMethod method, std::string* error) {
  const std::string defines = "#define ATMO_METHOD " + std::to_string(static_cast<int>(method)) + "\n";
  p->program = build_program("night_points.vert", "night_points.frag", defines, error);
  if (!p->program) return false;
  auto loc = [&](const char* name) { return glGetUniformLocation(p->program, name); };
  p->pass = locate_pass_uniforms(p->program);
  p->clip_from_view = loc("u_clip_from_view");
  p->view_from_enu = loc("u_view_from_enu");
  p->draw_viewport = loc("u_draw_viewport");
  p->point_size = loc("u_point_size");
  p->footprint_sigma = loc("u_footprint_sigma_px");
  return true;
}

void NightRenderer::destroy() {
  for (Program& p : programs_)
    if (p.program) glDeleteProgram(p.program);
  sprites_.destroy();
  if (linear_sampler_) glDeleteSamplers(1, &linear_sampler_);
  if (nearest_sampler_) glDeleteSamplers(1, &nearest_sampler_);
  forget();
}

void NightRenderer::forget() {
  for (Program& p : programs_) p = Program{};
  sprites_.forget();
  linear_sampler_ = nearest_sampler_ = 0;
}

bool NightRenderer::draw_points(const PassInputs& in, const NightSkyTextures& textures,
                                const core::night::PointSource* sources, std::size_t count, std::string* error) {
  if (count == 0 || sources == nullptr) return true;  // nothing to draw: no GL call
  if (!initialised()) {
    if (error) *error = "night renderer: not initialised";
    return false;
  }
  const float point_size = static_cast<float>(point_size_px());
  if (sprites_.max_point_size() < point_size) {
    if (error) *error = "night renderer: the GL implementation's largest point (" + std::to_string(sprites_.max_point_size()) +
                        " px) is smaller than the star footprint (" + std::to_string(point_size) + " px)";
    return false;
  }
  if (count > static_cast<std::size_t>(INT32_MAX)) count = static_cast<std::size_t>(INT32_MAX);
  GlStateGuard outer(kUnitsUsed);  // keeps the host's GL errors

  const Program& p = programs_[static_cast<int>(in.method)];
  const glm::mat3 view_from_enu = glm::transpose(in.enu_from_view);
  const glm::mat4 clip_from_view = glm::mat4(glm::inverse(glm::dmat4(in.view_from_clip)));
  const int m = kViewportMarginPx;
  const float draw_viewport[4] = {static_cast<float>(in.viewport[0] - m), static_cast<float>(in.viewport[1] - m),
                                  static_cast<float>(in.viewport[2] + 2 * m),
                                  static_cast<float>(in.viewport[3] + 2 * m)};
  const bool display = in.output_encoding == 1;
  {
    GlStateGuard guard(kUnitsUsed);
    guard.use_single_draw_buffer();
    glUseProgram(p.program);
    // The sky under a star, as the sky pass drew it (display output only): its night terms too.
    NightTerms night = display ? in.night : NightTerms{};
    night.moonlit_sky = night.moonlit_sky && textures.moon_sky_view != 0;
    const PassTableSizes sizes{textures.transmittance_size, textures.multiple_scattering_size, textures.sky_view_size,
                               textures.moon_sky_scale};
    set_pass_uniforms(p.pass, in, sizes, in.table_sizes.march_sky_steps, night);
    glUniformMatrix4fv(p.clip_from_view, 1, GL_FALSE, glm::value_ptr(clip_from_view));
    glUniformMatrix3fv(p.view_from_enu, 1, GL_FALSE, glm::value_ptr(view_from_enu));
    glUniform4fv(p.draw_viewport, 1, draw_viewport);
    glUniform1f(p.point_size, point_size);
    glUniform1f(p.footprint_sigma, static_cast<float>(core::night::kStarFootprintSigmaPx));

    auto bind = [](GLuint unit, GLuint texture, GLuint sampler) {
      glActiveTexture(GL_TEXTURE0 + unit);
      glBindTexture(GL_TEXTURE_2D, texture);
      glBindSampler(unit, sampler);
    };
    bind(kTransmittanceUnit, textures.transmittance, linear_sampler_);
    bind(kDepthUnit, in.depth_texture, nearest_sampler_);
    bind(kMultipleScatteringUnit, display ? textures.multiple_scattering : 0, linear_sampler_);
    bind(kSkyViewUnit, display ? textures.sky_view : 0, linear_sampler_);
    bind(kMoonSkyViewUnit, display ? textures.moon_sky_view : 0, linear_sampler_);

    glEnablei(GL_BLEND, 0);
    if (display) set_blend_of_buffer0(GL_ONE, GL_ONE, GL_ONE, GL_ONE, GL_MAX, GL_MAX);
    else set_blend_of_buffer0(GL_ONE, GL_ONE, GL_ZERO, GL_ONE, GL_FUNC_ADD, GL_FUNC_ADD);
    sprites_.draw(sources, count, in.viewport, m);
  }
  ++counters_.draws;
  counters_.sources_drawn += count;
  counters_.buffer_reallocations = sprites_.buffer_reallocations();
  return check_gl("drawing the night sky's point sources", error);
}

}  // namespace atmo::gl
