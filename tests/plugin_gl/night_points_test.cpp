// The night sky's point-source pass (plugin/gl/night_renderer, shaders/
// night_points.*) on a headless GL context, driven directly (the plugin's GL
// layer linked statically; the tables computed by the core on the CPU and
// uploaded here, as the Renderer does).
//
// Proved: one star drawn at 100 sub-pixel offsets into an RGBA32F target
// sums to the same light within 1 %, and to E·T/Omega·exposure (T from the
// CPU twin of the transmittance table, Omega from the core's
// pixel_solid_angle_sr) within 2 %, centred on its exact position; a star
// just outside the viewport's edge still lights the edge pixels and nothing
// is written outside the viewport; host geometry, the Earth and the camera's
// back hide stars; an empty list makes no GL call and leaves the framebuffer
// as it was; GL state is restored (the support library's snapshot, on
// deliberately unusual host state); the display-encoded output is
// encode(exposure · (L_sky + L_star)) on a dark sky, and drawing twice
// changes nothing there (MAX), while the linear output adds.
// Figures are printed with the prefix "[ night gl ]" and quoted in docs/NIGHT_SKY.md.
#include <glad/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <string>
#include <vector>

#include "atmo_support/gl_state.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/offscreen_target.h"
#include "core/atmosphere/atmosphere_model.h"
#include "core/night_sky/point_sources.h"
#include "core/night_sky/star_photometry.h"
#include "core/atmosphere/shader_twin.h"
#include "core/sky/sky_view_table.h"
#include "gl/night_renderer.h"

namespace {

using atmo::support::HeadlessGl;
using atmo::support::Image;
using atmo::support::OffscreenTarget;
namespace night = atmo::core::night;
namespace core = atmo::core;
namespace twin = atmo::twin;

constexpr int kW = 160;
constexpr int kH = 120;
constexpr double kFovY = 60.0;
constexpr float kEyeAltitudeM = 1000.0f;
constexpr double kPi = 3.14159265358979323846;

// The air and its tables, computed once (CPU, the Renderer's sizes).
const core::ModelTables& tables() {
  static const core::ModelTables t = core::compute_model_tables(core::AtmosphereSettings{}, 6371000.0);
  return t;
}

GLuint upload(const twin::Lut2D& table) {
  GLuint t = 0;
  glGenTextures(1, &t);
  glBindTexture(GL_TEXTURE_2D, t);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, table.width, table.height, 0, GL_RGB, GL_FLOAT, table.texels.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  glBindTexture(GL_TEXTURE_2D, 0);
  return t;
}

glm::dmat4 look(double heading_deg, double pitch_deg) {
  const double h = glm::radians(heading_deg), p = glm::radians(pitch_deg);
  const glm::dvec3 forward(std::sin(h) * std::cos(p), std::cos(h) * std::cos(p), std::sin(p));
  return glm::lookAt(glm::dvec3(0.0), forward, glm::dvec3(0, 0, 1));
}

// Sum of each colour channel over the whole image.
glm::dvec3 sum_rgb(const Image& img) {
  glm::dvec3 s(0.0);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) s += glm::dvec3(img.pixel(x, y)[0], img.pixel(x, y)[1], img.pixel(x, y)[2]);
  return s;
}

