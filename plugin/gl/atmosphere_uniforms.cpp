#include "gl/atmosphere_uniforms.h"

#include <glm/gtc/type_ptr.hpp>

namespace atmo::gl {

AtmosphereUniforms locate_atmosphere_uniforms(GLuint program) {
  auto loc = [&](const char* name) { return glGetUniformLocation(program, name); };
  AtmosphereUniforms u;
  u.bottom_radius = loc("u_atmosphere.bottom_radius_m");
  u.top_radius = loc("u_atmosphere.top_radius_m");
  u.rayleigh_scattering = loc("u_atmosphere.rayleigh_scattering");
  u.rayleigh_scale_height = loc("u_atmosphere.rayleigh_scale_height_m");
  u.mie_scattering = loc("u_atmosphere.mie_scattering");
  u.mie_extinction = loc("u_atmosphere.mie_extinction");
  u.mie_scale_height = loc("u_atmosphere.mie_scale_height_m");
  u.mie_g = loc("u_atmosphere.mie_g");
  u.ozone_absorption = loc("u_atmosphere.ozone_absorption");
  u.ozone_center = loc("u_atmosphere.ozone_center_m");
  u.ozone_half_width = loc("u_atmosphere.ozone_half_width_m");
  u.sun_illuminance = loc("u_atmosphere.sun_illuminance_lux");
  u.sun_angular_radius = loc("u_atmosphere.sun_angular_radius");
  u.ground_albedo = loc("u_atmosphere.ground_albedo");
  return u;
}

void set_atmosphere_uniforms(const AtmosphereUniforms& u, const twin::AtmosphereParameters& a) {
  glUniform1f(u.bottom_radius, a.bottom_radius_m);
  glUniform1f(u.top_radius, a.top_radius_m);
  glUniform3fv(u.rayleigh_scattering, 1, glm::value_ptr(a.rayleigh_scattering));
  glUniform1f(u.rayleigh_scale_height, a.rayleigh_scale_height_m);
  glUniform3fv(u.mie_scattering, 1, glm::value_ptr(a.mie_scattering));
  glUniform3fv(u.mie_extinction, 1, glm::value_ptr(a.mie_extinction));
  glUniform1f(u.mie_scale_height, a.mie_scale_height_m);
  glUniform1f(u.mie_g, a.mie_g);
  glUniform3fv(u.ozone_absorption, 1, glm::value_ptr(a.ozone_absorption));
  glUniform1f(u.ozone_center, a.ozone_center_m);
  glUniform1f(u.ozone_half_width, a.ozone_half_width_m);
  glUniform3fv(u.sun_illuminance, 1, glm::value_ptr(a.sun_illuminance_lux));
  glUniform1f(u.sun_angular_radius, a.sun_angular_radius);
  glUniform3fv(u.ground_albedo, 1, glm::value_ptr(a.ground_albedo));
}

}  // namespace atmo::gl
