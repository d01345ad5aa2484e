#include "atmo_host_scene/fog_lighting_binding.h"

namespace atmo::host_scene {

namespace {

// The include's samplers, their targets and the AtmoFogLighting texture of each, in unit order.
struct Sampler {
  const char* name;
  GLenum target, binding;
};
constexpr Sampler kSamplers[FogLightingBinding::kUnits] = {
    {"atmo_fog_surface_table", GL_TEXTURE_2D, GL_TEXTURE_BINDING_2D},
    {"atmo_fog_light_texture", GL_TEXTURE_2D, GL_TEXTURE_BINDING_2D},
    {"atmo_fog_cluster_grid", GL_TEXTURE_2D, GL_TEXTURE_BINDING_2D},
    {"atmo_fog_far_field", GL_TEXTURE_3D, GL_TEXTURE_BINDING_3D},
    {"atmo_fog_airlight_table", GL_TEXTURE_2D, GL_TEXTURE_BINDING_2D},
    {"atmo_fog_glow_tiles", GL_TEXTURE_2D, GL_TEXTURE_BINDING_2D},
    {"atmo_fog_glow_lists", GL_TEXTURE_2D, GL_TEXTURE_BINDING_2D},
    {"atmo_fog_glow_entries", GL_TEXTURE_2D, GL_TEXTURE_BINDING_2D}};

}  // namespace

FogLightingBinding::FogLightingBinding(GLuint program, const AtmoFogLighting& fog, int first_unit)
    : first_unit_(first_unit) {
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active_);
  const GLuint textures[kUnits] = {fog.surface_table,  fog.light_texture, fog.cluster_grid, fog.far_field,
                                   fog.airlight_table, fog.glow_tiles,    fog.glow_lists,   fog.glow_entries};
  for (int u = 0; u < kUnits; ++u) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(first_unit + u));
    glGetIntegerv(kSamplers[u].binding, &previous_[u]);
    glBindTexture(kSamplers[u].target, textures[u]);
    glUniform1i(glGetUniformLocation(program, kSamplers[u].name), first_unit + u);
  }
  float m[16];
  for (int k = 0; k < 16; ++k) m[k] = static_cast<float>(fog.cluster_from_position[k]);
  glUniformMatrix4fv(glGetUniformLocation(program, "atmo_fog_cluster_from_position"), 1, GL_FALSE, m);
  glUniform4f(glGetUniformLocation(program, "atmo_fog_cluster_grid_size"), float(fog.cluster_grid_size[0]),
              float(fog.cluster_grid_size[1]), float(fog.cluster_grid_size[2]), float(fog.cluster_grid_size[3]));
  glUniform2f(glGetUniformLocation(program, "atmo_fog_cluster_range"), float(fog.cluster_range[0]),
              float(fog.cluster_range[1]));
  float enu[9];
  for (int k = 0; k < 9; ++k) enu[k] = static_cast<float>(fog.enu_from_world[k]);
  glUniformMatrix3fv(glGetUniformLocation(program, "atmo_fog_enu_from_world"), 1, GL_FALSE, enu);
  glUniform4f(glGetUniformLocation(program, "atmo_fog_medium"), float(fog.medium[0]), float(fog.medium[1]),
              float(fog.medium[2]), float(fog.medium[3]));
  glUniform4f(glGetUniformLocation(program, "atmo_fog_diffusion"), float(fog.diffusion[0]), float(fog.diffusion[1]),
              float(fog.diffusion[2]), float(fog.diffusion[3]));
  glUniform3f(glGetUniformLocation(program, "atmo_fog_up"), float(fog.up_world[0]), float(fog.up_world[1]),
              float(fog.up_world[2]));
  glUniform2f(glGetUniformLocation(program, "atmo_fog_surface_table_size"), float(fog.surface_table_size[0]),
              float(fog.surface_table_size[1]));
  glUniform4f(glGetUniformLocation(program, "atmo_fog_glow_grid"), float(fog.glow_grid[0]), float(fog.glow_grid[1]),
              float(fog.glow_grid[2]), float(fog.glow_grid[3]));
  glUniform3f(glGetUniformLocation(program, "atmo_fog_ambient"), float(fog.ambient[0]), float(fog.ambient[1]),
              float(fog.ambient[2]));
  glUniform3f(glGetUniformLocation(program, "atmo_fog_fluence"), float(fog.fluence[0]), float(fog.fluence[1]),
              float(fog.fluence[2]));
  float flux[9];
  for (int k = 0; k < 9; ++k) flux[k] = static_cast<float>(fog.flux[k]);
  glUniformMatrix3fv(glGetUniformLocation(program, "atmo_fog_flux"), 1, GL_FALSE, flux);
}

FogLightingBinding::~FogLightingBinding() {
  for (int u = 0; u < kUnits; ++u) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(first_unit_ + u));
    glBindTexture(kSamplers[u].target, static_cast<GLuint>(previous_[u]));
  }
  glActiveTexture(static_cast<GLenum>(active_));
}

}  // namespace atmo::host_scene