class NightPoints : public ::testing::Test {
 protected:
  void SetUp() override { start(HeadlessGl::Profile::Core); }
  void start(HeadlessGl::Profile profile) {
    std::string error;
    gl_ = HeadlessGl::create(profile, &error);
    ASSERT_NE(gl_, nullptr) << error;
    target_ = OffscreenTarget::create(kW, kH, &error);
    ASSERT_NE(target_, nullptr) << error;
    ASSERT_TRUE(renderer_.init(&error)) << error;
    textures_.transmittance = upload(tables().transmittance);
    textures_.transmittance_size = glm::vec2(tables().transmittance.width, tables().transmittance.height);
    textures_.multiple_scattering = upload(tables().multiple_scattering);
    textures_.multiple_scattering_size =
        glm::vec2(tables().multiple_scattering.width, tables().multiple_scattering.height);
    in_.atmosphere = tables().atmosphere;
    in_.eye_altitude_m = kEyeAltitudeM;
    in_.sun_direction_enu = glm::vec3(0.0f, -std::cos(0.3f), -std::sin(0.3f));  // 17° below the horizon
    in_.viewport[0] = 0;
    in_.viewport[1] = 0;
    in_.viewport[2] = kW;
    in_.viewport[3] = kH;
    in_.exposure = 1.0f;
    in_.output_encoding = 0;
    in_.method = atmo::gl::SkyMethod::kLut;
    set_camera(0.0, 20.0);
  }
  void TearDown() override {
    if (!gl_) return;
    renderer_.destroy();
    for (GLuint* t : {&textures_.transmittance, &textures_.multiple_scattering, &textures_.sky_view})
      if (*t) glDeleteTextures(1, t);
    textures_ = {};
    target_.reset();
    gl_.reset();
  }

  void set_camera(double heading_deg, double pitch_deg) {
    view_from_world_ = look(heading_deg, pitch_deg);
    // Square pixels in the current viewport.
    projection_ = glm::perspective(glm::radians(kFovY), static_cast<double>(in_.viewport[2]) / in_.viewport[3], 0.5,
                                   20000.0);
    in_.enu_from_view = glm::mat3(glm::transpose(glm::dmat3(view_from_world_)));
    in_.view_from_clip = glm::mat4(glm::inverse(projection_));
  }

  // The ENU direction through window position (px, py) (pixel centres at +0.5)
  // of the current viewport, and the cosine of its angle from the optical axis.
  glm::dvec3 direction_at(double px, double py, double* cos_off_axis = nullptr) const {
    const glm::dvec2 ndc((px - in_.viewport[0]) / in_.viewport[2] * 2.0 - 1.0,
                         (py - in_.viewport[1]) / in_.viewport[3] * 2.0 - 1.0);
    const glm::dvec4 p = glm::inverse(projection_) * glm::dvec4(ndc, -1.0, 1.0);
    const glm::dvec3 view = glm::normalize(glm::dvec3(p) / p.w);
    if (cos_off_axis) *cos_off_axis = -view.z;
    return glm::transpose(glm::dmat3(view_from_world_)) * view;
  }

  // The window position of an ENU direction (at infinity).
  glm::dvec2 window_of(const glm::dvec3& enu) const {
    const glm::dvec4 clip = projection_ * glm::dvec4(glm::dmat3(view_from_world_) * enu, 0.0);
    const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
    return glm::dvec2(in_.viewport[0], in_.viewport[1]) +
           (ndc * 0.5 + 0.5) * glm::dvec2(in_.viewport[2], in_.viewport[3]);
  }

  static night::PointSource source(const glm::dvec3& dir, const glm::vec3& lux) {
    night::PointSource s;
    s.direction_enu = glm::vec3(glm::normalize(dir));
    s.illuminance_rgb_lux = lux;
    s.v_mag = static_cast<float>(night::magnitude_from_illuminance(lux.g));
    return s;
  }

  // E·T/Omega·exposure for a source at window position (px, py): the light its pixels must sum to.
  glm::dvec3 expected_sum(double px, double py, const glm::vec3& lux) const {
    double cos_axis = 1.0;
    const glm::dvec3 dir = direction_at(px, py, &cos_axis);
    const auto& t = tables();
    const glm::vec3 tr = twin::transmittance_to_sun(t.atmosphere, t.transmittance,
                                                    glm::vec2(t.transmittance.width, t.transmittance.height),
                                                    t.atmosphere.bottom_radius_m + kEyeAltitudeM, static_cast<float>(dir.z));
    const double omega = night::pixel_solid_angle_sr(std::tan(glm::radians(kFovY) / 2.0), in_.viewport[3], cos_axis);
    return glm::dvec3(lux) * glm::dvec3(tr) / omega * static_cast<double>(in_.exposure);
  }

