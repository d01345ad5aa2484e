#include "gl/fog_renderer.h"

#include <algorithm>
#include <cmath>

#include "gl/gl_state_guard.h"
#include "gl/shader_program.h"

namespace atmo::gl {

namespace {

constexpr GLuint kAirlightUnit = kPassUnitsUsed;  // after the sky passes' units
constexpr GLuint kGlowTilesUnit = kAirlightUnit + 1, kGlowListsUnit = kAirlightUnit + 2,
                 kGlowEntriesUnit = kAirlightUnit + 3;
constexpr GLuint kSmoothNearUnit = kAirlightUnit + 1, kSmoothFarUnit = kAirlightUnit + 2;  // the composite's
constexpr int kUnitsUsed = static_cast<int>(kGlowEntriesUnit) + 1;
static_assert(kUnitsUsed <= GlStateGuard::kMaxUnits, "the guard saves every unit the fog pass binds");

// A 2D texture of unfiltered texels (created on first use), under a GlStateGuard.
void texture_2d(GLuint* name, GLint format, GLsizei w, GLsizei h, GLenum layout, GLenum type, const void* data) {
  if (!*name) glGenTextures(1, name);
  glBindTexture(GL_TEXTURE_2D, *name);  // unpacking: the guard's baseline
  glTexImage2D(GL_TEXTURE_2D, 0, format, w, h, 0, layout, type, data);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}
constexpr int kInstanceFloats = 20;  // rect, light, intensity, axis, cone lobes

// Under a GlStateGuard, whose baseline unbinds any host PBO and sets tight unpacking.
void upload_r32f(GLuint* texture, const fog::FogTable& t) {
  if (!*texture) glGenTextures(1, texture);
  glBindTexture(GL_TEXTURE_2D, *texture);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, t.width, t.height, 0, GL_RED, GL_FLOAT, t.texels.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

}  // namespace

void FogRenderer::forget() {
  medium_program_ = glow_program_ = smooth_program_ = composite_program_ = seams_program_ = 0;
  seams_fbo_ = seams_near_texture_ = seams_far_texture_ = 0;
  glow_tiles_ = glow_lists_ = glow_entries_ = 0;
  smooth_fbo_ = smooth_near_ = smooth_far_ = 0;
  smooth_width_ = smooth_height_ = 0;
  airlight_table_ = surface_table_ = light_texture_ = 0;
  cluster_grid_ = far_field_ = 0;
  vao_ = instance_buffer_ = 0;
  linear_sampler_ = nearest_sampler_ = 0;
  tables_version_ = 0;
}

void FogRenderer::destroy() {
  for (GLuint p : {medium_program_, glow_program_, smooth_program_, composite_program_, seams_program_})
    if (p) glDeleteProgram(p);
  for (GLuint t : {glow_tiles_, glow_lists_, glow_entries_, smooth_near_, smooth_far_, seams_near_texture_,
                   seams_far_texture_})
    if (t) glDeleteTextures(1, &t);
  for (GLuint f : {smooth_fbo_, seams_fbo_})
    if (f) glDeleteFramebuffers(1, &f);
  for (GLuint t : {airlight_table_, surface_table_, light_texture_, cluster_grid_, far_field_})
    if (t) glDeleteTextures(1, &t);
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (instance_buffer_) glDeleteBuffers(1, &instance_buffer_);
  for (GLuint s : {linear_sampler_, nearest_sampler_})
    if (s) glDeleteSamplers(1, &s);
  forget();
}

bool FogRenderer::build_programs(std::string* error) {
  if (medium_program_) return true;
  medium_program_ = build_program("fullscreen.vert", "fog_medium.frag", "", error);
  if (!medium_program_) return false;
  glow_program_ = build_program("fog_glow.vert", "fog_glow.frag", "", error);
  if (!glow_program_) return false;
  medium_pass_ = locate_pass_uniforms(medium_program_);
  glow_pass_ = locate_pass_uniforms(glow_program_);
  medium_fog_ = glGetUniformLocation(medium_program_, "u_fog");
  medium_ambient_ = glGetUniformLocation(medium_program_, "u_fog_ambient");
  medium_fluence_ = glGetUniformLocation(medium_program_, "u_fog_fluence");
  medium_flux_ = glGetUniformLocation(medium_program_, "u_fog_flux");
  glow_table_ = glGetUniformLocation(glow_program_, "u_fog_airlight");
  glow_table_size_ = glGetUniformLocation(glow_program_, "u_fog_airlight_size");
  glow_top_ = glGetUniformLocation(glow_program_, "u_fog_top");
  glow_min_sin_ = glGetUniformLocation(glow_program_, "u_min_sin");
  glow_core_ = glGetUniformLocation(glow_program_, "u_core_sin");
  smooth_program_ = build_program("fullscreen.vert", "fog_glow_smooth.frag", "", error);
  if (!smooth_program_) return false;
  composite_program_ = build_program("fullscreen.vert", "fog_glow_composite.frag", "", error);
  if (!composite_program_) return false;
  seams_program_ = build_program("fullscreen.vert", "fog_glow_seams.frag", "", error);
  if (!seams_program_) return false;
  seams_near_ = glGetUniformLocation(seams_program_, "u_near");
  seams_far_ = glGetUniformLocation(seams_program_, "u_far");
  seams_tile_ = glGetUniformLocation(seams_program_, "u_tile");
  seams_axis_ = glGetUniformLocation(seams_program_, "u_axis");
  seams_tiles_ = glGetUniformLocation(seams_program_, "u_tiles");
  seams_tile_count_ = glGetUniformLocation(seams_program_, "u_tile_count");
  smooth_pass_ = locate_pass_uniforms(smooth_program_);
  composite_pass_ = locate_pass_uniforms(composite_program_);
  const auto at = [](GLuint program, const char* name) { return glGetUniformLocation(program, name); };
  smooth_table_ = at(smooth_program_, "u_fog_airlight");
  smooth_table_size_ = at(smooth_program_, "u_fog_airlight_size");
  smooth_top_ = at(smooth_program_, "u_fog_top");
  smooth_core_ = at(smooth_program_, "u_core_sin");
  smooth_tiles_ = at(smooth_program_, "u_tiles");
  smooth_lists_ = at(smooth_program_, "u_lists");
  smooth_glows_ = at(smooth_program_, "u_glows");
  smooth_tile_count_ = at(smooth_program_, "u_tile_count");
  smooth_divisor_ = at(smooth_program_, "u_divisor");
  composite_near_ = at(composite_program_, "u_near");
  composite_far_ = at(composite_program_, "u_far");
  composite_divisor_ = at(composite_program_, "u_divisor");
  create_pass_samplers(&linear_sampler_, &nearest_sampler_);
  glGenVertexArrays(1, &vao_);
  glGenBuffers(1, &instance_buffer_);
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, instance_buffer_);
  for (GLuint a = 0; a < 5; ++a) {
    glEnableVertexAttribArray(a);
    glVertexAttribPointer(a, 4, GL_FLOAT, GL_FALSE, kInstanceFloats * sizeof(float),
                          reinterpret_cast<const void*>(static_cast<uintptr_t>(a * 4 * sizeof(float))));
    glVertexAttribDivisor(a, 1);
  }
  return check_gl("building the fog programs", error);
}

bool FogRenderer::upload_tables(const fog::FogTable& airlight, const fog::FogTable& surface, uint64_t version,
                                std::string* error) {
  if (version == tables_version_ && airlight_table_) return true;
  GlStateGuard guard(1);
  glActiveTexture(GL_TEXTURE0);
  upload_r32f(&airlight_table_, airlight);
  upload_r32f(&surface_table_, surface);
  airlight_size_ = static_cast<float>(airlight.width);
  tables_version_ = version;
  return check_gl("uploading the fog tables", error);
}

bool FogRenderer::upload_glows(const fog::FogFrame& frame, const lights::GlowTiles& glows, float albedo,
                               std::string* error) {
  // The glows the tiles list, renumbered: the frame's lights they name, then the merged ones.
  std::vector<int32_t> renumber(frame.lights.size() + glows.merged.size(), -1);
  std::vector<float> entries;
  std::vector<uint32_t> lists(glows.lists.size());
  for (size_t k = 0; k < glows.lists.size(); ++k) {
    const uint32_t i = glows.lists[k];
    if (renumber[i] < 0) {
      renumber[i] = static_cast<int32_t>(entries.size() / 16);
      const fog::FrameLight& l = i < frame.lights.size() ? frame.lights[i] : glows.merged[i - frame.lights.size()];
      const glm::vec3 c = l.intensity_cd * albedo;
      const float t[16] = {l.position_enu_m.x, l.position_enu_m.y, l.position_enu_m.z, l.beta_per_m, c.x, c.y, c.z,
                           l.cos_inner, l.axis_enu.x, l.axis_enu.y, l.axis_enu.z, l.cos_outer, l.lobes, 0.0f, 0.0f, 0.0f};
      entries.insert(entries.end(), t, t + 16);
    }
    lists[k] = static_cast<uint32_t>(renumber[i]);
  }
  constexpr size_t kPerRow = 256, kEntriesPerRow = 4096;
  const size_t n = entries.size() / 16;
  const GLsizei rows = static_cast<GLsizei>(std::max<size_t>(1, (n + kPerRow - 1) / kPerRow));
  entries.resize(static_cast<size_t>(rows) * kPerRow * 16, 0.0f);
  const GLsizei list_rows = static_cast<GLsizei>(std::max<size_t>(1, (lists.size() + kEntriesPerRow - 1) / kEntriesPerRow));
  lists.resize(static_cast<size_t>(list_rows) * kEntriesPerRow, 0u);
  // Per tile: its first entry, its count, how many of them are merged lights (the seams pass smooths only
  // where a tile holds some), 0.
  std::vector<uint32_t> tiles(glows.offset.size() * 4, 0u);
  for (size_t t = 0; t < glows.offset.size(); ++t) {
    tiles[4 * t] = glows.offset[t];
    tiles[4 * t + 1] = glows.count[t];
    for (uint32_t k = glows.offset[t]; k < glows.offset[t] + glows.count[t]; ++k)
      tiles[4 * t + 2] += glows.lists[k] >= frame.lights.size() ? 1u : 0u;
  }
  glActiveTexture(GL_TEXTURE0 + kGlowEntriesUnit);
  texture_2d(&glow_entries_, GL_RGBA32F, static_cast<GLsizei>(4 * kPerRow), rows, GL_RGBA, GL_FLOAT, entries.data());
  glActiveTexture(GL_TEXTURE0 + kGlowListsUnit);
  texture_2d(&glow_lists_, GL_R32UI, static_cast<GLsizei>(kEntriesPerRow), list_rows, GL_RED_INTEGER, GL_UNSIGNED_INT,
             lists.data());
  glActiveTexture(GL_TEXTURE0 + kGlowTilesUnit);
  texture_2d(&glow_tiles_, GL_RGBA32UI, std::max(glows.grid.tiles_x, 1), std::max(glows.grid.tiles_y, 1),
             GL_RGBA_INTEGER, GL_UNSIGNED_INT, tiles.data());
  return check_gl("uploading the glows' tiles", error);
}

void FogRenderer::ensure_glow_textures() {
  if (glow_tiles_ && glow_lists_ && glow_entries_) return;
  GlStateGuard guard(kUnitsUsed);
  const uint32_t none[4] = {0u, 0u, 0u, 0u};
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glActiveTexture(GL_TEXTURE0);
  texture_2d(&glow_tiles_, GL_RGBA32UI, 1, 1, GL_RGBA_INTEGER, GL_UNSIGNED_INT, none);
  texture_2d(&glow_lists_, GL_R32UI, 1, 1, GL_RED_INTEGER, GL_UNSIGNED_INT, none);
  texture_2d(&glow_entries_, GL_RGBA32F, 1, 1, GL_RGBA, GL_FLOAT, zero);
}

bool FogRenderer::ensure_smooth_target(int width, int height, std::string* error) {
  if (smooth_fbo_ && width == smooth_width_ && height == smooth_height_) return true;
  if (!smooth_fbo_) glGenFramebuffers(1, &smooth_fbo_);
  glActiveTexture(GL_TEXTURE0 + kSmoothNearUnit);
  texture_2d(&smooth_near_, GL_RGBA32F, width, height, GL_RGBA, GL_FLOAT, nullptr);
  texture_2d(&smooth_far_, GL_RGBA32F, width, height, GL_RGBA, GL_FLOAT, nullptr);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, smooth_fbo_);  // (the draw binding only: the guard restores it)
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, smooth_near_, 0);
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, smooth_far_, 0);
  if (glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    if (error) *error = "the glows' reduced image is not a complete framebuffer";
    return false;
  }
  if (!seams_fbo_) glGenFramebuffers(1, &seams_fbo_);
  texture_2d(&seams_near_texture_, GL_RGBA32F, width, height, GL_RGBA, GL_FLOAT, nullptr);
  texture_2d(&seams_far_texture_, GL_RGBA32F, width, height, GL_RGBA, GL_FLOAT, nullptr);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, seams_fbo_);
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, seams_near_texture_, 0);
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, seams_far_texture_, 0);
  if (glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    if (error) *error = "the glows' seams image is not a complete framebuffer";
    return false;
  }
  smooth_width_ = width;
  smooth_height_ = height;
  return check_gl("making the glows' reduced image", error);
}

