// Shared fixture: every GL test gets a fresh core context; failing to make one
// FAILS the test (never skips), with HeadlessGl's message.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "atmo_support/headless_gl.h"

class GlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    gl_ = atmo::support::HeadlessGl::create(atmo::support::HeadlessGl::Profile::Core, &error);
    ASSERT_NE(gl_, nullptr) << error;
  }
  std::unique_ptr<atmo::support::HeadlessGl> gl_;
};
