#include "gl/cloud_layer_renderer.h"

#include <algorithm>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "gl/shader_program.h"

namespace atmo::gl {

bool CloudLayerRenderer::init(std::string* error) {
  if (initialised()) return true;
  program_ = build_program("fullscreen.vert", "clouds_layer.frag", "", error);
  if (!program_) return false;
  auto loc = [&](const char* name) { return glGetUniformLocation(program_, name); };
  pass_ = locate_pass_uniforms(program_);
  divisor_ = loc("u_divisor");
  full_viewport_ = loc("u_full_viewport");
  tex_a_ = loc("u_layer_a");
  tex_b_ = loc("u_layer_b");
  tex_clear_ = loc("u_layer_clear");
  size_ = loc("u_layer_size");
  clouds_from_enu_ = loc("u_clouds_from_enu");
  trace_stride_ = loc("u_trace_stride");
  trace_offset_ = loc("u_trace_offset");
  level_count_ = loc("u_layer.level_count");
  level_origin_ = loc("u_layer.level_origin[0]");
  level_dims_ = loc("u_layer.level_dims[0]");
  level_bricks_ = loc("u_layer.level_bricks[0]");
  phases_ = loc("u_layer.phases[0]");
  phase_um_ = loc("u_layer.phase_um[0]");
  phase_count_ = loc("u_layer.phase_count");
  bottom_ = loc("u_layer.bottom_m");
  top_ = loc("u_layer.top_m");
  step_voxels_ = loc("u_layer.step_voxels");
  max_steps_ = loc("u_layer.max_steps");
  albedo_ = loc("u_layer.albedo");
  light_illuminance_ = loc("u_layer.light_illuminance");
  light_dir_ = loc("u_layer.light_dir");
  sky_radiance_ = loc("u_layer.sky_radiance");
  ground_radiance_ = loc("u_layer.ground_radiance");
  octaves_.locate(program_);
  return check_gl("building the cloud layer program", error);
}

void CloudLayerRenderer::destroy() {
  if (program_) glDeleteProgram(program_);
  for (GLuint t : {tex_a, tex_b, tex_clear})
    if (t) glDeleteTextures(1, &t);
  *this = CloudLayerRenderer{};
}

bool CloudLayerRenderer::upload(const clouds::CloudClipmap& clipmap, uint64_t clipmap_version, std::string* error) {
  if (tex_a && clipmap_version == uploaded_version_) return true;
  if (clipmap.levels.empty()) return true;
  const int nx = clipmap.levels[0].nx, ny = clipmap.levels[0].ny;
  int nz = 0;
  for (const clouds::ClipmapLevel& L : clipmap.levels) nz += L.nz;
  GLint max3d = 256;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3d);
  if (nx > max3d || ny > max3d || nz > max3d) {
    if (error)
      *error = "the clouds' clipmap (" + std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz) +
               " voxels) exceeds the GL 3D texture limit " + std::to_string(max3d);
    return false;
  }
  glActiveTexture(GL_TEXTURE0);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);  // a host's bound PBO would be read instead (restored by the guard)
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glPixelStorei(GL_UNPACK_IMAGE_HEIGHT, 0);
  const bool same_size = tex_a && texture_size_ == glm::vec3(nx, ny, nz);
  for (int t = 0; t < 2; ++t) {
    GLuint& tex = t == 0 ? tex_a : tex_b;
    if (!tex) glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_3D, tex);
    glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAX_LEVEL, 0);
    if (!same_size)
      glTexImage3D(GL_TEXTURE_3D, 0, t == 0 ? GL_RGBA16F : GL_RG16F, nx, ny, nz, 0, t == 0 ? GL_RGBA : GL_RG, GL_FLOAT,
                   nullptr);
    int z = 0;
    for (const clouds::ClipmapLevel& L : clipmap.levels) {
      if (t == 0)
        glTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, z, L.nx, L.ny, L.nz, GL_RGBA, GL_FLOAT, glm::value_ptr(L.a[0]));
      else
        glTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, z, L.nx, L.ny, L.nz, GL_RG, GL_FLOAT, glm::value_ptr(L.b[0]));
      z += L.nz;
    }
  }
  // The clear bricks: bytes, fetched whole (integer texels, nearest).
  const int bx = clipmap.levels[0].bx, by = clipmap.levels[0].by;
  int bz = 0;
  for (const clouds::ClipmapLevel& L : clipmap.levels) bz += L.bz;
  if (!tex_clear) glGenTextures(1, &tex_clear);
  glBindTexture(GL_TEXTURE_3D, tex_clear);
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAX_LEVEL, 0);
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  if (brick_size_ != glm::ivec3(bx, by, bz))
    glTexImage3D(GL_TEXTURE_3D, 0, GL_R8UI, bx, by, bz, 0, GL_RED_INTEGER, GL_UNSIGNED_BYTE, nullptr);
  brick_size_ = glm::ivec3(bx, by, bz);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  int z = 0;
  for (const clouds::ClipmapLevel& L : clipmap.levels) {
    glTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, z, L.bx, L.by, L.bz, GL_RED_INTEGER, GL_UNSIGNED_BYTE, L.clear.data());
    z += L.bz;
  }
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  texture_size_ = glm::vec3(nx, ny, nz);
  bytes_ = static_cast<size_t>(nx) * ny * nz * 12 + static_cast<size_t>(bx) * by * bz;
  uploaded_version_ = clipmap_version;
  return check_gl("uploading the clouds' clipmap", error);
}

