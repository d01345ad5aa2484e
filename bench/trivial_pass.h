// trivial_pass.h — the ratio base of the GL benchmarks (gpu_passes_bench,
// clouds_bench): a full-screen triangle whose colour follows the pixel (a
// constant colour would let llvmpipe fill tiles without shading), and the
// bare compile-and-link both use for their few fixed test programs.
#pragma once

#include <glad/gl.h>

namespace bench_gl {

// One triangle over the viewport from gl_VertexID (an empty VAO).
inline constexpr const char* kFullScreenVertex =
    "#version 330 core\nvoid main(){vec2 p=vec2((gl_VertexID<<1)&2,gl_VertexID&2);"
    "gl_Position=vec4(p*2.0-1.0,0.5,1.0);}";
inline constexpr const char* kTrivialFragment =
    "#version 330 core\nout vec4 c;void main(){c=vec4(gl_FragCoord.xy*1e-3,0.5,1.0);}";

// Compiles and links without checks: the sources are fixed, and a broken one
// shows as a GL error in the benchmark's first frame.
inline GLuint make_program(const char* vs_src, const char* fs_src) {
  GLuint s1 = glCreateShader(GL_VERTEX_SHADER), s2 = glCreateShader(GL_FRAGMENT_SHADER);
  glShaderSource(s1, 1, &vs_src, nullptr);
  glShaderSource(s2, 1, &fs_src, nullptr);
  glCompileShader(s1);
  glCompileShader(s2);
  GLuint program = glCreateProgram();
  glAttachShader(program, s1);
  glAttachShader(program, s2);
  glLinkProgram(program);
  glDeleteShader(s1);
  glDeleteShader(s2);
  return program;
}

inline GLuint make_trivial_program() { return make_program(kFullScreenVertex, kTrivialFragment); }

}  // namespace bench_gl
