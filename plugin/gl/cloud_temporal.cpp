#include "gl/cloud_temporal.h"

#include <glm/gtc/type_ptr.hpp>

#include "gl/shader_program.h"

namespace atmo::gl {

namespace {
void allocate(GLuint* texture, GLenum format, int w, int h) {
  if (!*texture) glGenTextures(1, texture);
  glBindTexture(GL_TEXTURE_2D, *texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  glTexImage2D(GL_TEXTURE_2D, 0, format, w, h, 0, format == GL_R32F ? GL_RED : GL_RGBA, GL_FLOAT, nullptr);
}
}  // namespace

bool CloudTemporal::init(std::string* error) {
  if (program_) return true;
  program_ = build_program("fullscreen.vert", "clouds_resolve.frag", "", error);
  if (!program_) return false;
  auto loc = [&](const char* name) { return glGetUniformLocation(program_, name); };
  trace_ = loc("u_trace");
  trace_depth_ = loc("u_trace_depth");
  history_ = loc("u_history");
  has_history_ = loc("u_has_history");
  offset_ = loc("u_offset");
  size_ = loc("u_size");
  view_from_clip_ = loc("u_view_from_clip");
  enu_from_view_ = loc("u_enu_from_view");
  depth_convention_ = loc("u_depth_convention");
  last_clip_from_enu_ = loc("u_last_clip_from_enu");
  return check_gl("building the clouds' resolve program", error);
}

void CloudTemporal::free_history(History& h) {
  for (GLuint& t : h.image)
    if (t) glDeleteTextures(1, &t);
  h = History{};
}

void CloudTemporal::destroy() {
  if (program_) glDeleteProgram(program_);
  for (GLuint t : {trace_colour_, trace_depth_texture_})
    if (t) glDeleteTextures(1, &t);
  for (auto& [key, h] : histories_) free_history(h);
  *this = CloudTemporal{};
}

CloudTemporal::Plan CloudTemporal::plan(uint64_t view_key, const clouds::TemporalView& now) {
  for (uint64_t key : retired_) {
    auto it = histories_.find(key);
    if (it == histories_.end()) continue;
    free_history(it->second);
    histories_.erase(it);
  }
  retired_.clear();
  History& h = histories_[view_key];
  Plan p;
  p.view_key = view_key;
  p.w = now.width;
  p.h = now.height;
  p.trace_w = (now.width + 1) / 2;
  p.trace_h = (now.height + 1) / 2;
  p.use_history = h.valid && clouds::temporal_history_usable(h.last, now);
  if (!p.use_history) h.passes = 0;
  p.offset = clouds::temporal_trace_offset(h.passes);
  return p;
}

bool CloudTemporal::begin_trace(GLuint fbo, const Plan& plan, std::string* error) {
  glActiveTexture(GL_TEXTURE0);
  if (!trace_colour_ || trace_w_ != plan.trace_w || trace_h_ != plan.trace_h) {
    allocate(&trace_colour_, GL_RGBA16F, plan.trace_w, plan.trace_h);
    allocate(&trace_depth_texture_, GL_R32F, plan.trace_w, plan.trace_h);
    trace_w_ = plan.trace_w;
    trace_h_ = plan.trace_h;
    if (!check_gl("allocating the clouds' trace target", error)) return false;
  }
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, trace_colour_, 0);
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, trace_depth_texture_, 0);
  const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glDrawBuffers(2, buffers);
  if (glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    if (error) *error = "the clouds' trace framebuffer is incomplete";
    return false;
  }
  glViewport(0, 0, plan.trace_w, plan.trace_h);
  return true;
}

bool CloudTemporal::resolve(GLuint fbo, const Plan& plan, const clouds::TemporalView& now,
                            const glm::mat4& view_from_clip, const glm::mat3& enu_from_view, int depth_convention,
                            GLuint first_unit, GLuint linear_sampler, GLuint* image, std::string* error) {
  History& h = histories_[plan.view_key];
  if (!h.image[0] || h.w != plan.w || h.h != plan.h) {
    glActiveTexture(GL_TEXTURE0 + first_unit);
    for (GLuint& t : h.image) allocate(&t, GL_RGBA16F, plan.w, plan.h);
    h.w = plan.w;
    h.h = plan.h;
    h.valid = false;
    if (!check_gl("allocating a view's cloud history", error)) return false;
  }
  const bool use_history = plan.use_history && h.valid;
  const int next = 1 - h.current;
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, h.image[next], 0);
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, 0, 0);
  const GLenum buffers[1] = {GL_COLOR_ATTACHMENT0};
  glDrawBuffers(1, buffers);
  glViewport(0, 0, plan.w, plan.h);
  glUseProgram(program_);
  const GLuint textures[3] = {trace_colour_, trace_depth_texture_, h.image[h.current]};
  const GLint samplers[3] = {trace_, trace_depth_, history_};
  for (int i = 0; i < 3; ++i) {
    glActiveTexture(GL_TEXTURE0 + first_unit + i);
    glBindTexture(GL_TEXTURE_2D, textures[i]);
    glBindSampler(first_unit + i,
                  i == 1 ? 0 : linear_sampler);  // the depth is fetched per texel
    glUniform1i(samplers[i], static_cast<GLint>(first_unit + i));
  }
  glUniform1i(has_history_, use_history ? 1 : 0);
  glUniform2i(offset_, plan.offset.x, plan.offset.y);
  glUniform2f(size_, static_cast<float>(plan.w), static_cast<float>(plan.h));
  glUniformMatrix4fv(view_from_clip_, 1, GL_FALSE, glm::value_ptr(view_from_clip));
  glUniformMatrix3fv(enu_from_view_, 1, GL_FALSE, glm::value_ptr(enu_from_view));
  glUniform1i(depth_convention_, depth_convention);
  const glm::mat4 last_clip(use_history ? clouds::last_clip_from_eye_enu(h.last, now) : glm::dmat4(1.0));
  glUniformMatrix4fv(last_clip_from_enu_, 1, GL_FALSE, glm::value_ptr(last_clip));
  glDrawArrays(GL_TRIANGLES, 0, 3);
  h.current = next;
  h.valid = true;
  h.last = now;
  h.passes = use_history ? h.passes + 1 : 1;
  *image = h.image[h.current];
  return check_gl("resolving the clouds' image", error);
}

size_t CloudTemporal::bytes() const {
  size_t b = static_cast<size_t>(trace_w_) * trace_h_ * 12;
  for (const auto& [key, h] : histories_) b += static_cast<size_t>(h.w) * h.h * 16;
  return b;
}

}  // namespace atmo::gl
