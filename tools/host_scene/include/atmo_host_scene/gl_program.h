// gl_program.h — compile and link a GLSL 330 core program, the log as the error
// (used by the terrain and by hosts for their own small shaders).
#ifndef ATMO_HOST_SCENE_GL_PROGRAM_H
#define ATMO_HOST_SCENE_GL_PROGRAM_H

#include <string>

#include <glad/gl.h>

namespace atmo::host_scene {

// [gl-current] Returns the program name, or 0 with *error set. `defines` is
// inserted after the "#version 330 core" line of both stages.
GLuint build_program(const char* vertex_source, const char* fragment_source,
                     const std::string& defines, const char* name, std::string* error);

}  // namespace atmo::host_scene

#endif  // ATMO_HOST_SCENE_GL_PROGRAM_H