  bool draw(const std::vector<night::PointSource>& s, std::string* error) {
    return renderer_.draw_points(in_, textures_, s, error);
  }

  std::unique_ptr<HeadlessGl> gl_;
  std::unique_ptr<OffscreenTarget> target_;
  atmo::gl::NightRenderer renderer_;
  atmo::gl::NightSkyTextures textures_;
  atmo::gl::PassInputs in_;
  glm::dmat4 view_from_world_{1.0}, projection_{1.0};
};

TEST_F(NightPoints, TotalLightIsTheSameAtEverySubPixelOffsetAndPhotometric) {
  const glm::vec3 lux(1.0e-3f, 2.0e-3f, 3.0e-3f);
  double min_ratio = 1e9, max_ratio = 0.0, worst_centroid = 0.0, worst_channel = 0.0;
  std::string error;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) {
      const double px = 80.0 + 0.1 * i + 0.05, py = 60.0 + 0.1 * j + 0.05;
      target_->clear(0.0f, 0.0f, 0.0f, 0.0f);
      ASSERT_TRUE(draw({source(direction_at(px, py), lux)}, &error)) << error;
      const Image img = target_->read_color();
      const glm::dvec3 sum = sum_rgb(img);
      const glm::dvec3 expect = expected_sum(px, py, lux);
      for (int c = 0; c < 3; ++c) {
        const double ratio = sum[c] / expect[c];
        min_ratio = std::min(min_ratio, ratio);
        max_ratio = std::max(max_ratio, ratio);
        // Colour: each channel keeps its own illuminance and transmittance.
        worst_channel = std::max(worst_channel, std::abs(ratio - sum[1] / expect[1]));
      }
      // Centroid of the green channel = the star's window position (row 0 = top).
      glm::dvec2 centroid(0.0);
      double total = 0.0;
      for (int y = 0; y < kH; ++y) {
        for (int x = 0; x < kW; ++x) {
          const double g = img.pixel(x, y)[1];
          centroid += g * glm::dvec2(x + 0.5, (kH - 1 - y) + 0.5);
          total += g;
        }
      }
      centroid /= total;
      worst_centroid = std::max(worst_centroid, glm::length(centroid - glm::dvec2(px, py)));
      // Alpha untouched (adds 0).
      EXPECT_EQ(img.pixel(80, kH - 1 - 60)[3], 0.0f);
    }
  }
  std::printf("[ night gl ] one star at 10x10 sub-pixel offsets (%dx%d, %.0f deg, elevation ~20 deg, 1 km): summed "
              "light / (E T / Omega exposure) = %.5f .. %.5f (spread %.3f %%), channels agree to %.1e, centroid "
              "within %.4f px\n",
              kW, kH, kFovY, min_ratio, max_ratio, (max_ratio / min_ratio - 1.0) * 100.0, worst_channel,
              worst_centroid);
  EXPECT_LT(max_ratio / min_ratio - 1.0, 0.01);
  EXPECT_GT(min_ratio, 0.98);
  EXPECT_LT(max_ratio, 1.02);
  EXPECT_LT(worst_centroid, 0.02);
}

