// Where the passes are known to fail: extreme places, heights, times and air.
// Every pixel must stay finite and non-negative (degrade, never NaN), and the
// image must not jump when a huge ECEF eye moves by a millimetre.
#include <glad/gl.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "atmo_support/example_view.h"
#include "atmo_support/image_metrics.h"
#include "plugin_gl_fixture.h"

using namespace plugin_gl;

namespace {

// Host geometry at window depth 0.99995 (about 20 km) in the lower half, far plane above.
GLuint make_half_depth() { return atmo::support::make_split_depth_texture(kWidth, kHeight, 0.99995f); }

AtmoViewState view_at(double lat, double lon, double height, double heading, double pitch, GLuint depth) {
  auto vs = atmo::make<AtmoViewState>(ATMO_TYPE_VIEW_STATE);
  vs.eye_kind = ATMO_POSITION_GEODETIC;
  vs.eye_geodetic[0] = lat;
  vs.eye_geodetic[1] = lon;
  vs.eye_geodetic[2] = height;
  vs.world_frame = ATMO_WORLD_ENU;
  vs.world_origin_geodetic[0] = lat;
  vs.world_origin_geodetic[1] = lon;
  copy(look(heading, pitch), vs.view_from_world);
  copy(glm::perspective(glm::radians(70.0), double(kWidth) / kHeight, 1.0, 1e5), vs.clip_from_view);
  vs.viewport[2] = kWidth;
  vs.viewport[3] = kHeight;
  vs.depth_texture = depth;
  vs.exposure_scale = 1.0;
  return vs;
}

size_t bad_pixels(const atmo::support::Image& img) {
  size_t bad = 0;
  for (size_t i = 0; i < img.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) {
      float v = img.rgba[i * 4 + c];
      if (!std::isfinite(v) || v < 0.0f) ++bad;
    }
  return bad;
}

}  // namespace

TEST(Robustness, FiniteAndNonNegativeEverywhereItIsKnownToFail) {
  Fixture f;
  GLuint depth = make_half_depth();
  const double times[] = {1718964000.0 /* noon */, 1718997000.0 /* sun -4° */, 1719010000.0 /* deep night */,
                          1703160000.0 /* December */};
  const double heights[] = {-400.0, 0.0, 1.0, 12000.0, 30000.0, 100000.0, 500000.0};
  const double latitudes[] = {90.0, -90.0, 0.0, 47.26};
  const double visibilities[] = {50.0, 40000.0, 500000.0};
  const double pitches[] = {-89.9, 0.0, 89.9};
  int renders = 0;
  for (double vis : visibilities) {
    // A new context per air, so its first frame draws that air. Within it the
    // latitudes change the model sphere: those tables come from the worker while
    // the frames keep the previous sphere's (every frame must be finite either way).
    f.fresh_context();
    auto atm = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
    atm.visibility_m = vis;
    f.context->set_atmosphere(atm);
    for (double t : times) {
      auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
      frame.utc_posix_s = t;
      f.context->set_frame(frame);
      for (double lat : latitudes)
        for (double h : heights)
          for (double pitch : pitches) {
            f.view->set(view_at(lat, 179.9999, h, 33.0, pitch, depth));
            f.target->bind();
            f.target->clear(0.1f, 0.1f, 0.1f, 1.0f);
            ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS);
            ASSERT_EQ(f.view->render(ATMO_PASS_AERIAL_PERSPECTIVE), ATMO_SUCCESS);
            size_t bad = bad_pixels(f.target->read_color());
            ASSERT_EQ(bad, 0u) << "visibility " << vis << " m, time " << t << ", lat " << lat << ", height " << h
                               << " m, pitch " << pitch;
            ++renders;
          }
    }
  }
  std::printf("[ robustness ] %d renders (sky + aerial perspective), every pixel finite and >= 0\n", renders);
  glDeleteTextures(1, &depth);
}

