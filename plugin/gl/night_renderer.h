// night_renderer.h — the GL layer of the night sky's point sources (stars
// and planets, core/night_sky/point_sources.h): draws a list of PointSource
// into the bound framebuffer, as GL_POINTS, one vertex per source
// (shaders/night_points.vert, .frag). Per source, on the GPU: the projection
// through the host's camera, the atmosphere's transmittance along the line of
// sight (transmittance table; hidden behind the Earth), the solid angle of a
// pixel there; per pixel: the integrated-Gaussian footprint
// (shaders/night_sky/point_footprint.glsl, the core's star_footprint_weight),
// so L_pixel = E · T · weight / Omega_pixel and a source's total light does
// not depend on where it falls. Only where the host's depth is at the far
// plane. LINEAR_HDR adds exposure · L (blend ONE, ONE); DISPLAY_SRGB writes
// encode(exposure · (L_sky + L)) with the sky re-evaluated per pixel as the
// sky pass does, blended with MAX (docs/NIGHT_SKY.md, "Rendering: point
// sources"). An empty list costs nothing: no GL call at all.
//
// Needs GL 3.3 loaded through glad (Renderer::init does it) and the context
// current; state is saved and restored (GlStateGuard, plus the program point
// size switch, the scissor box and, in a compatibility context, point
// smoothing, which the guard does not cover).
#pragma once

#include <glad/gl.h>
#include <glm/glm.hpp>

#include <cstddef>
#include <string>
#include <vector>

#include "core/night_sky/point_sources.h"
#include "gl/renderer.h"

#include "gl/pass_uniforms.h"
#include "gl/point_sprites.h"

namespace atmo::gl {

class NightRenderer {
 public:
  // Builds the programs (one per SkyMethod), the vertex buffer and array.
  // GL must be loaded (after Renderer::init) and current.
  bool init(std::string* error);
  void destroy();  // deletes GL objects (context current)
  void forget();   // drops GL names without GL calls (context lost)
  bool initialised() const { return programs_[0].program != 0; }

  // Draws `count` sources into the bound draw framebuffer with the view of
  // `in` (camera, viewport, host depth, exposure, output encoding, method,
  // atmosphere, eye altitude, sun). count == 0: returns true without any GL
  // call. False and *error on a GL error (state restored either way).
  bool draw_points(const PassInputs& in, const NightSkyTextures& textures, const core::night::PointSource* sources,
                   std::size_t count, std::string* error);
  bool draw_points(const PassInputs& in, const NightSkyTextures& textures,
                   const std::vector<core::night::PointSource>& sources, std::string* error) {
    return draw_points(in, textures, sources.data(), sources.size(), error);
  }

  // GL discards a point whose centre is outside the viewport, which would
  // drop the light a source just outside the edge puts on the edge pixels
  // (a pop as it crosses the edge): the pass draws with the host's viewport
  // grown by this margin and scissors to the host's viewport, so nothing is
  // written outside it.
  static constexpr int kViewportMarginPx = 4;
  // Side of the point square, pixels: 2 R + 1.
  static int point_size_px();

  struct Counters {
    uint64_t draws = 0;            // draw_points calls that drew
    uint64_t sources_drawn = 0;    // vertices submitted
    uint64_t buffer_reallocations = 0;
  };
  const Counters& counters() const { return counters_; }

 private:
  struct Program {
    GLuint program = 0;
    PassUniforms pass;  // pass_common.glsl's uniforms, as the Renderer's passes
    GLint clip_from_view = -1, view_from_enu = -1, draw_viewport = -1, point_size = -1, footprint_sigma = -1;
  };
  bool build(Program* p, SkyMethod method, std::string* error);

  static constexpr int kMethods = 3;
  Program programs_[kMethods];
  PointSprites sprites_;
  GLuint linear_sampler_ = 0, nearest_sampler_ = 0;
  Counters counters_;
};

}  // namespace atmo::gl