TEST_F(NightPoints, StarAtTheViewportEdgeLightsOnlyTheViewport) {
  // The host's viewport is inset in the target; a star 1.2 px outside its
  // left edge (GL would discard a point whose centre is outside the viewport)
  // still lights the edge pixels, and nothing is drawn outside the viewport.
  in_.viewport[0] = 10;
  in_.viewport[1] = 8;
  in_.viewport[2] = kW - 20;
  in_.viewport[3] = kH - 16;
  set_camera(0.0, 20.0);
  const glm::vec3 lux(2.0e-3f);
  std::string error;
  const double px = 10.0 - 1.2, py = 60.3;
  target_->clear(0.0f, 0.0f, 0.0f, 0.0f);
  ASSERT_TRUE(draw({source(direction_at(px, py), lux)}, &error)) << error;
  const Image img = target_->read_color();
  double inside = 0.0, outside = 0.0, expected_weight = 0.0;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const int wy = kH - 1 - y;  // window row
      const bool in_viewport = x >= in_.viewport[0] && x < in_.viewport[0] + in_.viewport[2] && wy >= in_.viewport[1] &&
                               wy < in_.viewport[1] + in_.viewport[3];
      (in_viewport ? inside : outside) += img.pixel(x, y)[1];
      if (in_viewport && std::abs(x + 0.5 - px) <= 3.5 && std::abs(wy + 0.5 - py) <= 3.5)
        expected_weight += night::star_footprint_weight(x + 0.5 - px, wy + 0.5 - py);
    }
  }
  const double expect = expected_sum(px, py, lux).g * expected_weight;
  std::printf("[ night gl ] star 1.2 px outside the viewport's edge: %.4f of its light drawn on the edge pixels "
              "(expected %.4f), outside the viewport %.3g\n",
              inside / (expected_sum(px, py, lux).g), expected_weight, outside);
  EXPECT_GT(expected_weight, 0.02);
  EXPECT_NEAR(inside, expect, 0.02 * expect);
  EXPECT_EQ(outside, 0.0);
}

TEST_F(NightPoints, HostGeometryTheEarthAndTheCameraBackHideStars) {
  // Host depth: geometry (0.5) on the left half, far plane (1.0) on the right.
  std::vector<float> depth(static_cast<size_t>(kW) * kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) depth[static_cast<size_t>(y) * kW + x] = x < kW / 2 ? 0.5f : 1.0f;
  GLuint depth_texture = 0;
  glGenTextures(1, &depth_texture);
  glBindTexture(GL_TEXTURE_2D, depth_texture);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, kW, kH, 0, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glBindTexture(GL_TEXTURE_2D, 0);
  in_.depth_texture = depth_texture;
  const glm::vec3 lux(2.0e-3f);
  std::string error;

  auto light_of = [&](const std::vector<night::PointSource>& s) {
    target_->clear(0.0f, 0.0f, 0.0f, 0.0f);
    EXPECT_TRUE(draw(s, &error)) << error;
    return sum_rgb(target_->read_color()).g;
  };
  const double behind_geometry = light_of({source(direction_at(40.3, 60.2), lux)});
  const double over_sky = light_of({source(direction_at(120.3, 60.2), lux)});
  const double over_sky_expected = expected_sum(120.3, 60.2, lux).g;
  EXPECT_EQ(behind_geometry, 0.0);
  EXPECT_NEAR(over_sky, over_sky_expected, 0.02 * over_sky_expected);
  in_.depth_texture = 0;
  // Behind the camera: the direction opposite to a visible one.
  const double behind_camera = light_of({source(-direction_at(80.3, 60.2), lux)});
  EXPECT_EQ(behind_camera, 0.0);
  // The Earth: from 1 km the horizon dips 1.0°; a star 3° below the horizontal
  // is behind the Earth, one 3° above is seen (camera pitched down 3°).
  set_camera(0.0, -3.0);
  const double below = light_of({source(glm::dvec3(0.0, std::cos(3.0 * kPi / 180), -std::sin(3.0 * kPi / 180)), lux)});
  const double above = light_of({source(glm::dvec3(0.0, std::cos(3.0 * kPi / 180), std::sin(3.0 * kPi / 180)), lux)});
  EXPECT_EQ(below, 0.0);
  EXPECT_GT(above, 0.0);
  const glm::dvec2 above_px = window_of(glm::dvec3(0.0, std::cos(3.0 * kPi / 180), std::sin(3.0 * kPi / 180)));
  const double above_expected = expected_sum(above_px.x, above_px.y, lux).g;
  EXPECT_NEAR(above, above_expected, 0.02 * above_expected);
  std::printf("[ night gl ] hidden: behind host geometry %.3g, behind the camera %.3g, 3 deg below the horizon "
              "from 1 km %.3g; seen: over the sky %.5g (expected %.5g), 3 deg above the horizon %.5g (expected %.5g)\n",
              behind_geometry, behind_camera, below, over_sky, over_sky_expected, above, above_expected);
  glDeleteTextures(1, &depth_texture);
}

