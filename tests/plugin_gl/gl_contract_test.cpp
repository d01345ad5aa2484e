// The GL contract in a host's scene graph (issue 18): the host depth read at
// an offset viewport (AtmoViewState.depth_origin, both conventions), and the
// aerial-perspective volume's range with an infinite far plane
// (AtmoViewState.aerial_range_m and its default). The GL state and GL error
// contract of every pass is checked by `atmo validate` (tests/validate).
#include <glad/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <vector>

#include "atmo_support/example_view.h"
#include "plugin_gl_fixture.h"

namespace {

using namespace plugin_gl;
using atmo::support::Image;

constexpr float kGeometry[4] = {0.02f, 0.03f, 0.04f, 1.0f};  // the host's geometry colour (exposed units)

// Window depths for `distance_m` along the view axis through `clip_from_view` (depth in [0, 1] from NDC z in
// [-1, 1] for STANDARD, NDC z itself for REVERSED_ZERO_TO_ONE).
float window_depth(const glm::dmat4& clip_from_view, double distance_m, uint32_t convention) {
  const glm::dvec4 c = clip_from_view * glm::dvec4(0.0, 0.0, -distance_m, 1.0);
  const double z = c.z / c.w;
  return static_cast<float>(convention == ATMO_DEPTH_REVERSED_ZERO_TO_ONE ? z : 0.5 * z + 0.5);
}

// Host geometry in the lower half of a width x height viewport: bands at `distances` (m) from the bottom row up;
// the upper half is far (1 standard, 0 reversed).
std::vector<float> banded_depth(int width, int height, const glm::dmat4& clip_from_view, uint32_t convention,
                                const std::vector<double>& distances) {
  const float far = convention == ATMO_DEPTH_REVERSED_ZERO_TO_ONE ? 0.0f : 1.0f;
  std::vector<float> d(static_cast<size_t>(width) * height, far);
  const int rows = height / 2, band = std::max(1, rows / static_cast<int>(distances.size()));
  for (int y = 0; y < rows; ++y) {
    const size_t b = std::min(distances.size() - 1, static_cast<size_t>(y / band));
    const float z = window_depth(clip_from_view, distances[b], convention);
    for (int x = 0; x < width; ++x) d[static_cast<size_t>(y) * width + x] = z;
  }
  return d;
}

// Sky then aerial perspective over the geometry colour; returns the target's image.
Image draw_sky_and_haze(Fixture& f, OffscreenTarget& target, const AtmoViewState& vs) {
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = 1718964000.0;  // 2024-06-21 10:00 UTC
  f.context->set_frame(frame);
  f.view->set(vs);
  target.clear(kGeometry[0], kGeometry[1], kGeometry[2], kGeometry[3]);
  EXPECT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS);
  EXPECT_EQ(f.view->render(ATMO_PASS_AERIAL_PERSPECTIVE), ATMO_SUCCESS);
  glFinish();
  return target.read_color();
}

// Largest relative difference (per channel, against max(|a|, 1e-6)) between image `a` at (ax, ay) and `b` at
// (bx, by) over a w x h block (GL rows: y up; Image rows: top first).
double block_difference(const Image& a, int ax, int ay, const Image& b, int bx, int by, int w, int h) {
  double worst = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float* pa = a.pixel(ax + x, a.height - 1 - (ay + y));
      const float* pb = b.pixel(bx + x, b.height - 1 - (by + y));
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(double(pa[c]) - pb[c]) / std::max(std::abs(double(pb[c])), 1e-6));
    }
  return worst;
}

// The view both depth tests draw: 600 m over Innsbruck, 60° wide, near 1 m; geometry in bands at 0.3-30 km.
struct BandedView {
  glm::dmat4 proj = glm::perspective(glm::radians(60.0), double(kWidth) / kHeight, 1.0, 1e5);
  AtmoViewState vs = innsbruck_view(600.0, 0.0, 0.0, proj);
  std::vector<float> depth = banded_depth(kWidth, kHeight, proj, ATMO_DEPTH_STANDARD, {300.0, 2000.0, 8000.0, 30000.0});
  BandedView() { vs.exposure_scale = 1e-4; }
};