bool FogRenderer::draw(const Renderer&, const PassInputs& in, const FogDrawInputs& fog, std::string* error) {
  GlStateGuard guard(kUnitsUsed);  // first: building the programs binds the glows' VAO and buffer
  if (!build_programs(error)) return false;
  const fog::FogFrame& frame = *fog.frame;
  const lights::GlowTiles& glows = *fog.glows;
  const glm::dmat4 clip_from_view = glm::inverse(glm::dmat4(in.view_from_clip));
  const glm::dmat4 clip_from_enu = clip_from_view * glm::dmat4(glm::transpose(glm::dmat3(in.enu_from_view)));
  // The cores' rectangles and instance data.
  instances_.clear();
  stats_ = FogDrawStats{};
  stats_.lights = static_cast<int>(frame.lights.size());
  const double half_w = 0.5 * in.viewport[2], half_h = 0.5 * in.viewport[3];
  for (size_t k = 0; k < glows.cores.size(); ++k) {
    const fog::FrameLight& l = frame.lights[glows.cores[k]];
    const double d = glm::length(glm::dvec3(l.position_enu_m));
    const glm::vec4 r =
        lights::glow_rectangle(clip_from_enu, glm::dvec3(l.position_enu_m) / d, glows.core_radius_rad[k]);
    if (r.x >= r.z || r.y >= r.w) continue;  // off screen
    const float rect[4] = {r.x, r.y, r.z, r.w};
    instances_.insert(instances_.end(), rect, rect + 4);
    instances_.insert(instances_.end(), {l.position_enu_m.x, l.position_enu_m.y, l.position_enu_m.z, l.beta_per_m});
    const glm::vec3 i = l.intensity_cd * fog.albedo;
    instances_.insert(instances_.end(), {i.x, i.y, i.z, l.cos_inner});
    instances_.insert(instances_.end(), {l.axis_enu.x, l.axis_enu.y, l.axis_enu.z, l.cos_outer});
    instances_.insert(instances_.end(), {l.lobes, 0.0f, 0.0f, 0.0f});
    ++stats_.glows_drawn;
    stats_.covered_pixels += (r.z - r.x) * half_w * (r.w - r.y) * half_h;
  }
  const bool smooth = !glows.lists.empty();
  // Uploaded even when empty: the translucent surfaces' include reads this frame's glows.
  if (!upload_glows(frame, glows, fog.albedo, error)) return false;

  guard.use_single_draw_buffer();
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glActiveTexture(GL_TEXTURE0 + kDepthUnit);
  glBindTexture(GL_TEXTURE_2D, in.depth_texture);
  glBindSampler(kDepthUnit, nearest_sampler_);
  glActiveTexture(GL_TEXTURE0 + kAirlightUnit);
  glBindTexture(GL_TEXTURE_2D, airlight_table_);
  glBindSampler(kAirlightUnit, linear_sampler_);
  glBindVertexArray(vao_);

  // The glows' smooth part on the reduced image, into its own target (the host's framebuffer comes back).
  const int divisor = lights::kGlowDivisor;
  const int sw = (in.viewport[2] + divisor - 1) / divisor, sh = (in.viewport[3] + divisor - 1) / divisor;
  if (smooth) {
    GLint host_fbo = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &host_fbo);
    if (!ensure_smooth_target(sw, sh, error)) return false;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, smooth_fbo_);
    const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, buffers);
    glViewport(0, 0, sw, sh);
    glDisablei(GL_BLEND, 0);
    glDisablei(GL_BLEND, 1);
    glUseProgram(smooth_program_);
    set_pass_uniforms(smooth_pass_, in, PassTableSizes{}, 1, NightTerms{});
    glUniform1i(smooth_table_, static_cast<GLint>(kAirlightUnit));
    glUniform1f(smooth_table_size_, airlight_size_);
    glUniform1f(smooth_top_, frame.top_above_eye_m);
    glUniform1f(smooth_core_, glows.core_sin);
    glUniform1i(smooth_tiles_, static_cast<GLint>(kGlowTilesUnit));
    glUniform1i(smooth_lists_, static_cast<GLint>(kGlowListsUnit));
    glUniform1i(smooth_glows_, static_cast<GLint>(kGlowEntriesUnit));
    glUniform2f(smooth_tile_count_, float(glows.grid.tiles_x), float(glows.grid.tiles_y));
    glUniform1i(smooth_divisor_, divisor);
    const std::pair<GLuint, GLuint> bound[] = {
        {kGlowTilesUnit, glow_tiles_}, {kGlowListsUnit, glow_lists_}, {kGlowEntriesUnit, glow_entries_}};
    for (const auto& [unit, texture] : bound) {  // (ensure_smooth_target used these units)
      glActiveTexture(GL_TEXTURE0 + unit);
      glBindTexture(GL_TEXTURE_2D, texture);
      glBindSampler(unit, nearest_sampler_);
    }
    glDrawArrays(GL_TRIANGLES, 0, 3);
    // The tiles' seams smoothed, across x into the seams image, then across y back.
    glUseProgram(seams_program_);
    glUniform1i(seams_near_, static_cast<GLint>(kSmoothNearUnit));
    glUniform1i(seams_far_, static_cast<GLint>(kSmoothFarUnit));
    glUniform1i(seams_tiles_, static_cast<GLint>(kGlowEntriesUnit));
    glActiveTexture(GL_TEXTURE0 + kGlowEntriesUnit);
    glBindTexture(GL_TEXTURE_2D, glow_tiles_);
    glBindSampler(kGlowEntriesUnit, nearest_sampler_);
    glUniform2f(seams_tile_count_, float(glows.grid.tiles_x), float(glows.grid.tiles_y));
    for (int axis = 0; axis < 2; ++axis) {
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, axis == 0 ? seams_fbo_ : smooth_fbo_);
      glDrawBuffers(2, buffers);
      glActiveTexture(GL_TEXTURE0 + kSmoothNearUnit);
      glBindTexture(GL_TEXTURE_2D, axis == 0 ? smooth_near_ : seams_near_texture_);
      glBindSampler(kSmoothNearUnit, nearest_sampler_);
      glActiveTexture(GL_TEXTURE0 + kSmoothFarUnit);
      glBindTexture(GL_TEXTURE_2D, axis == 0 ? smooth_far_ : seams_far_texture_);
      glBindSampler(kSmoothFarUnit, nearest_sampler_);
      const double tile = axis == 0 ? double(in.viewport[2]) / glows.grid.tiles_x : double(in.viewport[3]) / glows.grid.tiles_y;
      glUniform1f(seams_tile_, static_cast<float>(tile / divisor));
      glUniform1i(seams_axis_, axis);
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(host_fbo));  // its draw buffers: as the guard set
    for (size_t t = 0; t < glows.count.size(); ++t)
      stats_.smooth_evaluations += double(glows.count[t]);  // per tile; times its reduced pixels below
    stats_.smooth_evaluations *= double(sw) * sh / std::max<size_t>(glows.count.size(), 1);
  }
  glViewport(in.viewport[0], in.viewport[1], in.viewport[2], in.viewport[3]);

  // The fog over the frame: colour * transmittance + its own light.
  glUseProgram(medium_program_);
  set_pass_uniforms(medium_pass_, in, PassTableSizes{}, 1, NightTerms{});
  glUniform4f(medium_fog_, fog.extinction_per_m, fog.albedo, frame.top_above_eye_m, 0.0f);
  glUniform3f(medium_ambient_, fog.ambient_cd_m2.x, fog.ambient_cd_m2.y, fog.ambient_cd_m2.z);
  glUniform3f(medium_fluence_, frame.fluence.x, frame.fluence.y, frame.fluence.z);
  glUniformMatrix3fv(medium_flux_, 1, GL_FALSE, &frame.flux_towards_lights[0][0]);
  glEnablei(GL_BLEND, 0);
  set_blend_of_buffer0(GL_ONE, GL_SRC1_COLOR, GL_ZERO, GL_ONE, GL_FUNC_ADD, GL_FUNC_ADD);
  glDrawArrays(GL_TRIANGLES, 0, 3);

  set_blend_of_buffer0(GL_ONE, GL_ONE, GL_ZERO, GL_ONE, GL_FUNC_ADD, GL_FUNC_ADD);
  // The smooth part, upsampled by depth, added.
  if (smooth) {
    glUseProgram(composite_program_);
    set_pass_uniforms(composite_pass_, in, PassTableSizes{}, 1, NightTerms{});
    glActiveTexture(GL_TEXTURE0 + kSmoothNearUnit);
    glBindTexture(GL_TEXTURE_2D, smooth_near_);
    glBindSampler(kSmoothNearUnit, nearest_sampler_);
    glActiveTexture(GL_TEXTURE0 + kSmoothFarUnit);
    glBindTexture(GL_TEXTURE_2D, smooth_far_);
    glBindSampler(kSmoothFarUnit, nearest_sampler_);
    glUniform1i(composite_near_, static_cast<GLint>(kSmoothNearUnit));
    glUniform1i(composite_far_, static_cast<GLint>(kSmoothFarUnit));
    glUniform1i(composite_divisor_, divisor);
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  // The cores, added.
  if (stats_.glows_drawn > 0) {
    glUseProgram(glow_program_);
    set_pass_uniforms(glow_pass_, in, PassTableSizes{}, 1, NightTerms{});
    glUniform1i(glow_table_, static_cast<GLint>(kAirlightUnit));
    glUniform1f(glow_table_size_, airlight_size_);
    glUniform1f(glow_top_, frame.top_above_eye_m);
    glUniform1f(glow_min_sin_, fog.min_sin);
    glUniform1f(glow_core_, glows.core_sin);
    glBindBuffer(GL_ARRAY_BUFFER, instance_buffer_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(instances_.size() * sizeof(float)), instances_.data(),
                 GL_STREAM_DRAW);
    glDrawArraysInstanced(GL_TRIANGLES, 0, 6, stats_.glows_drawn);
  }
  return check_gl("drawing the fog and glows", error);
}

