#include "atmo_host_scene/gl_program.h"

#include <vector>

namespace atmo::host_scene {

namespace {

const char* kVersion = "#version 330 core\n";

// The info log of a shader or program (glGetShaderiv/InfoLog or the program twins).
template <typename GetIv, typename GetLog>
std::string info_log(GLuint object, GetIv get_iv, GetLog get_log) {
  GLint length = 0;
  get_iv(object, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(static_cast<size_t>(length > 0 ? length : 1), '\0');
  get_log(object, static_cast<GLsizei>(log.size()), nullptr, log.data());
  return log.data();
}

GLuint compile(GLenum stage, const char* source, const std::string& defines, const char* name,
               std::string* error) {
  const GLuint shader = glCreateShader(stage);
  const char* parts[3] = {kVersion, defines.c_str(), source};
  glShaderSource(shader, 3, parts, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok) return shader;
  if (error) {
    *error = std::string(name) + (stage == GL_VERTEX_SHADER ? " vertex" : " fragment") +
             " shader: " + info_log(shader, glGetShaderiv, glGetShaderInfoLog);
  }
  glDeleteShader(shader);
  return 0;
}

}  // namespace

GLuint build_program(const char* vertex_source, const char* fragment_source,
                     const std::string& defines, const char* name, std::string* error) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex_source, defines, name, error);
  if (!vs) return 0;
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment_source, defines, name, error);
  if (!fs) {
    glDeleteShader(vs);
    return 0;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok) return program;
  if (error) *error = std::string(name) + " link: " + info_log(program, glGetProgramiv, glGetProgramInfoLog);
  glDeleteProgram(program);
  return 0;
}

}  // namespace atmo::host_scene
