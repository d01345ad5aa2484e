// cloud_octave_uniforms.h — the `uniform CloudOctaves u_octaves` of every
// cloud program (cloud_functions.glsl's struct): located by name from
// clouds::kOctaveFloats, so a new member is set everywhere it is declared.
#pragma once

#include <glad/gl.h>

#include <array>
#include <string>

#include <glm/gtc/type_ptr.hpp>

#include "core/clouds/cloud_optics.h"

namespace atmo::gl {

struct OctaveUniforms {
  GLint count = -1, up_grid = -1;
  std::array<GLint, clouds::kOctaveFloatCount> floats{};  // in kOctaveFloats' order

  void locate(GLuint program) {
    count = glGetUniformLocation(program, "u_octaves.count");
    up_grid = glGetUniformLocation(program, "u_octaves.up_grid");
    for (size_t i = 0; i < clouds::kOctaveFloatCount; ++i)
      floats[i] = glGetUniformLocation(program, ("u_octaves." + std::string(clouds::kOctaveFloats[i].name)).c_str());
  }
  // On the program in use.
  void set(const clouds::twin::CloudOctaves& o) const {
    glUniform1i(count, o.count);
    glUniform3fv(up_grid, 1, glm::value_ptr(o.up_grid));
    for (size_t i = 0; i < clouds::kOctaveFloatCount; ++i) glUniform1f(floats[i], o.*clouds::kOctaveFloats[i].field);
  }
};

}  // namespace atmo::gl