void CloudLayerRenderer::use(const clouds::twin::CloudLayerMarch& m, const clouds::twin::CloudOctaves& oc,
                             const glm::mat3& clouds_from_enu, int trace_stride, glm::ivec2 trace_offset,
                             GLuint unit_a, GLuint sampler) const {
  glUseProgram(program_);
  glActiveTexture(GL_TEXTURE0 + unit_a);
  glBindTexture(GL_TEXTURE_3D, tex_a);
  glBindSampler(unit_a, sampler);
  glActiveTexture(GL_TEXTURE0 + unit_a + 1);
  glBindTexture(GL_TEXTURE_3D, tex_b);
  glBindSampler(unit_a + 1, sampler);
  glUniform1i(tex_a_, static_cast<GLint>(unit_a));
  glActiveTexture(GL_TEXTURE0 + unit_a + 2);
  glBindTexture(GL_TEXTURE_3D, tex_clear);
  glBindSampler(unit_a + 2, 0);  // its own nearest filtering (an integer texture)
  glUniform1i(tex_b_, static_cast<GLint>(unit_a + 1));
  glUniform1i(tex_clear_, static_cast<GLint>(unit_a + 2));
  glUniform3fv(size_, 1, glm::value_ptr(texture_size_));
  glUniformMatrix3fv(clouds_from_enu_, 1, GL_FALSE, glm::value_ptr(clouds_from_enu));
  glUniform1i(trace_stride_, trace_stride);
  glUniform2i(trace_offset_, trace_offset.x, trace_offset.y);
  glUniform1i(level_count_, m.level_count);
  glUniform4fv(level_origin_, CLOUD_LAYER_MAX_LEVELS, glm::value_ptr(m.level_origin[0]));
  glUniform4fv(level_dims_, CLOUD_LAYER_MAX_LEVELS, glm::value_ptr(m.level_dims[0]));
  glUniform4fv(level_bricks_, CLOUD_LAYER_MAX_LEVELS, glm::value_ptr(m.level_bricks[0]));
  glUniform4fv(phases_, CLOUD_LAYER_PHASES, glm::value_ptr(m.phases[0]));
  glUniform1fv(phase_um_, CLOUD_LAYER_PHASES, m.phase_um);
  glUniform1i(phase_count_, m.phase_count);
  glUniform1f(bottom_, m.bottom_m);
  glUniform1f(top_, m.top_m);
  glUniform1f(step_voxels_, m.step_voxels);
  glUniform1i(max_steps_, m.max_steps);
  glUniform1f(albedo_, m.albedo);
  glUniform3fv(light_illuminance_, 1, glm::value_ptr(m.light_illuminance));
  glUniform3fv(light_dir_, 1, glm::value_ptr(m.light_dir));
  glUniform3fv(sky_radiance_, 1, glm::value_ptr(m.sky_radiance));
  glUniform3fv(ground_radiance_, 1, glm::value_ptr(m.ground_radiance));
  octaves_.set(oc);
}

}  // namespace atmo::gl
