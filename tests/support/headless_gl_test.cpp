#include <glad/gl.h>
#include <gtest/gtest.h>

#include <string>

#include "atmo_support/headless_gl.h"

using atmo::support::HeadlessGl;

namespace {

void expect_working_context(HeadlessGl& gl, bool want_core) {
  EXPECT_FALSE(gl.renderer().empty());
  EXPECT_FALSE(gl.version().empty());
  EXPECT_EQ(gl.is_core(), want_core);
  EXPECT_GE(gl.major_version() * 10 + gl.minor_version(), 33);
  // A real GL call through glad works and leaves no error.
  glClearColor(0.5f, 0.25f, 0.125f, 1.0f);
  GLfloat c[4] = {};
  glGetFloatv(GL_COLOR_CLEAR_VALUE, c);
  EXPECT_FLOAT_EQ(c[1], 0.25f);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
}

}  // namespace

TEST(HeadlessGl, CreatesCoreContext) {
  std::string error;
  auto gl = HeadlessGl::create(HeadlessGl::Profile::Core, &error);
  ASSERT_NE(gl, nullptr) << error;  // fail, never skip: CI must have Mesa
  EXPECT_TRUE(error.empty());
  std::printf("renderer: %s\nversion: %s\nplatform: %s\n", gl->renderer().c_str(), gl->version().c_str(),
              gl->platform().c_str());
  expect_working_context(*gl, true);
  EXPECT_EQ(gl->major_version() * 10 + gl->minor_version(), 45);  // llvmpipe has 4.5 core
}

TEST(HeadlessGl, CreatesCompatibilityContext) {
  std::string error;
  auto gl = HeadlessGl::create(HeadlessGl::Profile::Compatibility, &error);
  ASSERT_NE(gl, nullptr) << error;
  expect_working_context(*gl, false);
}

TEST(HeadlessGl, DestroyAndRecreate) {
  for (int round = 0; round < 3; ++round) {
    std::string error;
    auto gl = HeadlessGl::create(HeadlessGl::Profile::Core, &error);
    ASSERT_NE(gl, nullptr) << "round " << round << ": " << error;
    expect_working_context(*gl, true);
    GLuint tex = 0;
    glGenTextures(1, &tex);
    EXPECT_NE(tex, 0u);
    gl.reset();  // context loss as the plugin's tests simulate it
  }
}

TEST(HeadlessGl, TwoAliveAtOnceAndSwitch) {
  std::string error;
  auto a = HeadlessGl::create(HeadlessGl::Profile::Core, &error);
  ASSERT_NE(a, nullptr) << error;
  auto b = HeadlessGl::create(HeadlessGl::Profile::Core, &error);
  ASSERT_NE(b, nullptr) << error;
  a->make_current();
  glClearColor(1, 0, 0, 1);
  b->make_current();
  glClearColor(0, 1, 0, 1);
  a->make_current();
  GLfloat c[4] = {};
  glGetFloatv(GL_COLOR_CLEAR_VALUE, c);
  EXPECT_EQ(c[0], 1.0f);  // separate contexts keep separate state
  b.reset();              // must not terminate the display under a
  a->make_current();
  glGetFloatv(GL_COLOR_CLEAR_VALUE, c);
  EXPECT_EQ(c[0], 1.0f);
  EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  a->release_current();
}

TEST(HeadlessGl, ProcAddressMatchesLoaderSignature) {
  std::string error;
  auto gl = HeadlessGl::create(HeadlessGl::Profile::Core, &error);
  ASSERT_NE(gl, nullptr) << error;
  void* (*loader)(void*, const char*) = &HeadlessGl::get_proc_address;
  EXPECT_NE(loader(nullptr, "glDrawArrays"), nullptr);
  EXPECT_NE(loader(nullptr, "glClipControl"), nullptr);
}
