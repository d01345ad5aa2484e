#include "atmo_host_scene/sky_occlusion_binding.h"

namespace atmo::host_scene {

namespace {

// The include's samplers in unit order (all GL_TEXTURE_2D).
constexpr const char* kSamplers[SkyOcclusionBinding::kUnits] = {"atmo_occ_tables", "atmo_occ_spheres", "atmo_occ_objects",
                                                                "atmo_occ_tiles", "atmo_occ_tile_objects"};

void uniform4(GLuint program, const char* name, const double v[4]) {
  glUniform4f(glGetUniformLocation(program, name), float(v[0]), float(v[1]), float(v[2]), float(v[3]));
}

}  // namespace

SkyOcclusionBinding::SkyOcclusionBinding(GLuint program, const AtmoSkyOcclusion& o, int first_unit)
    : first_unit_(first_unit) {
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active_);
  const GLuint textures[kUnits] = {o.tables, o.spheres, o.objects, o.tiles, o.tile_objects};
  for (int u = 0; u < kUnits; ++u) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(first_unit + u));
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &previous_[u]);
    glBindTexture(GL_TEXTURE_2D, textures[u]);
    glUniform1i(glGetUniformLocation(program, kSamplers[u]), first_unit + u);
  }
  float m4[16], m3[9];
  for (int k = 0; k < 16; ++k) m4[k] = static_cast<float>(o.tile_from_position[k]);
  for (int k = 0; k < 9; ++k) m3[k] = static_cast<float>(o.enu_from_world[k]);
  glUniformMatrix4fv(glGetUniformLocation(program, "atmo_occ_tile_from_position"), 1, GL_FALSE, m4);
  glUniformMatrix3fv(glGetUniformLocation(program, "atmo_occ_enu_from_world"), 1, GL_FALSE, m3);
  uniform4(program, "atmo_occ_grid", o.grid);
  uniform4(program, "atmo_occ_limits", o.limits);
  uniform4(program, "atmo_occ_sun", o.sun);
  glUniform3f(glGetUniformLocation(program, "atmo_occ_sun_lux"), float(o.sun_lux[0]), float(o.sun_lux[1]),
              float(o.sun_lux[2]));
  glUniform3fv(glGetUniformLocation(program, "atmo_occ_sky_sh9"), 9, o.sky_sh9);
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