bool FogRenderer::upload_host_lights(const fog::FogFrame& frame, const lights::LightClusters& clusters,
                                     const glm::dmat3& world_from_enu, std::string* error) {
  // The clusters' lights, each cluster's list in turn: 3 texels a light, 1024 a row (atmo_fog_lights.glsl).
  constexpr size_t kPerRow = 1024;
  const size_t n = clusters.lists.size();
  const GLsizei light_rows = static_cast<GLsizei>(std::max<size_t>(1, (n + kPerRow - 1) / kPerRow));
  std::vector<float> texels(static_cast<size_t>(light_rows) * kPerRow * 12, 0.0f);
  for (size_t k = 0; k < n; ++k) {
    const uint32_t i = clusters.lists[k];
    const bool own = i < frame.lights.size();
    const fog::FrameLight& l = own ? frame.lights[i] : clusters.merged[i - frame.lights.size()];
    const float range = clusters.list_range_m[k];
    const glm::vec3 p(world_from_enu * glm::dvec3(l.position_enu_m));
    const glm::vec3 axis(world_from_enu * glm::dvec3(l.axis_enu));
    const float cos_outer = l.lobes > 1.5f ? l.cos_outer + 4.0f : l.cos_outer;  // both ways: + 4
    // The axis's length is 1 + the entry's extent (a merged light's, m; 0 for a light).
    const glm::vec3 axis_extent = axis * (1.0f + l.extent_m);
    const float t[12] = {p.x, p.y, p.z, range, l.intensity_cd.x, l.intensity_cd.y, l.intensity_cd.z, l.cos_inner,
                         axis_extent.x, axis_extent.y, axis_extent.z, cos_outer};
    std::copy(t, t + 12, texels.begin() + static_cast<std::ptrdiff_t>(k * 12));
  }
  // The clusters: (first, count) per cluster, rows of tiles, slices stacked.
  const lights::ClusterGrid& g = clusters.grid;
  const GLsizei grid_w = g.tiles_x, grid_h = g.tiles_y * lights::ClusterGrid::kSlices;
  std::vector<uint32_t> grid(static_cast<size_t>(grid_w) * grid_h * 2);
  for (size_t f = 0; f < clusters.offset.size(); ++f) {
    grid[2 * f] = clusters.offset[f];
    grid[2 * f + 1] = clusters.count[f];
  }
  // The far field: the six faces (ENU at the eye), each a stack of the slices.
  const int slices = lights::ClusterGrid::kSlices, per_slice = g.tiles_x * g.tiles_y;
  constexpr int kFaces = lights::LightClusters::kFaces;
  std::vector<float> far(static_cast<size_t>(per_slice) * slices * kFaces * 4, 0.0f);
  for (int face = 0; face < kFaces; ++face)
    for (int f = 0; f < per_slice * slices; ++f) {
      const glm::vec3& e = clusters.far[face][static_cast<size_t>(f)];
      float* texel = &far[(static_cast<size_t>(face) * per_slice * slices + static_cast<size_t>(f)) * 4];
      texel[0] = e.x;
      texel[1] = e.y;
      texel[2] = e.z;
    }
  GlStateGuard guard(1);
  glActiveTexture(GL_TEXTURE0);
  texture_2d(&light_texture_, GL_RGBA32F, static_cast<GLsizei>(3 * kPerRow), light_rows, GL_RGBA, GL_FLOAT,
             texels.data());
  texture_2d(&cluster_grid_, GL_RG32UI, grid_w, grid_h, GL_RG_INTEGER, GL_UNSIGNED_INT, grid.data());
  if (!far_field_) glGenTextures(1, &far_field_);
  glBindTexture(GL_TEXTURE_3D, far_field_);
  glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA32F, g.tiles_x, g.tiles_y, kFaces * slices, 0, GL_RGBA, GL_FLOAT, far.data());
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glTexParameteri(GL_TEXTURE_3D, wrap, GL_CLAMP_TO_EDGE);
  return check_gl("uploading the host's lights", error);
}

}  // namespace atmo::gl
