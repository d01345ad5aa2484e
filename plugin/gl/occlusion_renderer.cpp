#include "gl/occlusion_renderer.h"

#include <algorithm>
#include <vector>

#include "gl/gl_state_guard.h"
#include "gl/pass_uniforms.h"
#include "gl/shader_program.h"

namespace atmo::gl {

namespace {

void texture_2d(GLuint* name, GLint format, GLsizei w, GLsizei h, GLenum layout, GLenum type, const void* data,
                GLint filter) {
  if (!*name) glGenTextures(1, name);
  glBindTexture(GL_TEXTURE_2D, *name);
  glTexImage2D(GL_TEXTURE_2D, 0, format, w, h, 0, layout, type, data);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

// Rows of `per_row` elements of `components` values each, padded with zeros.
template <typename T>
std::vector<T> rows_of(const T* data, size_t count, size_t components, size_t per_row, GLsizei* rows) {
  *rows = static_cast<GLsizei>(std::max<size_t>(1, (count + per_row - 1) / per_row));
  std::vector<T> out(static_cast<size_t>(*rows) * per_row * components, T(0));
  std::copy(data, data + count * components, out.begin());
  return out;
}

}  // namespace

bool OcclusionRenderer::upload(const shadows::OcclusionFrame& frame, std::string* error) {
  GlStateGuard guard(1);
  glActiveTexture(GL_TEXTURE0);
  if (!tables_) {
    const shadows::OcclusionTables& t = shadows::occlusion_tables();
    texture_2d(&tables_, GL_RGBA32F, shadows::OcclusionTables::kSize, shadows::OcclusionTables::kRows, GL_RGBA,
               GL_FLOAT, t.texels.data(), GL_LINEAR);
  }
  GLsizei rows = 0;
  const glm::vec4 none(0.0f);
  const std::vector<float> spheres =
      rows_of(&(frame.spheres.empty() ? none : frame.spheres[0]).x, frame.spheres.size(), 4, 1024, &rows);
  texture_2d(&spheres_, GL_RGBA32F, 1024, rows, GL_RGBA, GL_FLOAT, spheres.data(), GL_NEAREST);
  const std::vector<float> objects =
      rows_of(&(frame.objects.empty() ? none : frame.objects[0]).x, frame.objects.size(), 4, 1024, &rows);
  texture_2d(&objects_, GL_RGBA32F, 1024, rows, GL_RGBA, GL_FLOAT, objects.data(), GL_NEAREST);
  texture_2d(&tiles_, GL_RG32UI, frame.tiles_x, frame.tiles_y, GL_RG_INTEGER, GL_UNSIGNED_INT, frame.tiles.data(),
             GL_NEAREST);
  const uint32_t zero = 0;
  const std::vector<uint32_t> lists = rows_of(frame.tile_objects.empty() ? &zero : frame.tile_objects.data(),
                                              frame.tile_objects.size(), 1, 4096, &rows);
  texture_2d(&tile_objects_, GL_R32UI, 4096, rows, GL_RED_INTEGER, GL_UNSIGNED_INT, lists.data(), GL_NEAREST);
  return check_gl("uploading the occluders", error);
}

namespace {
// The include's textures on the units after the pass's tables.
constexpr GLuint kTablesUnit = kPassUnitsUsed, kSpheresUnit = kTablesUnit + 1, kObjectsUnit = kTablesUnit + 2,
                 kTilesUnit = kTablesUnit + 3, kTileObjectsUnit = kTablesUnit + 4;
constexpr int kUnitsUsed = static_cast<int>(kTileObjectsUnit) + 1;
static_assert(kUnitsUsed <= GlStateGuard::kMaxUnits, "the guard saves every unit the pass binds");
}  // namespace

bool OcclusionRenderer::build_program(bool bounce, Mode mode, std::string* error, bool no_sun) {
  GLuint& program = no_sun ? image_no_sun_programs_[bounce ? 1 : 0] : programs_[mode][bounce ? 1 : 0];
  if (!program) {
    const char* mode_define[3] = {"", "#define ATMO_OCC_REDUCED\n", "#define ATMO_OCC_IMAGE_PREPARE\n"};
    const std::string defines = std::string(bounce ? "" : "#define ATMO_OCC_NO_BOUNCE\n") + mode_define[mode] +
                                (no_sun ? "#define ATMO_OCC_NO_SUN\n" : "");
    program = gl::build_program("fullscreen.vert", "sky_occlusion.frag", defines, error);
    if (!program) return false;
  }
  if (program_ == program) return true;
  program_ = program;
  pass_ = locate_pass_uniforms(program_);
  const auto at = [this](const char* name) { return glGetUniformLocation(program_, name); };
  u_tables_ = at("atmo_occ_tables");
  u_spheres_ = at("atmo_occ_spheres");
  u_objects_ = at("atmo_occ_objects");
  u_tiles_ = at("atmo_occ_tiles");
  u_tile_objects_ = at("atmo_occ_tile_objects");
  u_tile_from_position_ = at("atmo_occ_tile_from_position");
  u_enu_from_world_ = at("atmo_occ_enu_from_world");
  u_grid_ = at("atmo_occ_grid");
  u_limits_ = at("atmo_occ_limits");
  u_sun_ = at("atmo_occ_sun");
  u_sun_lux_ = at("atmo_occ_sun_lux");
  u_sky_sh9_ = at("atmo_occ_sky_sh9");
  u_sun_sh9_ = at("atmo_occ_sun_sh9");
  u_transfer_ = at("atmo_occ_transfer");
  u_normal_up_ = at("u_normal_up");
  u_reduction_ = at("u_reduction");
  u_no_sun_ = at("u_no_sun");
  if (!vao_) {
    create_pass_samplers(&linear_sampler_, &nearest_sampler_);
    glGenVertexArrays(1, &vao_);
  }
  return check_gl("building the sky-occlusion program", error);
}

bool OcclusionRenderer::ensure_reduced_target(int width, int height, std::string* error) {
  if (reduced_fbo_ && width == reduced_width_ && height == reduced_height_) return true;
  if (!reduced_fbo_) glGenFramebuffers(1, &reduced_fbo_);
  glActiveTexture(GL_TEXTURE0 + kTablesUnit);  // a unit the guard restores
  texture_2d(&reduced_texture_, GL_RGBA32F, width, height, GL_RGBA, GL_FLOAT, nullptr, GL_NEAREST);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, reduced_fbo_);  // (the draw binding only: the guard restores it)
  glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, reduced_texture_, 0);
  if (glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    if (error) *error = "the sky occlusion's reduced image is not a complete framebuffer";
    return false;
  }
  reduced_width_ = width;
  reduced_height_ = height;
  return check_gl("making the sky occlusion's reduced image", error);
}

