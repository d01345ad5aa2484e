// light_point_renderer.h — the GL side of ATMO_PASS_LIGHT_POINTS: draws the
// lights core/lights/light_points.h chose, one GL_POINTS vertex each
// (shaders/light_points.vert, .frag): the host's depth hides a light behind
// its geometry, and each pixel of the footprint gets E · weight / Omega_pixel
// (the stars' integrated Gaussian, widened past the view's white). The
// programs are built by the first pass with a light to draw.
#pragma once

#include <glad/gl.h>

#include <string>
#include <vector>

#include "core/lights/light_points.h"
#include "gl/pass_uniforms.h"
#include "gl/point_sprites.h"
#include "gl/renderer.h"

namespace atmo::gl {

class LightPointRenderer {
 public:
  LightPointRenderer() = default;
  LightPointRenderer(const LightPointRenderer&) = delete;
  LightPointRenderer& operator=(const LightPointRenderer&) = delete;

  // [gl-current] Deletes everything; idempotent. forget(): the context is gone (no GL call).
  void destroy();
  void forget();

  // Draws the points into the bound framebuffer (state restored). No points: no GL call.
  bool draw(const PassInputs& in, const std::vector<lights::LightPoint>& points, std::string* error);

  // The footprint's width for a light at or below the view's white, and at most (pixels).
  static constexpr float kSigmaPx = 0.7f;
  static constexpr float kSigmaMaxPx = 2.1f;
  // The widest footprint reaches this far from its centre: the viewport is grown by it.
  static constexpr int kMarginPx = 7;

 private:
  bool build(std::string* error);

  GLuint program_ = 0, linear_sampler_ = 0, nearest_sampler_ = 0;
  PassUniforms pass_;
  GLint clip_from_view_ = -1, view_from_enu_ = -1, draw_viewport_ = -1, sigma_ = -1, sigma_max_ = -1;
  PointSprites sprites_;
};

}  // namespace atmo::gl
