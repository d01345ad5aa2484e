#include "gl/shader_program.h"

#include <set>
#include <sstream>
#include <vector>

namespace atmo::embedded_shaders {
std::string_view find(std::string_view path);
}

namespace atmo::gl {

namespace {
constexpr const char* kVersionLine = "#version 330 core\n";

// The info log of a shader or program (glGetShaderiv/InfoLog or the program twins).
template <typename GetIv, typename GetLog>
std::string info_log(GLuint object, GetIv get_iv, GetLog get_log) {
  GLint length = 0;
  get_iv(object, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(static_cast<size_t>(length > 1 ? length : 1));
  get_log(object, static_cast<GLsizei>(log.size()), nullptr, log.data());
  return log.data();
}

bool expand(std::string_view path, std::set<std::string>& seen, std::string& out, std::string* error) {
  std::string_view text = embedded_shaders::find(path);
  if (text.empty()) {
    if (error) *error = "shader file '" + std::string(path) + "' is not embedded in the plugin";
    return false;
  }
  if (!seen.insert(std::string(path)).second) return true;  // include once
  std::istringstream lines{std::string(text)};
  std::string line;
  while (std::getline(lines, line)) {
    const std::string directive = "#include \"";
    if (line.rfind(directive, 0) == 0) {
      size_t end = line.find('"', directive.size());
      if (end == std::string::npos) {
        if (error) *error = std::string(path) + ": malformed #include";
        return false;
      }
      if (!expand(line.substr(directive.size(), end - directive.size()), seen, out, error)) return false;
    } else {
      out += line;
      out += '\n';
    }
  }
  return true;
}

GLuint compile(GLenum stage, std::string_view path, std::string_view defines, std::string_view appendix,
               std::string* error) {
  std::set<std::string> seen;
  std::string source = kVersionLine;
  source += defines;
  if (!expand(path, seen, source, error)) return 0;
  source += appendix;
  GLuint shader = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    if (error) *error = "compiling " + std::string(path) + ": " + info_log(shader, glGetShaderiv, glGetShaderInfoLog);
    glDeleteShader(shader);
    return 0;
  }
  return shader;
}
}  // namespace

std::string expand_shader_source(std::string_view path, std::string* error) {
  std::set<std::string> seen;
  std::string out;
  if (!expand(path, seen, out, error)) return {};
  return out;
}

GLuint build_program(std::string_view vertex_path, std::string_view fragment_path, std::string_view defines,
                     std::string* error, std::string_view fragment_appendix) {
  GLuint vs = compile(GL_VERTEX_SHADER, vertex_path, defines, {}, error);
  if (!vs) return 0;
  GLuint fs = compile(GL_FRAGMENT_SHADER, fragment_path, defines, fragment_appendix, error);
  if (!fs) {
    glDeleteShader(vs);
    return 0;
  }
  GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    if (error)
      *error = "linking " + std::string(vertex_path) + " + " + std::string(fragment_path) + " (" +
               std::string(defines) + "): " +
               info_log(program, glGetProgramiv, glGetProgramInfoLog);
    glDeleteProgram(program);
    return 0;
  }
  return program;
}

namespace {
std::string gl_error_string(GLenum e) {
  switch (e) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    default: return "GL error " + std::to_string(e);
  }
}
}  // namespace

bool check_gl(const char* what, std::string* error) {
  GLenum e = glGetError();
  if (e == GL_NO_ERROR) return true;
  if (error) *error = gl_error_string(e) + " while " + what;
  while (glGetError() != GL_NO_ERROR) {}
  return false;
}

}  // namespace atmo::gl
