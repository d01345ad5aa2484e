#include "gl/occlusion_textures.h"

#include <algorithm>
#include <vector>

#include "gl/gl_state_guard.h"
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

bool OcclusionTextures::upload(const shadows::OcclusionFrame& frame, std::string* error) {
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

void OcclusionTextures::destroy() {
  for (GLuint t : {tables_, spheres_, objects_, tiles_, tile_objects_})
    if (t) glDeleteTextures(1, &t);
  forget();
}

void OcclusionTextures::forget() { tables_ = spheres_ = objects_ = tiles_ = tile_objects_ = 0; }

}  // namespace atmo::gl