// --------------------------------------------------------------- offset viewport

// A viewport at (x, y) = (40, 24) in a 176 x 112 target draws what the same view draws at (0, 0), for a depth
// texture the size of the viewport (depth_origin = VIEWPORT) and one the size of the framebuffer
// (depth_origin = WINDOW, the default): sky only above the geometry, haze on it, nothing outside the viewport.
TEST(GlContract, OffsetViewportReadsTheDepthOfItsOwnPixels) {
  Fixture f;
  BandedView banded;
  AtmoViewState& vs = banded.vs;
  const std::vector<float>& depth = banded.depth;
  const GLuint viewport_depth = atmo::support::make_depth_texture(kWidth, kHeight, depth);

  // The reference: the viewport at the origin of a target its size.
  vs.depth_texture = viewport_depth;
  const Image reference = draw_sky_and_haze(f, *f.target, vs);
  // It has sky above and haze on the geometry (so the comparisons below see both).
  const float* sky = reference.pixel(kWidth / 2, kHeight / 4);
  const float* ground = reference.pixel(kWidth / 2, 3 * kHeight / 4);
  EXPECT_GT(sky[2], 10.0f * kGeometry[2]);
  EXPECT_NE(ground[2], kGeometry[2]);
  EXPECT_LT(ground[2], sky[2]);

  const int ox = 40, oy = 24, tw = kWidth + 80, th = kHeight + 48;
  std::string error;
  auto big = OffscreenTarget::create(tw, th, &error);
  ASSERT_TRUE(big) << error;
  vs.viewport[0] = ox;
  vs.viewport[1] = oy;

  // A viewport-sized texture.
  vs.depth_origin = ATMO_DEPTH_ORIGIN_VIEWPORT;
  const Image shifted_viewport = draw_sky_and_haze(f, *big, vs);
  // A framebuffer-sized texture holding the same depth at the viewport's pixels (far elsewhere).
  std::vector<float> window(static_cast<size_t>(tw) * th, 1.0f);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      window[static_cast<size_t>(y + oy) * tw + x + ox] = depth[static_cast<size_t>(y) * kWidth + x];
  const GLuint window_depth_texture = atmo::support::make_depth_texture(tw, th, window);
  vs.depth_texture = window_depth_texture;
  vs.depth_origin = ATMO_DEPTH_ORIGIN_WINDOW;
  const Image shifted_window = draw_sky_and_haze(f, *big, vs);

  const double d_viewport = block_difference(shifted_viewport, ox, oy, reference, 0, 0, kWidth, kHeight);
  const double d_window = block_difference(shifted_window, ox, oy, reference, 0, 0, kWidth, kHeight);
  std::printf("offset viewport (%d, %d): largest relative difference to the unshifted view: viewport-sized depth "
              "%.3g, framebuffer-sized depth %.3g\n", ox, oy, d_viewport, d_window);
  EXPECT_LE(d_viewport, 1e-5);
  EXPECT_LE(d_window, 1e-5);
  // Outside the viewport nothing is drawn.
  for (const Image* img : {&shifted_viewport, &shifted_window})
    for (int y = 0; y < th; ++y)
      for (int x = 0; x < tw; ++x) {
        if (x >= ox && x < ox + kWidth && y >= oy && y < oy + kHeight) continue;
        ASSERT_EQ(img->pixel(x, th - 1 - y)[2], kGeometry[2]) << "pixel (" << x << ", " << y << ") outside";
      }
  glDeleteTextures(1, &viewport_depth);
  glDeleteTextures(1, &window_depth_texture);
}

// ------------------------------------------------------------ depth formats

