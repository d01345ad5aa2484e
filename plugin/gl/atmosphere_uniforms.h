// atmosphere_uniforms.h — the `AtmosphereParameters u_atmosphere` uniform
// block that every program compiling shaders/atmosphere/functions.glsl
// declares: looked up once after linking, set per draw. Shared by the sky and
// aerial passes (gl/renderer) and the night pass (gl/night_renderer).
#pragma once

#include <glad/gl.h>

#include "core/atmosphere/shader_twin.h"

namespace atmo::gl {

struct AtmosphereUniforms {
  // Locations (-1 where a program does not use a member).
  GLint bottom_radius = -1, top_radius = -1, rayleigh_scattering = -1, rayleigh_scale_height = -1,
        mie_scattering = -1, mie_extinction = -1, mie_scale_height = -1, mie_g = -1, ozone_absorption = -1,
        ozone_center = -1, ozone_half_width = -1, sun_illuminance = -1, sun_angular_radius = -1, ground_albedo = -1;
};

AtmosphereUniforms locate_atmosphere_uniforms(GLuint program);

// The program must be in use.
void set_atmosphere_uniforms(const AtmosphereUniforms& u, const twin::AtmosphereParameters& a);

}  // namespace atmo::gl