TEST_F(NightPoints, FromAboveTheAtmosphereStarsSetThroughTheLimb) {
  // Eye at 150 km (the air ends at 100 km): a star above the horizontal has
  // no air in the way; one seen through the atmosphere's limb is dimmed by
  // the air along the chord (looked up where the ray enters); one behind
  // the Earth (its limb dips 12.3°) is hidden.
  in_.eye_altitude_m = 150000.0f;
  in_.method = atmo::gl::SkyMethod::kMarch;
  const glm::vec3 lux(2.0e-3f);
  std::string error;
  auto ratio_at = [&](double elevation_deg) {
    set_camera(0.0, elevation_deg);
    target_->clear(0.0f, 0.0f, 0.0f, 0.0f);
    const double e = elevation_deg * kPi / 180.0;
    EXPECT_TRUE(draw({source(glm::dvec3(0.0, std::cos(e), std::sin(e)), lux)}, &error)) << error;
    const double omega = night::pixel_solid_angle_sr(std::tan(glm::radians(kFovY) / 2.0), kH, 1.0);
    return sum_rgb(target_->read_color()).g / (lux.g / omega);  // the transmittance
  };
  const double up = ratio_at(10.0), level = ratio_at(-5.0), limb_45km = ratio_at(-10.3), limb_17km = ratio_at(-11.6),
               earth = ratio_at(-13.0);
  std::printf("[ night gl ] from 150 km, green transmittance: +10 deg %.4f, -5 deg %.4f, through the limb at 45 km "
              "%.4f, at 17 km %.4f, behind the Earth %.3g\n",
              up, level, limb_45km, limb_17km, earth);
  EXPECT_NEAR(up, 1.0, 0.01);
  EXPECT_NEAR(level, 1.0, 0.01);
  EXPECT_LT(limb_45km, 1.0);
  EXPECT_GT(limb_45km, limb_17km);
  EXPECT_GT(limb_17km, 0.0);
  EXPECT_EQ(earth, 0.0);
}

TEST_F(NightPoints, CompatibilityProfileWithSmoothPoints) {
  // A compatibility context whose host left point smoothing on (round,
  // antialiased points would cut the footprint's corners; llvmpipe draws
  // squares either way, other drivers do not): the pass switches it off while
  // drawing and puts it back, and the light is all there.
  TearDown();
  start(HeadlessGl::Profile::Compatibility);
  ASSERT_NE(gl_, nullptr);
  ASSERT_FALSE(gl_->is_core()) << "no compatibility context here (Mesa gives one; fail, never skip)";
  constexpr GLenum kPointSmooth = 0x0B10;
  glEnable(kPointSmooth);
  target_->clear(0.0f, 0.0f, 0.0f, 0.0f);
  const atmo::support::GlStateSnapshot before = atmo::support::capture_gl_state();
  const glm::vec3 lux(2.0e-3f);
  const double px = 80.3, py = 60.6;
  std::string error;
  ASSERT_TRUE(draw({source(direction_at(px, py), lux)}, &error)) << error;
  const atmo::support::GlStateSnapshot after = atmo::support::capture_gl_state();
  const auto diff = atmo::support::diff_gl_state(before, after);
  EXPECT_TRUE(diff.empty()) << (diff.empty() ? "" : diff[0]);
  EXPECT_TRUE(glIsEnabled(kPointSmooth));
  glDisable(kPointSmooth);
  const double ratio = sum_rgb(target_->read_color()).g / expected_sum(px, py, lux).g;
  std::printf("[ night gl ] compatibility profile (%s), point smoothing left on by the host: summed light / "
              "expected %.5f, %zu state values compared, %zu differ\n",
              gl_->version().c_str(), ratio, before.values.size(), diff.size());
  EXPECT_NEAR(ratio, 1.0, 0.01);
}

