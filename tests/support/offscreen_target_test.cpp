#include <glad/gl.h>
#include <gtest/gtest.h>

#include "atmo_support/gl_state.h"
#include "atmo_support/offscreen_target.h"
#include "gl_test_util.h"

using namespace atmo::support;

class Offscreen : public GlTest {};

TEST_F(Offscreen, ClearAndReadBack) {
  std::string error;
  auto t = OffscreenTarget::create(32, 24, &error);
  ASSERT_NE(t, nullptr) << error;
  EXPECT_EQ(t->width(), 32);
  EXPECT_EQ(t->height(), 24);
  EXPECT_NE(t->fbo(), 0u);
  GLint fmt = 0;
  glBindTexture(GL_TEXTURE_2D, t->color_texture());
  glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_INTERNAL_FORMAT, &fmt);
  EXPECT_EQ(fmt, GL_RGBA32F);
  glBindTexture(GL_TEXTURE_2D, t->depth_texture());
  glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_INTERNAL_FORMAT, &fmt);
  EXPECT_EQ(fmt, GL_DEPTH_COMPONENT32F);
  glBindTexture(GL_TEXTURE_2D, 0);

  t->bind();
  glClearColor(0.25f, 2.5f, -1.0f, 0.5f);  // float target: no clamping
  glClearDepth(0.75);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const Image img = t->read_color();
  ASSERT_EQ(img.width, 32);
  ASSERT_EQ(img.height, 24);
  ASSERT_EQ(img.rgba.size(), 32u * 24u * 4u);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const float* p = img.pixel(x, y);
      ASSERT_EQ(p[0], 0.25f);
      ASSERT_EQ(p[1], 2.5f);
      ASSERT_EQ(p[2], -1.0f);
      ASSERT_EQ(p[3], 0.5f);
    }
  const auto depth = t->read_depth();
  ASSERT_EQ(depth.size(), 32u * 24u);
  for (float d : depth) ASSERT_FLOAT_EQ(d, 0.75f);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

TEST_F(Offscreen, RowZeroIsTop) {
  std::string error;
  auto t = OffscreenTarget::create(8, 6, &error);
  ASSERT_NE(t, nullptr) << error;
  t->clear(0, 0, 1, 1, 1.0f);  // blue everywhere
  // GL's window y grows upwards: the scissor box y = 3..5 is the top half.
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, 3, 8, 3);
  glClearColor(1, 0, 0, 1);
  glClearDepth(0.25);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
  const Image img = t->read_color();
  const auto depth = t->read_depth();
  for (int y = 0; y < 6; ++y) {
    const bool top = y < 3;
    EXPECT_EQ(img.pixel(5, y)[0], top ? 1.0f : 0.0f) << "row " << y;
    EXPECT_EQ(img.pixel(5, y)[2], top ? 0.0f : 1.0f) << "row " << y;
    EXPECT_FLOAT_EQ(depth[static_cast<size_t>(y) * 8 + 5], top ? 0.25f : 1.0f) << "row " << y;
  }
}

TEST_F(Offscreen, ReadBackKeepsHostState) {
  std::string error;
  auto t = OffscreenTarget::create(4, 4, &error);
  ASSERT_NE(t, nullptr) << error;
  t->clear(1, 1, 1, 1);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  const GlStateSnapshot before = capture_gl_state();
  (void)t->read_color();
  (void)t->read_depth();
  const auto lines = diff_gl_state(before, capture_gl_state());
  EXPECT_TRUE(lines.empty()) << (lines.empty() ? "" : lines[0]);
}

TEST_F(Offscreen, CreateDoesNotChangeBindingsAndRejectsBadSize) {
  const GlStateSnapshot before = capture_gl_state();
  std::string error;
  auto t = OffscreenTarget::create(16, 16, &error);
  ASSERT_NE(t, nullptr) << error;
  EXPECT_TRUE(diff_gl_state(before, capture_gl_state()).empty());
  EXPECT_EQ(OffscreenTarget::create(0, 16, &error), nullptr);
  EXPECT_FALSE(error.empty());
}
