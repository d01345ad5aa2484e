// GL state snapshots, to check the plugin's contract "on return, all GL state
// the plugin touched is as the host left it".
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace atmo::support {

struct GlStateSnapshot {
  // Named values in capture order, e.g. {"GL_DEPTH_FUNC", {0x201}} or
  // {"GL_TEXTURE_BINDING_2D[unit 3]", {7}}.
  std::vector<std::pair<std::string, std::vector<double>>> values;
  // Queries that raised a GL error (should stay empty; the error is consumed).
  std::vector<std::string> query_errors;

  const std::vector<double>* find(const std::string& name) const;
};

// Needs a current context. Clears pending GL errors first (the host's error
// flags are lost). Switches the active texture unit to read per-unit bindings,
// then restores it. Queries above the context's version are skipped.
GlStateSnapshot capture_gl_state();

// One line per differing value, e.g. "GL_DEPTH_FUNC: before 0x0203, after 0x0201";
// a value present in one snapshot only shows as "<absent>".
std::vector<std::string> diff_gl_state(const GlStateSnapshot& before, const GlStateSnapshot& after);

// RAII: makes GL objects and sets a non-default host state, so a plugin that
// relies on GL defaults or forgets to restore state is caught. It sets:
//  - a linked program in use (GLSL 330), a VAO with its own array and element
//    buffers, uniform buffers bound at indices 0 and 2 (and the generic point);
//  - on texture units 0..7 textures on 2D, 3D, 2D_ARRAY and CUBE_MAP; a
//    sampler on unit 3; active texture GL_TEXTURE5;
//  - its own FBO (RGBA8 colour + DEPTH24_STENCIL8 renderbuffer, 64x64) bound
//    as draw and read framebuffer, its renderbuffer bound;
//  - viewport (3,5,50,40), scissor (2,4,30,20) enabled;
//  - depth test on, GL_GREATER, depth mask false, depth range (0.1, 0.9);
//  - blend on (src GL_SRC_COLOR / dst GL_ONE_MINUS_DST_ALPHA rgb, GL_ZERO /
//    GL_SRC_ALPHA alpha), equations REVERSE_SUBTRACT / MAX, blend colour;
//  - cull face on, GL_FRONT, front face GL_CW;
//  - stencil on, func GL_NOTEQUAL ref 3 mask 0x0F, ops INCR/DECR/INVERT,
//    write mask 0x0F; colour mask (1,0,1,1);
//  - polygon offset fill on (1.5, 2.0); clear colour/depth/stencil;
//  - pack/unpack alignment 1; program point size on; primitive restart on
//    (index 7); dither off; seamless cube maps on; GL_FRAMEBUFFER_SRGB on;
//    provoking vertex GL_FIRST_VERTEX_CONVENTION.
// It leaves alone what would make any renderer draw nothing or wrongly no
// matter what it sets (rasterizer discard, logic op, clip distances, clip
// control, polygon mode). The destructor deletes its objects and puts all of
// the above back to the GL defaults (viewport and scissor box to the values
// found at construction, and the stencil value/write masks, whose initial
// value differs between drivers). Needs a current context, the same one in the destructor.
class UnusualGlState {
 public:
  UnusualGlState();
  ~UnusualGlState();
  UnusualGlState(const UnusualGlState&) = delete;
  UnusualGlState& operator=(const UnusualGlState&) = delete;

  unsigned program() const { return program_; }
  unsigned vao() const { return vao_; }
  unsigned fbo() const { return fbo_; }

 private:
  unsigned program_ = 0, vao_ = 0, fbo_ = 0, color_rb_ = 0, depth_rb_ = 0, sampler_ = 0;
  unsigned buffers_[4] = {0, 0, 0, 0};  // array, element, uniform 0, uniform 2
  unsigned textures_[32] = {};         // 8 units x 4 targets
  int viewport_[4] = {0, 0, 0, 0};
  int scissor_[4] = {0, 0, 0, 0};
  int stencil_masks_[4] = {0, 0, 0, 0};  // value front/back, write front/back
};

}  // namespace atmo::support