// Counts calls through a few glad entry points the pass uses first, to prove
// that an empty list makes no GL call at all.
int g_gl_calls = 0;
PFNGLGETERRORPROC real_get_error = nullptr;
PFNGLGETINTEGERVPROC real_get_integerv = nullptr;
PFNGLISENABLEDPROC real_is_enabled = nullptr;
PFNGLUSEPROGRAMPROC real_use_program = nullptr;
PFNGLBINDBUFFERPROC real_bind_buffer = nullptr;
PFNGLDRAWARRAYSPROC real_draw_arrays = nullptr;
GLenum GLAD_API_PTR count_get_error() { ++g_gl_calls; return real_get_error(); }
void GLAD_API_PTR count_get_integerv(GLenum a, GLint* b) { ++g_gl_calls; real_get_integerv(a, b); }
GLboolean GLAD_API_PTR count_is_enabled(GLenum a) { ++g_gl_calls; return real_is_enabled(a); }
void GLAD_API_PTR count_use_program(GLuint a) { ++g_gl_calls; real_use_program(a); }
void GLAD_API_PTR count_bind_buffer(GLenum a, GLuint b) { ++g_gl_calls; real_bind_buffer(a, b); }
void GLAD_API_PTR count_draw_arrays(GLenum a, GLint b, GLsizei c) { ++g_gl_calls; real_draw_arrays(a, b, c); }

struct CountGlCalls {
  CountGlCalls() {
    real_get_error = glad_glGetError;
    real_get_integerv = glad_glGetIntegerv;
    real_is_enabled = glad_glIsEnabled;
    real_use_program = glad_glUseProgram;
    real_bind_buffer = glad_glBindBuffer;
    real_draw_arrays = glad_glDrawArrays;
    glad_glGetError = count_get_error;
    glad_glGetIntegerv = count_get_integerv;
    glad_glIsEnabled = count_is_enabled;
    glad_glUseProgram = count_use_program;
    glad_glBindBuffer = count_bind_buffer;
    glad_glDrawArrays = count_draw_arrays;
    g_gl_calls = 0;
  }
  ~CountGlCalls() {
    glad_glGetError = real_get_error;
    glad_glGetIntegerv = real_get_integerv;
    glad_glIsEnabled = real_is_enabled;
    glad_glUseProgram = real_use_program;
    glad_glBindBuffer = real_bind_buffer;
    glad_glDrawArrays = real_draw_arrays;
  }
};

TEST_F(NightPoints, EmptyListMakesNoGlCallAndChangesNothing) {
  target_->clear(0.25f, 0.5f, 0.75f, 1.0f);
  const Image before = target_->read_color();
  std::string error;
  int empty_calls = 0, one_star_calls = 0;
  {
    CountGlCalls count;
    EXPECT_TRUE(draw({}, &error)) << error;
    EXPECT_TRUE(renderer_.draw_points(in_, textures_, nullptr, 0, &error)) << error;
    empty_calls = g_gl_calls;
  }
  const Image after = target_->read_color();
  EXPECT_EQ(before.rgba, after.rgba);
  {
    CountGlCalls count;  // the instrumentation sees a real draw
    EXPECT_TRUE(draw({source(direction_at(80.5, 60.5), glm::vec3(1e-3f))}, &error)) << error;
    one_star_calls = g_gl_calls;
  }
  std::printf("[ night gl ] empty list: %d GL calls (one star: %d through the same entry points), framebuffer "
              "unchanged\n",
              empty_calls, one_star_calls);
  EXPECT_EQ(empty_calls, 0);
  EXPECT_GT(one_star_calls, 5);
  EXPECT_EQ(renderer_.counters().draws, 1u);
}

