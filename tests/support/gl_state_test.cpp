#include <glad/gl.h>
#include <gtest/gtest.h>

#include <string>

#include "atmo_support/gl_state.h"
#include "gl_test_util.h"

using namespace atmo::support;

namespace {
std::string join(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}
}  // namespace

class GlState : public GlTest {};

TEST_F(GlState, SnapshotHasManyValuesAndNoErrors) {
  const GlStateSnapshot s = capture_gl_state();
  EXPECT_GE(s.values.size(), 60u);
  EXPECT_TRUE(s.query_errors.empty()) << join(s.query_errors);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  for (const char* name : {"GL_CURRENT_PROGRAM", "GL_VERTEX_ARRAY_BINDING", "GL_DEPTH_FUNC", "GL_BLEND[7]",
                           "GL_COLOR_WRITEMASK[7]", "GL_TEXTURE_BINDING_CUBE_MAP[unit 15]",
                           "GL_SAMPLER_BINDING[unit 15]", "GL_CLIP_ORIGIN", "GL_CLIP_DEPTH_MODE", "GL_DRAW_BUFFER7",
                           "GL_CLIP_DISTANCE7", "GL_TRANSFORM_FEEDBACK_BINDING", "GL_PROVOKING_VERTEX",
                           "GL_POLYGON_MODE", "GL_STENCIL_BACK_WRITEMASK", "GL_UNPACK_ROW_LENGTH"}) {
    EXPECT_NE(s.find(name), nullptr) << name;
  }
  ASSERT_NE(s.find("GL_DEPTH_FUNC"), nullptr);
  EXPECT_EQ(s.find("GL_DEPTH_FUNC")->at(0), GL_LESS);
}

TEST_F(GlState, ConsecutiveCapturesAreEqual) {
  glActiveTexture(GL_TEXTURE4);  // capture switches units internally; must restore
  const GlStateSnapshot a = capture_gl_state();
  const GlStateSnapshot b = capture_gl_state();
  EXPECT_TRUE(diff_gl_state(a, b).empty()) << join(diff_gl_state(a, b));
  GLint active = 0;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
  EXPECT_EQ(active, GL_TEXTURE4);
}

TEST_F(GlState, DiffNamesChangedValue) {
  const GlStateSnapshot a = capture_gl_state();
  glDepthFunc(GL_LEQUAL);
  const GlStateSnapshot b = capture_gl_state();
  const auto lines = diff_gl_state(a, b);
  ASSERT_EQ(lines.size(), 1u) << join(lines);
  EXPECT_EQ(lines[0], "GL_DEPTH_FUNC: before 0x0201, after 0x0203");
}

TEST_F(GlState, CapturePreExistingErrorIsCleared) {
  glEnable(0xFFFF);  // GL_INVALID_ENUM left pending by a "host"
  const GlStateSnapshot s = capture_gl_state();
  EXPECT_TRUE(s.query_errors.empty()) << join(s.query_errors);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

TEST_F(GlState, UnusualStateChangesSnapshotAndDestructorRestores) {
  const GlStateSnapshot defaults = capture_gl_state();
  {
    UnusualGlState unusual;
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    const GlStateSnapshot odd = capture_gl_state();
    EXPECT_TRUE(odd.query_errors.empty()) << join(odd.query_errors);
    const auto lines = diff_gl_state(defaults, odd);
    EXPECT_GE(lines.size(), 40u) << join(lines);
    for (const char* name : {"GL_CURRENT_PROGRAM", "GL_VERTEX_ARRAY_BINDING", "GL_ACTIVE_TEXTURE",
                             "GL_DRAW_FRAMEBUFFER_BINDING", "GL_DEPTH_FUNC", "GL_DEPTH_WRITEMASK", "GL_BLEND[0]",
                             "GL_CULL_FACE_MODE", "GL_STENCIL_FAIL", "GL_COLOR_WRITEMASK[0]", "GL_VIEWPORT",
                             "GL_SCISSOR_TEST", "GL_TEXTURE_BINDING_3D[unit 7]", "GL_SAMPLER_BINDING[unit 3]",
                             "GL_UNIFORM_BUFFER_BINDING[2]", "GL_POLYGON_OFFSET_FACTOR"}) {
      bool found = false;
      for (const auto& l : lines) found |= l.rfind(std::string(name) + ":", 0) == 0;
      EXPECT_TRUE(found) << name << " not changed by UnusualGlState\n" << join(lines);
    }
    GLint program = 0, status = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &program);
    glGetProgramiv(static_cast<GLuint>(program), GL_LINK_STATUS, &status);
    EXPECT_EQ(status, GL_TRUE);
    glBindFramebuffer(GL_FRAMEBUFFER, unusual.fbo());
    EXPECT_EQ(glCheckFramebufferStatus(GL_FRAMEBUFFER), static_cast<GLenum>(GL_FRAMEBUFFER_COMPLETE));
  }
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  const GlStateSnapshot after = capture_gl_state();
  EXPECT_TRUE(diff_gl_state(defaults, after).empty()) << join(diff_gl_state(defaults, after));
}

TEST(GlStateCompat, CaptureWorksInCompatibilityProfile) {
  std::string error;
  auto gl = HeadlessGl::create(HeadlessGl::Profile::Compatibility, &error);
  ASSERT_NE(gl, nullptr) << error;
  const GlStateSnapshot defaults = capture_gl_state();
  EXPECT_GE(defaults.values.size(), 60u);
  EXPECT_TRUE(defaults.query_errors.empty()) << join(defaults.query_errors);
  {
    UnusualGlState unusual;
    EXPECT_FALSE(diff_gl_state(defaults, capture_gl_state()).empty());
  }
  const GlStateSnapshot after = capture_gl_state();
  EXPECT_TRUE(diff_gl_state(defaults, after).empty()) << join(diff_gl_state(defaults, after));
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

TEST(GlStateDiff, AbsentValuesAndFormatting) {
  GlStateSnapshot a, b;
  a.values = {{"GL_DEPTH_TEST", {0}}, {"GL_VIEWPORT", {0, 0, 16, 16}}, {"ONLY_BEFORE", {1}}};
  b.values = {{"GL_DEPTH_TEST", {1}}, {"GL_VIEWPORT", {0, 0, 8, 16}}, {"ONLY_AFTER", {2.5}}};
  const auto lines = diff_gl_state(a, b);
  ASSERT_EQ(lines.size(), 4u) << join(lines);
  EXPECT_EQ(lines[0], "GL_DEPTH_TEST: before false, after true");
  EXPECT_EQ(lines[1], "GL_VIEWPORT: before (0, 0, 16, 16), after (0, 0, 8, 16)");
  EXPECT_EQ(lines[2], "ONLY_BEFORE: before 1, after <absent>");
  EXPECT_EQ(lines[3], "ONLY_AFTER: before <absent>, after 2.5");
}
