// night_terms_uniforms.h — the night-sky terms every program compiling
// shaders/atmosphere/sky_pixel.glsl declares (u_night_terms, the moonlit
// sky-view table, u_moon_disc, u_night_background): looked up once after
// linking, set per draw. Shared by the sky pass (gl/renderer) and the night
// point pass (gl/night_renderer), which re-evaluates the sky under a star.
#pragma once

#include <glad/gl.h>
#include <glm/glm.hpp>

#include "core/night_sky/night_sky_twin.h"

namespace atmo::gl {

struct NightTerms;

// The texture unit of the moonlit sky-view table in every program.
constexpr GLuint kMoonSkyViewUnit = 6;

struct NightTermUniforms {
  GLint terms = -1, moon_sky_view = -1, moon_direction = -1, moon_sky_scale = -1, pixel_angle = -1;
  GLint moon[5] = {-1, -1, -1, -1, -1};
  GLint background[17] = {-1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};
};

NightTermUniforms locate_night_term_uniforms(GLuint program);

// The program must be in use. `moon_sky_scale` takes the moonlit table's
// texels to the current Moon's light; the table is bound by the caller at
// kMoonSkyViewUnit.
void set_night_term_uniforms(const NightTermUniforms& u, const NightTerms& night, const glm::vec3& moon_sky_scale);

}  // namespace atmo::gl