TEST_F(NightPoints, GlStateIsRestoredOnDefaultAndUnusualHostState) {
  std::string error;
  for (bool unusual_state : {false, true}) {
    for (int encoding : {0, 1}) {
      target_->bind();
      std::unique_ptr<atmo::support::UnusualGlState> unusual;
      if (unusual_state) {
        unusual = std::make_unique<atmo::support::UnusualGlState>();
        // The host's own viewport of the unusual state (its FBO is 64x64).
        in_.viewport[0] = 3;
        in_.viewport[1] = 5;
        in_.viewport[2] = 50;
        in_.viewport[3] = 40;
      }
      set_camera(0.0, 20.0);
      in_.output_encoding = encoding;
      const atmo::support::GlStateSnapshot before = atmo::support::capture_gl_state();
      std::vector<night::PointSource> stars;
      for (int k = 0; k < 50; ++k) stars.push_back(source(direction_at(5.0 + k, 10.0 + 0.6 * k), glm::vec3(1e-3f)));
      EXPECT_TRUE(draw(stars, &error)) << error;
      const atmo::support::GlStateSnapshot after = atmo::support::capture_gl_state();
      const auto diff = atmo::support::diff_gl_state(before, after);
      std::string lines;
      for (const auto& l : diff) lines += l + "\n";
      EXPECT_TRUE(diff.empty()) << "encoding " << encoding << ":\n" << lines;
      EXPECT_TRUE(after.query_errors.empty());
      EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
      std::printf("[ night gl ] GL state, %s host state, encoding %d: %zu values compared, %zu differ\n",
                  unusual_state ? "unusual" : "default", encoding, before.values.size(), diff.size());
    }
  }
}

