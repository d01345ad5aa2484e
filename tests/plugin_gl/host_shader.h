// What the tests' own "host" shaders need: a source file read from the tree
// (a host include) and a stage compiled with its log reported as a test failure.
#pragma once

#include <glad/gl.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

namespace plugin_gl {

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline GLuint compile(GLenum stage, const std::string& source) {
  GLuint s = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(s, 1, &text, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    ADD_FAILURE() << "host shader: " << log;
  }
  return s;
}

}  // namespace plugin_gl