namespace {
bool frame_has_bounce(const shadows::OcclusionFrame& frame) {
  return (static_cast<int>(frame.grid.w) & 1) != 0;  // OcclusionFrame::grid.w: 1 bounce + 2 hybrid
}
}  // namespace

// The depth, the include's textures and uniforms, the pass's uniforms, for program_ (in use after).
void OcclusionRenderer::bind_inputs(const PassInputs& in, const shadows::OcclusionFrame& frame, bool normal_up,
                                    bool no_sun) {
  glActiveTexture(GL_TEXTURE0 + kDepthUnit);
  glBindTexture(GL_TEXTURE_2D, in.depth_texture);
  glBindSampler(kDepthUnit, nearest_sampler_);
  const std::pair<GLuint, GLuint> bound[] = {{kTablesUnit, tables_},
                                             {kSpheresUnit, spheres_},
                                             {kObjectsUnit, objects_},
                                             {kTilesUnit, tiles_},
                                             {kTileObjectsUnit, tile_objects_}};
  for (const auto& [unit, texture] : bound) {
    glActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(GL_TEXTURE_2D, texture);
    glBindSampler(unit, unit == kTablesUnit ? linear_sampler_ : nearest_sampler_);
  }
  glUseProgram(program_);
  set_pass_uniforms(pass_, in, PassTableSizes{}, 1, NightTerms{});
  glUniform1i(u_tables_, static_cast<GLint>(kTablesUnit));
  glUniform1i(u_spheres_, static_cast<GLint>(kSpheresUnit));
  glUniform1i(u_objects_, static_cast<GLint>(kObjectsUnit));
  glUniform1i(u_tiles_, static_cast<GLint>(kTilesUnit));
  glUniform1i(u_tile_objects_, static_cast<GLint>(kTileObjectsUnit));
  // The pass hands the include ENU positions: its "world" is ENU at the eye.
  const glm::mat4 tile_from_enu = frame.tile_from_position * glm::mat4(glm::transpose(frame.enu_from_world));
  const glm::mat3 identity(1.0f);
  glUniformMatrix4fv(u_tile_from_position_, 1, GL_FALSE, &tile_from_enu[0][0]);
  glUniformMatrix3fv(u_enu_from_world_, 1, GL_FALSE, &identity[0][0]);
  glUniform4fv(u_grid_, 1, &frame.grid[0]);
  glUniform4fv(u_limits_, 1, &frame.limits[0]);
  glUniform4fv(u_sun_, 1, &frame.sun[0]);
  glUniform3fv(u_sun_lux_, 1, &frame.sun_lux[0]);
  glUniform3fv(u_sky_sh9_, 9, frame.sky.sky_sh9.data());
  glUniform3fv(u_sun_sh9_, 9, frame.sky.sun_sh9.data());
  glUniform4fv(u_transfer_, 108, frame.sky.transfer.data());
  glUniform1i(u_normal_up_, normal_up ? 1 : 0);
  glUniform1i(u_no_sun_, no_sun ? 1 : 0);
  glBindVertexArray(vao_);
}