// The host's depth in each depth format a host renders to, and with its comparison mode on (a shadow-map
// habit): the plugin reads it through its own sampler object, whose compare mode is off, so the texture's
// GL_TEXTURE_COMPARE_MODE changes nothing; every format reads the distances its precision holds (docs/ABI.md,
// "The host's depth texture"). Reference: GL_DEPTH_COMPONENT32F.
GLuint depth_texture_in(GLenum internal_format, const std::vector<float>& depth, int w, int h) {
  GLuint t = 0;
  glGenTextures(1, &t);
  glBindTexture(GL_TEXTURE_2D, t);
  if (internal_format == GL_DEPTH24_STENCIL8) {
    std::vector<uint32_t> packed(depth.size());  // GL_UNSIGNED_INT_24_8: depth in the top 24 bits
    for (size_t i = 0; i < depth.size(); ++i)
      packed[i] = (static_cast<uint32_t>(std::lround(double(depth[i]) * 16777215.0)) << 8) | 0x5Au;
    glTexImage2D(GL_TEXTURE_2D, 0, internal_format, w, h, 0, GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8, packed.data());
  } else if (internal_format == GL_DEPTH32F_STENCIL8) {
    std::vector<uint32_t> packed(depth.size() * 2);  // GL_FLOAT_32_UNSIGNED_INT_24_8_REV: float, then stencil
    for (size_t i = 0; i < depth.size(); ++i) {
      std::memcpy(&packed[2 * i], &depth[i], 4);
      packed[2 * i + 1] = 0x5Au;
    }
    glTexImage2D(GL_TEXTURE_2D, 0, internal_format, w, h, 0, GL_DEPTH_STENCIL, GL_FLOAT_32_UNSIGNED_INT_24_8_REV,
                 packed.data());
  } else {
    glTexImage2D(GL_TEXTURE_2D, 0, internal_format, w, h, 0, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
  }
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glBindTexture(GL_TEXTURE_2D, 0);
  return t;
}

TEST(GlContract, DepthFormatsAndCompareModeReadTheSameDistances) {
  Fixture f;
  BandedView banded;
  AtmoViewState& vs = banded.vs;
  const std::vector<float>& depth = banded.depth;
  ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  const GLuint reference_texture = depth_texture_in(GL_DEPTH_COMPONENT32F, depth, kWidth, kHeight);
  vs.depth_texture = reference_texture;
  const Image reference = draw_sky_and_haze(f, *f.target, vs);

  struct Format {
    GLenum internal_format;
    const char* name;
    double bound;  // largest relative difference to the 32F reference
  };
  // Measured on llvmpipe: 24-bit (and DEPTH_COMPONENT32, stored as 24) 9.5e-4, 16-bit 0.105 -- at 30 km with
  // near = 1 m a 16-bit step spans kilometres: the docs name it unsuitable for aerial perspective.
  const Format formats[] = {{GL_DEPTH_COMPONENT32F, "DEPTH_COMPONENT32F", 0.0},
                            {GL_DEPTH32F_STENCIL8, "DEPTH32F_STENCIL8", 0.0},
                            {GL_DEPTH_COMPONENT24, "DEPTH_COMPONENT24", 2e-3},
                            {GL_DEPTH24_STENCIL8, "DEPTH24_STENCIL8", 2e-3},
                            {GL_DEPTH_COMPONENT32, "DEPTH_COMPONENT32", 2e-3},
                            {GL_DEPTH_COMPONENT16, "DEPTH_COMPONENT16", 0.2}};
  for (const Format& format : formats)
    for (bool compare : {false, true}) {
      const GLuint t = depth_texture_in(format.internal_format, depth, kWidth, kHeight);
      if (compare) {
        glBindTexture(GL_TEXTURE_2D, t);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
        glBindTexture(GL_TEXTURE_2D, 0);
      }
      ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR)) << format.name;
      vs.depth_texture = t;
      const Image image = draw_sky_and_haze(f, *f.target, vs);
      const double d = block_difference(image, 0, 0, reference, 0, 0, kWidth, kHeight);
      std::printf("%-19s compare mode %-22s: largest relative difference to DEPTH_COMPONENT32F %.3g\n",
                  format.name, compare ? "COMPARE_REF_TO_TEXTURE" : "NONE", d);
      EXPECT_LE(d, format.bound) << format.name << (compare ? " with its compare mode on" : "");
      EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
      glDeleteTextures(1, &t);
    }
  glDeleteTextures(1, &reference_texture);
}

