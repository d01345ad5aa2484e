// Terrain drawn headless (EGL, llvmpipe) with each depth convention: the depth
// it writes inverts back to the ray-cast distance, lights show at night, the
// "none" kind draws nothing, and draw()/DepthSetup leave the GL state as found.
#include <cmath>
#include <memory>
#include <string>

#include <glad/gl.h>
#include <gtest/gtest.h>

#include "atmo_host_scene/depth_setup.h"
#include "atmo_host_scene/terrain.h"
#include "atmo_support/gl_state.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/offscreen_target.h"

namespace hs = atmo::host_scene;
namespace support = atmo::support;

namespace {

constexpr int kSize = 101;  // odd: the centre pixel's centre is on the view axis
constexpr double kFar = 100000.0;

class TerrainGl : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    gl_ = support::HeadlessGl::create(support::HeadlessGl::Profile::Core, &error);
    ASSERT_TRUE(gl_) << "no headless GL: " << error;  // fail, never skip (docs/TESTING.md)
    target_ = support::OffscreenTarget::create(kSize, kSize, &error);
    ASSERT_TRUE(target_) << error;
  }
  void TearDown() override {
    target_.reset();
    gl_.reset();
  }

  hs::ViewSetup view(hs::DepthConvention convention) const {
    hs::ViewSetup v;
    v.world_origin = {47.0, 8.0, 400.0};
    v.pose.position_enu_m = glm::dvec3(0.0, 0.0, 100.0);
    v.pose.heading_deg = 0.0;  // north, across the runway (heading 90) onto flat grass
    v.pose.pitch_deg = -30.0;
    v.vfov_rad = glm::radians(40.0);
    v.near_m = 0.5;
    v.far_m = kFar;
    v.depth_convention = convention;
    v.viewport = {0, 0, kSize, kSize};
    return v;
  }

  // Clears, draws inside a DepthSetup; returns the centre depth.
  float draw(const hs::Terrain& terrain, const hs::ViewSetup& v, const hs::SceneLighting& light) {
    target_->bind();
    {
      const hs::DepthSetup depth(v.depth_convention);
      EXPECT_TRUE(depth.ok());
      glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      terrain.draw(v, light);
    }
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    const std::vector<float> depth = target_->read_depth();
    return depth[static_cast<size_t>(kSize / 2) * kSize + kSize / 2];
  }

  std::unique_ptr<support::HeadlessGl> gl_;
  std::unique_ptr<support::OffscreenTarget> target_;
};

hs::SceneLighting sunny_day() {
  hs::SceneLighting l;
  l.sun_direction_enu = glm::normalize(glm::dvec3(0.3, -0.4, 0.8));
  l.sun_illuminance_lux = glm::dvec3(100000.0);
  l.sky_ambient_lux = glm::dvec3(15000.0);
  return l;
}

// Independent inverses of the three conventions.
double distance(hs::DepthConvention c, double depth, const hs::ViewSetup& v) {
  switch (c) {
    case hs::DepthConvention::Standard: {
      const double ndc = 2.0 * depth - 1.0;
      return 2.0 * v.near_m * v.far_m / (v.far_m + v.near_m - ndc * (v.far_m - v.near_m));
    }
    case hs::DepthConvention::Reversed: return v.near_m / depth;
    case hs::DepthConvention::Logarithmic: return std::exp2(depth * std::log2(v.far_m + 1.0)) - 1.0;
  }
  return 0.0;
}

}  // namespace

TEST_F(TerrainGl, DepthInvertsToRayDistance) {
  hs::Terrain terrain;
  std::string error;
  ASSERT_TRUE(terrain.gl_init(&error)) << error;
  // Ray along the view axis: 100 m down at 30 degrees meets the flat ground
  // (dropped by the curvature) about 200 m away; view-space depth w = that distance.
  const double ground = -hs::curvature_drop_m(0.0, 173.2);
  const double expected = (100.0 - ground) / std::sin(glm::radians(30.0));
  for (hs::DepthConvention c :
       {hs::DepthConvention::Standard, hs::DepthConvention::Reversed, hs::DepthConvention::Logarithmic}) {
    if (!hs::depth_convention_supported(c)) continue;
    const hs::ViewSetup v = view(c);
    const float depth = draw(terrain, v, sunny_day());
    EXPECT_NEAR(distance(c, depth, v), expected, 0.02) << hs::to_string(c) << " depth " << depth;
    const support::Image image = target_->read_color();
    const float* centre = image.pixel(kSize / 2, kSize / 2);
    EXPECT_GT(centre[1], 0.0f) << "lit grass is not black";
  }
  terrain.gl_shutdown();
}

TEST_F(TerrainGl, NoneDrawsNothing) {
  hs::TerrainOptions o;
  o.kind = hs::TerrainOptions::Kind::None;
  hs::Terrain terrain(o);
  std::string error;
  ASSERT_TRUE(terrain.gl_init(&error)) << error;
  const float depth = draw(terrain, view(hs::DepthConvention::Reversed), sunny_day());
  EXPECT_EQ(depth, 0.0f);  // still the reversed clear value
  const support::Image image = target_->read_color();
  for (size_t i = 0; i < image.rgba.size(); i += 4) ASSERT_EQ(image.rgba[i + 1], 0.0f);
  terrain.gl_shutdown();
}

TEST_F(TerrainGl, LightPointsShowAtNight) {
  hs::Terrain terrain;
  std::string error;
  ASSERT_TRUE(terrain.gl_init(&error)) << error;
  hs::ViewSetup v = view(hs::DepthConvention::Reversed);
  // Over the approach lights, looking down the runway.
  v.pose.position_enu_m = glm::dvec3(-2600.0, 0.0, 60.0);
  v.pose.heading_deg = 90.0;
  v.pose.pitch_deg = -5.0;
  v.vfov_rad = glm::radians(60.0);
  v.exposure_scale = hs::exposure_scale_from_ev100(0.0);
  const hs::SceneLighting night;  // no sun, no sky: only the lights give light
  draw(terrain, v, night);
  const support::Image image = target_->read_color();
  int lit = 0;
  for (size_t i = 0; i < image.rgba.size(); i += 4) lit += image.rgba[i] > 0.01f ? 1 : 0;
  EXPECT_GT(lit, 20);
  EXPECT_LT(lit, kSize * kSize / 4);  // points, not surfaces
  terrain.gl_shutdown();
}

TEST_F(TerrainGl, DrawAndDepthSetupRestoreGlState) {
  hs::Terrain terrain;
  std::string error;
  ASSERT_TRUE(terrain.gl_init(&error)) << error;
  for (hs::DepthConvention c :
       {hs::DepthConvention::Standard, hs::DepthConvention::Reversed, hs::DepthConvention::Logarithmic}) {
    target_->bind();
    const support::GlStateSnapshot before = support::capture_gl_state();
    {
      const hs::DepthSetup depth(c);
      terrain.draw(view(c), sunny_day());
    }
    const support::GlStateSnapshot after = support::capture_gl_state();
    const std::vector<std::string> diff = support::diff_gl_state(before, after);
    EXPECT_TRUE(diff.empty()) << hs::to_string(c) << ": " << (diff.empty() ? "" : diff.front());
  }
  terrain.gl_shutdown();
}