bool OcclusionRenderer::ensure_image(Image* image, int width, int height, std::string* error) {
  if (image->fbo && image->width == width && image->height == height) return true;
  if (!image->fbo) glGenFramebuffers(1, &image->fbo);
  glActiveTexture(GL_TEXTURE0 + kTablesUnit);  // a unit the guard restores
  for (GLuint& t : image->textures) texture_2d(&t, GL_RGBA32F, width, height, GL_RGBA, GL_FLOAT, nullptr, GL_LINEAR);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, image->fbo);  // (the draw binding only: the guard restores it)
  for (int k = 0; k < 3; ++k)
    glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(k), GL_TEXTURE_2D,
                           image->textures[k], 0);
  if (glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    if (error) *error = "the sky occlusion's image is not a complete framebuffer";
    return false;
  }
  image->width = width;
  image->height = height;
  return check_gl("making the sky occlusion's image", error);
}

bool OcclusionRenderer::draw_image(const PassInputs& in, const shadows::OcclusionFrame& frame, uint64_t view_key,
                                   bool normal_up, int reduction, bool no_sun, std::string* error) {
  GlStateGuard guard(kUnitsUsed);
  for (uint64_t key : retired_) {
    auto it = images_.find(key);
    if (it == images_.end()) continue;
    for (GLuint t : it->second.textures)
      if (t) glDeleteTextures(1, &t);
    if (it->second.fbo) glDeleteFramebuffers(1, &it->second.fbo);
    images_.erase(it);
  }
  retired_.clear();
  if (!build_program(frame_has_bounce(frame), kImage, error, no_sun) || !upload(frame, error)) return false;
  Image& image = images_[view_key];
  const int w = (in.viewport[2] + reduction - 1) / reduction, h = (in.viewport[3] + reduction - 1) / reduction;
  if (!ensure_image(&image, w, h, error)) return false;
  // Texel (i, j) is evaluated at window pixel viewport + (i, j) * reduction + reduction / 2 (its centre +0.5).
  image.map[0] = static_cast<float>(in.viewport[0] + reduction / 2) + 0.5f;
  image.map[1] = static_cast<float>(in.viewport[1] + reduction / 2) + 0.5f;
  image.map[2] = static_cast<float>(reduction);
  image.map[3] = 0.0f;
  bind_inputs(in, frame, normal_up, false);
  glUniform1i(u_reduction_, reduction);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, image.fbo);
  const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
  glDrawBuffers(3, buffers);
  glViewport(0, 0, w, h);
  for (GLuint k = 0; k < 3; ++k) {  // (buffers 0..2: the guard restores them)
    glDisablei(GL_BLEND, k);
    glColorMaski(k, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  }
  glDrawArrays(GL_TRIANGLES, 0, 3);
  return check_gl("drawing the sky occlusion's image", error);
}

const OcclusionRenderer::Image* OcclusionRenderer::image(uint64_t view_key) const {
  const auto it = images_.find(view_key);
  return it == images_.end() || !it->second.fbo ? nullptr : &it->second;
}