TEST(GlContract, DepthOriginAndAerialRangeAreValidated) {
  Fixture f;
  const glm::dmat4 proj = glm::perspective(glm::radians(60.0), double(kWidth) / kHeight, 1.0, 1e5);
  AtmoViewState good = innsbruck_view(600.0, 0.0, 0.0, proj);
  const AtmoPluginApi& api = f.context->api();
  AtmoView view = f.view->handle();
  struct Case {
    const char* what;
    void (*spoil)(AtmoViewState*);
    AtmoResult want;
    const char* names;
  };
  const Case cases[] = {
      {"depth_origin 2", [](AtmoViewState* s) { s->depth_origin = 2; }, ATMO_ERROR_INVALID_ARGUMENT,
       "AtmoViewState.depth_origin = 2"},
      {"aerial_range_m 50", [](AtmoViewState* s) { s->aerial_range_m = 50.0; }, ATMO_ERROR_OUT_OF_RANGE,
       "AtmoViewState.aerial_range_m = 50"},
      {"aerial_range_m 2e7", [](AtmoViewState* s) { s->aerial_range_m = 2e7; }, ATMO_ERROR_OUT_OF_RANGE,
       "AtmoViewState.aerial_range_m"},
      {"aerial_range_m NaN", [](AtmoViewState* s) { s->aerial_range_m = std::nan(""); }, ATMO_ERROR_NON_FINITE_VALUE,
       "AtmoViewState.aerial_range_m"},
  };
  for (const Case& c : cases) {
    AtmoViewState s = good;
    c.spoil(&s);
    EXPECT_EQ(api.set_view(view, &s), c.want) << c.what;
    EXPECT_NE(std::string(api.last_error(f.context->handle())).find(c.names), std::string::npos)
        << c.what << ": " << api.last_error(f.context->handle());
  }
  AtmoViewState s = good;
  s.aerial_range_m = 100.0;
  EXPECT_EQ(api.set_view(view, &s), ATMO_SUCCESS);
  s.aerial_range_m = 1e7;
  EXPECT_EQ(api.set_view(view, &s), ATMO_SUCCESS);
}

// ------------------------------------------------------------ infinite far plane

// Reversed-Z projections (glClipControl zero-to-one): finite and infinite far plane.
glm::dmat4 reversed_projection(double fovy_rad, double aspect, double near_m, double far_m) {
  const double f = 1.0 / std::tan(0.5 * fovy_rad);
  glm::dmat4 p(0.0);
  p[0][0] = f / aspect;
  p[1][1] = f;
  p[2][3] = -1.0;
  if (std::isinf(far_m)) {
    p[3][2] = near_m;  // z_ndc = near / distance
  } else {
    p[2][2] = near_m / (far_m - near_m);
    p[3][2] = far_m * near_m / (far_m - near_m);
  }
  return p;
}

struct HazeRun {
  Image image;
  double range_m;
};

HazeRun haze_with(Fixture& f, const glm::dmat4& proj, double aerial_range_m, const std::vector<double>& bands) {
  AtmoViewState vs = innsbruck_view(600.0, 0.0, 0.0, proj);
  vs.exposure_scale = 1e-4;
  vs.depth_convention = ATMO_DEPTH_REVERSED_ZERO_TO_ONE;
  vs.aerial_range_m = aerial_range_m;
  const GLuint depth = atmo::support::make_depth_texture(
      kWidth, kHeight, banded_depth(kWidth, kHeight, proj, ATMO_DEPTH_REVERSED_ZERO_TO_ONE, bands));
  vs.depth_texture = depth;
  HazeRun run;
  run.image = draw_sky_and_haze(f, *f.target, vs);
  run.range_m = f.view->lighting().aerial_range_m;
  glDeleteTextures(1, &depth);
  return run;
}