TEST(Robustness, MillimetreMovesOfAnEcefEyeDoNotJitter) {
  Fixture f;
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = 1718964000.0;
  f.context->set_frame(frame);
  GLuint depth = make_half_depth();
  // Eye on the equator at 0° E, 1500 m up, in ECEF; ECEF world axes. Looking east, horizontal:
  // east = +Y, up = +X at (0°, 0°).
  auto vs = view_at(0.0, 0.0, 1500.0, 90.0, 0.0, depth);
  vs.eye_kind = ATMO_POSITION_ECEF;
  vs.world_frame = ATMO_WORLD_ECEF;
  vs.eye_ecef_m[0] = 6378137.0 + 1500.0;
  copy(glm::lookAt(glm::dvec3(0), glm::dvec3(0, 1, 0), glm::dvec3(1, 0, 0)), vs.view_from_world);
  atmo::support::Image previous;
  double worst_step = 0.0;
  for (int step = 0; step < 6; ++step) {
    vs.eye_ecef_m[0] = 6378137.0 + 1500.0 + 0.001 * step;
    vs.eye_ecef_m[1] = 0.001 * step;
    f.view->set(vs);
    f.target->bind();
    f.target->clear(0.2f, 0.2f, 0.2f, 1.0f);
    ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS);
    ASSERT_EQ(f.view->render(ATMO_PASS_AERIAL_PERSPECTIVE), ATMO_SUCCESS);
    atmo::support::Image img = f.target->read_color();
    if (step > 0) {
      auto stats = atmo::support::relative_luminance_error(img, previous, 1.0);
      worst_step = std::max(worst_step, stats.max);
    }
    previous = img;
  }
  std::printf("[ robustness ] ECEF eye at 6 379 km moved in 1 mm steps: worst per-pixel relative change %.2e\n",
              worst_step);
  EXPECT_LT(worst_step, 1e-3);
  glDeleteTextures(1, &depth);
}

// The same camera given in the host's local ENU frame and in ECEF (the world
// moved by ~6.4e6 m): the 8-bit images may differ by at most one level.
TEST(Robustness, EcefWorldGivesTheSameImageAsALocalWorld) {
  Fixture f;
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = 1718989800.0;  // low sun: the most colour and gradient
  f.context->set_frame(frame);
  GLuint depth = make_half_depth();
  const double lat = 47.26, lon = 11.35, height = 900.0;
  auto local = view_at(lat, lon, height, 300.0, 3.0, depth);
  local.exposure_scale = 1.0 / (1.2 * 4096.0);  // EV100 12
  local.output_encoding = ATMO_OUTPUT_DISPLAY_SRGB;

  // ECEF: eye in ECEF metres, view rotation expressed in ECEF axes.
  auto ecef = local;
  ecef.eye_kind = ATMO_POSITION_ECEF;
  ecef.world_frame = ATMO_WORLD_ECEF;
  const double la = glm::radians(lat), lo = glm::radians(lon);
  const double semi_major = 6378137.0, e2 = 6.69437999014e-3;
  const double n = semi_major / std::sqrt(1.0 - e2 * std::sin(la) * std::sin(la));
  ecef.eye_ecef_m[0] = (n + height) * std::cos(la) * std::cos(lo);
  ecef.eye_ecef_m[1] = (n + height) * std::cos(la) * std::sin(lo);
  ecef.eye_ecef_m[2] = (n * (1.0 - e2) + height) * std::sin(la);
  const glm::dvec3 east(-std::sin(lo), std::cos(lo), 0.0);
  const glm::dvec3 north(-std::sin(la) * std::cos(lo), -std::sin(la) * std::sin(lo), std::cos(la));
  const glm::dvec3 up(std::cos(la) * std::cos(lo), std::cos(la) * std::sin(lo), std::sin(la));
  const glm::dmat3 ecef_from_enu(east, north, up);
  const glm::dmat4 view_enu = look(300.0, 3.0);
  const glm::dmat3 view_rotation = glm::dmat3(view_enu) * glm::transpose(ecef_from_enu);
  copy(glm::dmat4(view_rotation), ecef.view_from_world);

  auto render = [&](const AtmoViewState& vs) {
    f.view->set(vs);
    f.target->bind();
    f.target->clear(0.1f, 0.2f, 0.3f, 1.0f);
    EXPECT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS);
    EXPECT_EQ(f.view->render(ATMO_PASS_AERIAL_PERSPECTIVE), ATMO_SUCCESS);
    return f.target->read_color();
  };
  atmo::support::Image a = render(local), b = render(ecef);
  int worst_levels = 0;
  for (size_t i = 0; i < a.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) {
      int la8 = static_cast<int>(std::lround(std::clamp(a.rgba[i * 4 + c], 0.0f, 1.0f) * 255.0f));
      int lb8 = static_cast<int>(std::lround(std::clamp(b.rgba[i * 4 + c], 0.0f, 1.0f) * 255.0f));
      worst_levels = std::max(worst_levels, std::abs(la8 - lb8));
    }
  std::printf("[ robustness ] local ENU world vs ECEF world (6.4e6 m coordinates): worst 8-bit difference %d level(s)\n",
              worst_levels);
  EXPECT_LE(worst_levels, 1);
  glDeleteTextures(1, &depth);
}