bool OcclusionRenderer::draw(const PassInputs& in, const shadows::OcclusionFrame& frame, bool normal_up,
                             int reduction, bool no_sun, std::string* error) {
  GlStateGuard guard(kUnitsUsed);
  const bool reduced = reduction > 1;
  if (!build_program(frame_has_bounce(frame), reduced ? kReduced : kEveryPixel, error) || !upload(frame, error))
    return false;
  if (reduced && !upsample_program_) {
    upsample_program_ = gl::build_program("fullscreen.vert", "sky_occlusion_upsample.frag", "", error);
    if (!upsample_program_) return false;
    upsample_pass_ = locate_pass_uniforms(upsample_program_);
    u_upsample_reduced_ = glGetUniformLocation(upsample_program_, "u_reduced");
    u_upsample_reduction_ = glGetUniformLocation(upsample_program_, "u_reduction");
  }
  const int rw = (in.viewport[2] + reduction - 1) / reduction, rh = (in.viewport[3] + reduction - 1) / reduction;
  GLint host_fbo = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &host_fbo);
  if (reduced && !ensure_reduced_target(rw, rh, error)) return false;
  guard.use_single_draw_buffer();
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  bind_inputs(in, frame, normal_up, no_sun);
  if (reduced) {
    // The factors at one pixel a block, into the reduced image; then spread over the host's pixels by depth.
    glUniform1i(u_reduction_, reduction);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, reduced_fbo_);
    const GLenum buffer = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &buffer);
    glViewport(0, 0, rw, rh);
    glDisablei(GL_BLEND, 0);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(host_fbo));  // its draw buffers: as the guard set
    glViewport(in.viewport[0], in.viewport[1], in.viewport[2], in.viewport[3]);
    glUseProgram(upsample_program_);
    set_pass_uniforms(upsample_pass_, in, PassTableSizes{}, 1, NightTerms{});
    glActiveTexture(GL_TEXTURE0 + kSpheresUnit);  // the spheres are not read any more: the unit takes the image
    glBindTexture(GL_TEXTURE_2D, reduced_texture_);
    glBindSampler(kSpheresUnit, nearest_sampler_);
    glUniform1i(u_upsample_reduced_, static_cast<GLint>(kSpheresUnit));
    glUniform1i(u_upsample_reduction_, reduction);
  }
  glEnablei(GL_BLEND, 0);
  // colour * factor; the host's alpha kept.
  set_blend_of_buffer0(GL_DST_COLOR, GL_ZERO, GL_ZERO, GL_ONE, GL_FUNC_ADD, GL_FUNC_ADD);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  return check_gl("drawing the objects' sky occlusion", error);
}

void OcclusionRenderer::destroy() {
  for (GLuint t : {tables_, spheres_, objects_, tiles_, tile_objects_})
    if (t) glDeleteTextures(1, &t);
  for (const auto& row : programs_)
    for (GLuint p : row)
      if (p) glDeleteProgram(p);
  if (upsample_program_) glDeleteProgram(upsample_program_);
  for (GLuint p : image_no_sun_programs_)
    if (p) glDeleteProgram(p);
  if (reduced_texture_) glDeleteTextures(1, &reduced_texture_);
  if (reduced_fbo_) glDeleteFramebuffers(1, &reduced_fbo_);
  for (auto& [key, image] : images_) {
    for (GLuint t : image.textures)
      if (t) glDeleteTextures(1, &t);
    if (image.fbo) glDeleteFramebuffers(1, &image.fbo);
  }
  if (vao_) glDeleteVertexArrays(1, &vao_);
  for (GLuint s : {linear_sampler_, nearest_sampler_})
    if (s) glDeleteSamplers(1, &s);
  forget();
}

void OcclusionRenderer::forget() {
  tables_ = spheres_ = objects_ = tiles_ = tile_objects_ = 0;
  for (auto& row : programs_) row[0] = row[1] = 0;
  image_no_sun_programs_[0] = image_no_sun_programs_[1] = 0;
  images_.clear();
  retired_.clear();
  upsample_program_ = reduced_fbo_ = reduced_texture_ = 0;
  reduced_width_ = reduced_height_ = 0;
  program_ = vao_ = linear_sampler_ = nearest_sampler_ = 0;
}

}  // namespace atmo::gl