// Relative differences of the geometry's pixels (lower half), sorted.
std::vector<double> geometry_differences(const Image& a, const Image& b) {
  std::vector<double> d;
  for (int y = kHeight / 2; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      for (int c = 0; c < 3; ++c) {
        const double va = a.pixel(x, y)[c], vb = b.pixel(x, y)[c];
        d.push_back(std::abs(va - vb) / std::max(std::abs(vb), 1e-9));
      }
  std::sort(d.begin(), d.end());
  return d;
}

// The default range does not depend on the projection (so the three depth conventions draw one image, and an
// infinite far plane does not stretch it): it is the farthest ground in sight (the eye's horizon plus a 8 849 m
// summit's), 423 km from 600 m, computed here independently; a 1000 km and a 100 km far plane draw the same
// image as an infinite one. A host's aerial_range_m is used as given.
TEST(GlContract, InfiniteFarPlaneKeepsTheAerialRange) {
  Fixture f;
  const double fovy = glm::radians(60.0), aspect = double(kWidth) / kHeight;
  const std::vector<double> bands = {500.0, 3000.0, 15000.0, 60000.0};
  const HazeRun infinite = haze_with(f, reversed_projection(fovy, aspect, 1.0, INFINITY), 0.0, bands);
  const HazeRun beyond = haze_with(f, reversed_projection(fovy, aspect, 1.0, 1e6), 0.0, bands);
  const HazeRun finite = haze_with(f, reversed_projection(fovy, aspect, 1.0, 1e5), 0.0, bands);

  // The mean Earth radius; the plugin uses its model sphere at the eye (6 379 km at Innsbruck), 0.07 % longer.
  const double r0 = 6371000.0, eye = 600.0, summit = 8849.0;
  const double ground_m =
      std::sqrt((r0 + eye) * (r0 + eye) - r0 * r0) + std::sqrt((r0 + summit) * (r0 + summit) - r0 * r0);
  std::printf("aerial range: infinite far %.0f m, 1000 km far %.0f m, 100 km far %.0f m; farthest ground %.0f m\n",
              infinite.range_m, beyond.range_m, finite.range_m, ground_m);
  EXPECT_NEAR(infinite.range_m, ground_m, 1e-3 * ground_m);
  EXPECT_EQ(beyond.range_m, infinite.range_m);
  EXPECT_EQ(finite.range_m, infinite.range_m);

  const std::vector<double> vs_beyond = geometry_differences(infinite.image, beyond.image);
  const std::vector<double> vs_finite = geometry_differences(infinite.image, finite.image);
  std::printf("geometry, infinite against 1000 km far plane: max %.3g; against 100 km far plane: max %.3g\n",
              vs_beyond.back(), vs_finite.back());
  EXPECT_LE(vs_beyond.back(), 1e-5);  // the same volume; only the depth's float precision differs
  EXPECT_LE(vs_finite.back(), 1e-5);

  // Set by the host: used as given (a shorter volume, finer slices: a different image).
  const double set_range_m = 144482.0;
  const HazeRun set = haze_with(f, reversed_projection(fovy, aspect, 1.0, INFINITY), set_range_m, bands);
  EXPECT_FLOAT_EQ(static_cast<float>(set.range_m), static_cast<float>(set_range_m));
  const std::vector<double> vs_set = geometry_differences(set.image, infinite.image);
  std::printf("infinite far plane with aerial_range_m = %.0f m against the default: max %.3g\n", set.range_m,
              vs_set.back());
  EXPECT_GT(vs_set.back(), 1e-4);  // the host's range reached the pass
}

}  // namespace
