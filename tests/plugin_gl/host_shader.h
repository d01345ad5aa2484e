// What the tests' own "host" shaders need: a source file read from the tree
// (a host include), a stage compiled and a program linked with their logs
// reported as test failures, and one full-screen triangle drawn.
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

// A vertex + fragment program, linked; deleted with its shaders when it goes.
class HostProgram {
 public:
  HostProgram(const std::string& vertex_source, const std::string& fragment_source)
      : vs_(compile(GL_VERTEX_SHADER, vertex_source)), fs_(compile(GL_FRAGMENT_SHADER, fragment_source)) {
    program_ = glCreateProgram();
    glAttachShader(program_, vs_);
    glAttachShader(program_, fs_);
    glLinkProgram(program_);
    GLint ok = 0;
    glGetProgramiv(program_, GL_LINK_STATUS, &ok);
    linked_ = ok != 0;
    if (!linked_) {
      char log[4096];
      glGetProgramInfoLog(program_, sizeof log, nullptr, log);
      ADD_FAILURE() << "host program: " << log;
    }
  }
  ~HostProgram() {
    glUseProgram(0);
    glDeleteProgram(program_);
    glDeleteShader(vs_);
    glDeleteShader(fs_);
  }
  HostProgram(const HostProgram&) = delete;
  HostProgram& operator=(const HostProgram&) = delete;

  GLuint id() const { return program_; }
  bool linked() const { return linked_; }
  GLint uniform(const char* name) const { return glGetUniformLocation(program_, name); }

 private:
  GLuint vs_ = 0, fs_ = 0, program_ = 0;
  bool linked_ = false;
};

// One triangle over the viewport (the vertex shader makes it from gl_VertexID), through a VAO of its own.
inline void draw_full_screen_triangle() {
  GLuint vao = 0;
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDeleteVertexArrays(1, &vao);
}

}  // namespace plugin_gl
