// shader_program.h — builds GL programs from the shaders embedded in the
// plugin (shaders/ at build time), resolving `#include "path"` lines, which
// GLSL itself lacks, and prepending the #version line.
#pragma once

#include <glad/gl.h>

#include <string>
#include <string_view>

namespace atmo::gl {

// Returns the embedded source with includes expanded; empty + *error if a file is missing.
std::string expand_shader_source(std::string_view path, std::string* error);

// Compiles and links a vertex + fragment program; `defines` (lines such as
// "#define ATMO_METHOD 0\n") go right after the #version line, so one source
// builds specialised variants. `fragment_appendix` goes after the fragment
// file (a test's main() over a file of functions). 0 and *error (with the
// compiler log and file names) on failure.
GLuint build_program(std::string_view vertex_path, std::string_view fragment_path, std::string_view defines,
                     std::string* error, std::string_view fragment_appendix = {});

// True if GL has no error pending; else false, *error = "<GL error name>
// while <what>", and every pending error cleared (the passes' own check after
// their GL work; errors the host left are cleared before it).
bool check_gl(const char* what, std::string* error);

}  // namespace atmo::gl