TEST_F(NightPoints, DisplayEncodedOutputOnADarkSky) {
  // The sky-view table of this view (CPU; the GPU builds the same texels).
  const auto& t = tables();
  const twin::Lut2D sky_view = core::compute_sky_view_table(t.atmosphere, t.transmittance, t.multiple_scattering,
                                                            kEyeAltitudeM, in_.sun_direction_enu.z);
  GLuint sky_view_texture = 0;
  glGenTextures(1, &sky_view_texture);
  glBindTexture(GL_TEXTURE_2D, sky_view_texture);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, sky_view.width, sky_view.height, 0, GL_RGB, GL_FLOAT,
               sky_view.texels.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  glBindTexture(GL_TEXTURE_2D, 0);
  textures_.sky_view = sky_view_texture;
  textures_.sky_view_size = glm::vec2(sky_view.width, sky_view.height);

  // A V = 2 star on a sky 17° after sunset, exposed so the sky is dark.
  const double px = 80.3, py = 60.7;
  const glm::dvec3 dir = direction_at(px, py);
  const glm::vec3 sky_at_star = core::sky_radiance_from_table(t.atmosphere, t.transmittance, sky_view, kEyeAltitudeM,
                                                              glm::vec3(dir), in_.sun_direction_enu);
  in_.exposure = static_cast<float>(0.02 / std::max(night::rgb_luminance(glm::dvec3(sky_at_star)), 1e-12));
  in_.output_encoding = 1;
  const glm::vec3 lux = glm::vec3(night::illuminance_from_magnitude(2.0) * night::star_rgb_from_bv(0.6));
  const glm::dvec3 star_sum = expected_sum(px, py, lux) / static_cast<double>(in_.exposure);  // E T / Omega, cd/m^2
  std::string error;

  for (atmo::gl::SkyMethod method : {atmo::gl::SkyMethod::kLut, atmo::gl::SkyMethod::kMarch}) {
    in_.method = method;
    target_->clear(0.0f, 0.0f, 0.0f, 0.0f);
    ASSERT_TRUE(draw({source(dir, lux)}, &error)) << error;
    const Image img = target_->read_color();
    double worst = 0.0, peak = 0.0, sky_encoded = 0.0;
    int drawn = 0, outside = 0;
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        const int wy = kH - 1 - y;
        const float* v = img.pixel(x, y);
        const double dx = x + 0.5 - px, dy = wy + 0.5 - py;
        if (std::abs(dx) > 3.5 || std::abs(dy) > 3.5) {
          outside += v[0] != 0.0f || v[1] != 0.0f || v[2] != 0.0f;
          continue;
        }
        ++drawn;
        const glm::vec3 d = glm::vec3(direction_at(x + 0.5, wy + 0.5));
        const glm::vec3 sky =
            method == atmo::gl::SkyMethod::kLut
                ? core::sky_radiance_from_table(t.atmosphere, t.transmittance, sky_view, kEyeAltitudeM, d,
                                                in_.sun_direction_enu)
                : twin::sky_radiance(t.atmosphere, t.transmittance, glm::vec2(t.transmittance.width, t.transmittance.height),
                                     t.multiple_scattering,
                                     glm::vec2(t.multiple_scattering.width, t.multiple_scattering.height),
                                     kEyeAltitudeM, d, in_.sun_direction_enu, in_.table_sizes.march_sky_steps);
        const float w = static_cast<float>(night::star_footprint_weight(dx, dy));
        const glm::vec3 expect = twin::encode_display_srgb((sky + glm::vec3(star_sum) * w) * in_.exposure);
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(static_cast<double>(v[c]) - expect[c]));
        peak = std::max(peak, static_cast<double>(v[1]));
        if (std::abs(dx) > 3.0 || std::abs(dy) > 3.0) sky_encoded = std::max(sky_encoded, static_cast<double>(v[1]));
      }
    }
    // MAX blending: drawing the same star again changes nothing.
    ASSERT_TRUE(draw({source(dir, lux)}, &error)) << error;
    const Image twice = target_->read_color();
    std::printf("[ night gl ] display sRGB, %s sky 17 deg after sunset (sky %.2e cd/m^2 at exposure %.3g): %d pixels "
                "drawn, |encoded - encode(exposure (L_sky + L_star))| <= %.1e; peak %.3f over sky %.3f (%.0f steps "
                "of 1/255); drawn twice: %s\n",
                method == atmo::gl::SkyMethod::kLut ? "LUT" : "MARCH", night::rgb_luminance(glm::dvec3(sky_at_star)),
                in_.exposure, drawn, worst, peak, sky_encoded, (peak - sky_encoded) * 255.0,
                twice.rgba == img.rgba ? "unchanged" : "CHANGED");
    EXPECT_EQ(drawn, 49);
    EXPECT_EQ(outside, 0);
    EXPECT_LT(worst, method == atmo::gl::SkyMethod::kLut ? 2e-3 : 5e-3);
    EXPECT_GT((peak - sky_encoded) * 255.0, 10.0);
    EXPECT_EQ(twice.rgba, img.rgba);
  }

  // The linear output adds: twice the light after two draws.
  in_.output_encoding = 0;
  in_.method = atmo::gl::SkyMethod::kLut;
  target_->clear(0.0f, 0.0f, 0.0f, 0.0f);
  ASSERT_TRUE(draw({source(dir, lux)}, &error)) << error;
  const double once = sum_rgb(target_->read_color()).g;
  ASSERT_TRUE(draw({source(dir, lux)}, &error)) << error;
  const double twice = sum_rgb(target_->read_color()).g;
  EXPECT_NEAR(twice, 2.0 * once, 1e-5 * once);
}

}  // namespace
