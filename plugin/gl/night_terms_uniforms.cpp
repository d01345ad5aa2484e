#include "gl/night_terms_uniforms.h"

#include <glm/gtc/type_ptr.hpp>

#include "gl/renderer.h"

namespace atmo::gl {

namespace {
// Member names, in the order of NightTermUniforms::moon / ::background.
constexpr const char* kMoonMembers[5] = {"direction", "angular_radius_rad", "to_sun", "sun_radiance",
                                         "earthshine_radiance"};
constexpr const char* kBackgroundMembers[17] = {
    "icrs_from_enu",           "sun_icrs",
    "eye_altitude_m",          "planet_radius_m",
    "airglow_zenith_cd_m2",    "airglow_layer_altitude_m",
    "airglow_layer_thickness_m", "zodiacal_cd_m2_per_unit",
    "starlight_pole_cd_m2",    "starlight_plane_excess_cd_m2",
    "starlight_width_sin_b",   "starlight_longitude_contrast",
    "diffuse_galactic_fraction", "cosmic_cd_m2",
    "airglow_rgb",             "zodiacal_rgb",
    "starlight_rgb"};
}  // namespace

NightTermUniforms locate_night_term_uniforms(GLuint program) {
  auto loc = [&](const std::string& name) { return glGetUniformLocation(program, name.c_str()); };
  NightTermUniforms u;
  u.terms = loc("u_night_terms");
  u.moon_sky_view = loc("u_moon_sky_view");
  u.moon_direction = loc("u_moon_direction_enu");
  u.moon_sky_scale = loc("u_moon_sky_scale");
  u.pixel_angle = loc("u_pixel_angle_rad");
  for (int i = 0; i < 5; ++i) u.moon[i] = loc(std::string("u_moon_disc.") + kMoonMembers[i]);
  for (int i = 0; i < 17; ++i) u.background[i] = loc(std::string("u_night_background.") + kBackgroundMembers[i]);
  return u;
}

void set_night_term_uniforms(const NightTermUniforms& u, const NightTerms& n, const glm::vec3& moon_sky_scale) {
  glUniform1i(u.terms, n.bits());
  glUniform1i(u.moon_sky_view, static_cast<GLint>(kMoonSkyViewUnit));
  glUniform3fv(u.moon_direction, 1, glm::value_ptr(n.moon_direction_enu));
  glUniform3fv(u.moon_sky_scale, 1, glm::value_ptr(moon_sky_scale));
  glUniform1f(u.pixel_angle, n.pixel_angle_rad);
  const twin::MoonDisc& m = n.moon;
  glUniform3fv(u.moon[0], 1, glm::value_ptr(m.direction));
  glUniform1f(u.moon[1], m.angular_radius_rad);
  glUniform3fv(u.moon[2], 1, glm::value_ptr(m.to_sun));
  glUniform3fv(u.moon[3], 1, glm::value_ptr(m.sun_radiance));
  glUniform3fv(u.moon[4], 1, glm::value_ptr(m.earthshine_radiance));
  const twin::NightBackground& b = n.sky_background;
  glUniformMatrix3fv(u.background[0], 1, GL_FALSE, glm::value_ptr(b.icrs_from_enu));
  glUniform3fv(u.background[1], 1, glm::value_ptr(b.sun_icrs));
  const float scalars[12] = {b.eye_altitude_m,
                             b.planet_radius_m,
                             b.airglow_zenith_cd_m2,
                             b.airglow_layer_altitude_m,
                             b.airglow_layer_thickness_m,
                             b.zodiacal_cd_m2_per_unit,
                             b.starlight_pole_cd_m2,
                             b.starlight_plane_excess_cd_m2,
                             b.starlight_width_sin_b,
                             b.starlight_longitude_contrast,
                             b.diffuse_galactic_fraction,
                             b.cosmic_cd_m2};
  for (int i = 0; i < 12; ++i) glUniform1f(u.background[2 + i], scalars[i]);
  glUniform3fv(u.background[14], 1, glm::value_ptr(b.airglow_rgb));
  glUniform3fv(u.background[15], 1, glm::value_ptr(b.zodiacal_rgb));
  glUniform3fv(u.background[16], 1, glm::value_ptr(b.starlight_rgb));
}

}  // namespace atmo::gl
