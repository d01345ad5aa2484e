#include "atmo_host_scene/sky_occlusion_binding.h"

namespace atmo::host_scene {

namespace {

// The include's samplers in unit order (all GL_TEXTURE_2D).
constexpr const char* kSamplers[SkyOcclusionBinding::kUnits] = {"atmo_occ_tables", "atmo_occ_spheres", "atmo_occ_objects",
                                                                "atmo_occ_tiles", "atmo_occ_tile_objects"};
// With ATMO_OCC_IMAGE: the image's three (the last two units stay unbound).
constexpr const char* kImageSamplers[SkyOcclusionBinding::kUnits] = {"atmo_occ_image0", "atmo_occ_image1",
                                                                     "atmo_occ_image2", "", ""};

void uniform4(GLuint program, const char* name, const double v[4]) {
  glUniform4f(glGetUniformLocation(program, name), float(v[0]), float(v[1]), float(v[2]), float(v[3]));
}

}  // namespace

SkyOcclusionBinding::SkyOcclusionBinding(GLuint program, const AtmoSkyOcclusion& o, int first_unit)
    : first_unit_(first_unit) {
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active_);
  // The include compiled with ATMO_OCC_IMAGE reads the image (three textures), ENU axes and the sky's SH9 only.
  const bool image = glGetUniformLocation(program, "atmo_occ_image0") >= 0;
  const GLuint textures[kUnits] = {o.tables, o.spheres, o.objects, o.tiles, o.tile_objects};
  const GLuint image_textures[kUnits] = {o.image[0], o.image[1], o.image[2], 0, 0};
  for (int u = 0; u < kUnits; ++u) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(first_unit + u));
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &previous_[u]);
    glBindTexture(GL_TEXTURE_2D, image ? image_textures[u] : textures[u]);
    glUniform1i(glGetUniformLocation(program, image ? kImageSamplers[u] : kSamplers[u]), first_unit + u);
  }
  float m4[16], m3[9];
  for (int k = 0; k < 16; ++k) m4[k] = static_cast<float>(o.tile_from_position[k]);
  for (int k = 0; k < 9; ++k) m3[k] = static_cast<float>(o.enu_from_world[k]);
  glUniformMatrix3fv(glGetUniformLocation(program, "atmo_occ_enu_from_world"), 1, GL_FALSE, m3);
  glUniform3fv(glGetUniformLocation(program, "atmo_occ_sky_sh9"), 9, o.sky_sh9);
  if (image) {
    uniform4(program, "atmo_occ_image_map", o.image_map);
    return;
  }
  glUniformMatrix4fv(glGetUniformLocation(program, "atmo_occ_tile_from_position"), 1, GL_FALSE, m4);
  uniform4(program, "atmo_occ_grid", o.grid);
  uniform4(program, "atmo_occ_limits", o.limits);
  uniform4(program, "atmo_occ_sun", o.sun);
  glUniform3f(glGetUniformLocation(program, "atmo_occ_sun_lux"), float(o.sun_lux[0]), float(o.sun_lux[1]),
              float(o.sun_lux[2]));
  glUniform3fv(glGetUniformLocation(program, "atmo_occ_sun_sh9"), 9, o.sun_sh9);
  glUniform4fv(glGetUniformLocation(program, "atmo_occ_transfer"), 108, o.transfer);
}

SkyOcclusionBinding::~SkyOcclusionBinding() {
  for (int u = 0; u < kUnits; ++u) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(first_unit_ + u));
    glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(previous_[u]));
  }
  glActiveTexture(static_cast<GLenum>(active_));
}

}  // namespace atmo::host_scene
