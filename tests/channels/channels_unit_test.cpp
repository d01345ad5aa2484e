// atmo-channels' pure parts: the wrap layout's yaws, bands and cameras, the flight's interpolation and
// events, the seam comparison and the stitched panorama.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "atmo_host_scene/camera.h"
#include "channel_layout.h"
#include "flight.h"
#include "seams.h"

namespace ch = atmo::channels;
namespace hs = atmo::host_scene;
namespace sc = atmo::scenario;
namespace su = atmo::support;

namespace {

ch::Layout three() {
  ch::Layout l;
  l.count = 3;
  l.horizontal_fov_deg = 60;
  l.vertical_fov_deg = 34;
  l.overlap_deg = 6;
  l.width = 160;
  l.height = 90;
  return l;
}

// Where a direction (camera axes) lands on a channel's image, pixels from the left and the top.
glm::dvec2 pixel_of(const ch::Layout& l, const glm::dvec3& camera_dir) {
  const glm::dvec4 clip = ch::channel_projection(l) * glm::dvec4(camera_dir, 1.0);
  return {(clip.x / clip.w * 0.5 + 0.5) * l.width, (0.5 - clip.y / clip.w * 0.5) * l.height};
}

}  // namespace

TEST(ChannelLayout, YawsAreCentredAndStepByFovLessOverlap) {
  const ch::Layout l = three();
  EXPECT_DOUBLE_EQ(ch::channel_yaw_deg(l, 0), -54.0);
  EXPECT_DOUBLE_EQ(ch::channel_yaw_deg(l, 1), 0.0);
  EXPECT_DOUBLE_EQ(ch::channel_yaw_deg(l, 2), 54.0);
  ch::Layout two = l;
  two.count = 2;
  EXPECT_DOUBLE_EQ(ch::channel_yaw_deg(two, 0), -27.0);
  EXPECT_DOUBLE_EQ(ch::channel_yaw_deg(two, 1), 27.0);
}

TEST(ChannelLayout, BandColumnsHoldTheSharedAnglesCentres) {
  const ch::Layout l = three();
  const int b = ch::band_columns(l);
  // tan(24 deg) / tan(30 deg) = 0.7712: the band is the outer 22.9 % of each half, 18.3 columns of 80.
  EXPECT_EQ(b, 18);
  ch::Layout none = l;
  none.overlap_deg = 0;
  EXPECT_EQ(ch::band_columns(none), 0);
  // Column b - 1's centre is inside the band, column b's is not.
  const double h = glm::radians(30.0), o = glm::radians(6.0);
  auto angle_of_column = [&](int x) { return std::atan(((x + 0.5) / l.width * 2.0 - 1.0) * std::tan(h)); };
  EXPECT_LE(angle_of_column(b - 1), -h + o);
  EXPECT_GT(angle_of_column(b), -h + o);
}

TEST(ChannelLayout, ErrorsNameTheProblem) {
  EXPECT_EQ(ch::layout_error(three()), "");
  ch::Layout l = three();
  l.count = 7;  // 7 x 54 = 378 > 360
  EXPECT_NE(ch::layout_error(l).find("past a full turn"), std::string::npos) << ch::layout_error(l);
  l = three();
  l.overlap_deg = 60;
  EXPECT_NE(ch::layout_error(l).find("overlap_deg"), std::string::npos);
  l = three();
  l.count = 0;
  EXPECT_NE(ch::layout_error(l), "");
}

// The middle channel of a level eye is the host-scene camera at the eye's heading and pitch.
TEST(ChannelLayout, UnturnedChannelIsTheHostSceneCamera) {
  for (double pitch : {0.0, 7.5, -20.0}) {
    const glm::dmat3 mine = ch::enu_from_channel_camera(123.0, pitch, 0.0);
    hs::CameraPose pose;
    pose.heading_deg = 123.0;
    pose.pitch_deg = pitch;
    const glm::dmat3 theirs = hs::enu_from_camera_rotation(pose);
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) EXPECT_NEAR(mine[c][r], theirs[c][r], 1e-12);
  }
}

// A level eye: channel i looks along heading + yaw_i. A pitched eye: adjacent channels still share their edge
// (a direction on channel i's right edge is on channel i + 1's left edge at the same height), which a pitch per
// channel about its own axis would break.
TEST(ChannelLayout, AdjacentChannelsShareTheirEdgesAtAnyPitch) {
  ch::Layout l = three();
  l.overlap_deg = 0;
  for (double pitch : {0.0, 12.0, -30.0}) {
    const glm::dmat3 left = ch::enu_from_channel_camera(40.0, pitch, ch::channel_yaw_deg(l, 0));
    const glm::dmat3 right = ch::enu_from_channel_camera(40.0, pitch, ch::channel_yaw_deg(l, 1));
    if (pitch == 0.0) {
      const glm::dvec3 f = -left[2];
      EXPECT_NEAR(glm::degrees(std::atan2(f.x, f.y)), 40.0 - 60.0, 1e-9);
    }
    for (double y : {0.0, 20.0, 89.0}) {
      // The right edge of the left channel at row y, as an ENU direction.
      const double ndc_y = 1.0 - 2.0 * y / l.height;
      const glm::dvec3 cam(std::tan(glm::radians(30.0)), ndc_y * std::tan(glm::radians(17.0)), -1.0);
      const glm::dvec3 world = left * cam;
      const glm::dvec2 p = pixel_of(l, glm::transpose(right) * world);
      EXPECT_NEAR(p.x, 0.0, 1e-6) << "pitch " << pitch << " row " << y;
      EXPECT_NEAR(p.y, y, 1e-6) << "pitch " << pitch;
    }
  }
}

TEST(Flight, InterpolatesHoldsAndFiresEvents) {
  const auto loaded = sc::parse_scenario(R"({
    "schema_version": 1, "name": "f", "utc": "2024-06-21T04:30:00Z",
    "location": {"latitude_deg": 47.26, "longitude_deg": 11.35, "height_m": 620},
    "cameras": [{"name": "c", "position": {"enu_m": [0, 0, 1]}, "heading_deg": 0, "pitch_deg": 0,
                 "vertical_fov_deg": 30, "width": 16, "height": 9, "near_m": 1, "far_m": 1000}],
    "flight": {"frame_rate_hz": 0.5, "keyframes": [
        {"t_s": 2, "position": {"enu_m": [0, 0, 100]}, "heading_deg": 350},
        {"t_s": 6, "position": {"enu_m": [400, -800, 300]}, "heading_deg": -10, "pitch_deg": 8}],
      "events": [{"at_frame": 2, "atmosphere": {}}, {"at_frame": 2, "clouds": []}, {"at_frame": 3, "clouds": []}]}
  })", "f.json");
  ASSERT_TRUE(loaded.scenario) << loaded.error;
  const sc::Scenario& s = *loaded.scenario;
  const ch::FlightPlan plan = ch::flight_plan_of(s);
  EXPECT_EQ(plan.frames, 4);  // floor(6 * 0.5) + 1
  const ch::FrameState f0 = ch::frame_state(s, plan, 0);  // t 0: before the first keyframe, held
  EXPECT_EQ(f0.eye_enu_m[2], 100.0);
  EXPECT_EQ(f0.heading_deg, 350.0);
  EXPECT_EQ(f0.event_count, 0);
  const ch::FrameState f2 = ch::frame_state(s, plan, 2);  // t 4: half way
  EXPECT_EQ(f2.frame, 2u);
  EXPECT_DOUBLE_EQ(f2.t_s, 4.0);
  EXPECT_DOUBLE_EQ(f2.utc_posix_s, s.utc_posix_s + 4.0);
  EXPECT_DOUBLE_EQ(f2.eye_enu_m[0], 200.0);
  EXPECT_DOUBLE_EQ(f2.eye_enu_m[1], -400.0);
  EXPECT_DOUBLE_EQ(f2.eye_enu_m[2], 200.0);
  EXPECT_DOUBLE_EQ(f2.heading_deg, 170.0);  // as written: 350 to -10 turns the long way
  EXPECT_DOUBLE_EQ(f2.pitch_deg, 4.0);
  ASSERT_EQ(f2.event_count, 2);
  EXPECT_EQ(f2.events[0], 0);
  EXPECT_EQ(f2.events[1], 1);
  const ch::FrameState f9 = ch::frame_state(s, plan, 9);  // past the last keyframe: held
  EXPECT_EQ(f9.eye_enu_m[0], 400.0);
  EXPECT_EQ(f9.heading_deg, -10.0);
  EXPECT_EQ(ch::frame_state(s, plan, 3).event_count, 1);
}

TEST(Flight, WithoutAFlightIsTheFirstCameraStill) {
  const auto loaded = sc::parse_scenario(R"({
    "schema_version": 1, "name": "f", "utc": "2024-06-21T04:30:00Z",
    "location": {"latitude_deg": 47.26, "longitude_deg": 11.35, "height_m": 620},
    "cameras": [{"name": "c", "position": {"enu_m": [5, 6, 7]}, "heading_deg": 33, "pitch_deg": -4,
                 "vertical_fov_deg": 30, "width": 16, "height": 9, "near_m": 1, "far_m": 1000}]
  })", "f.json");
  ASSERT_TRUE(loaded.scenario) << loaded.error;
  const ch::FlightPlan plan = ch::flight_plan_of(*loaded.scenario);
  EXPECT_EQ(plan.frames, 1);
  const ch::EyePose p = ch::eye_at(plan.keyframes, 123.0);
  EXPECT_EQ(p.enu_m, glm::dvec3(5, 6, 7));
  EXPECT_EQ(p.heading_deg, 33.0);
  EXPECT_EQ(p.pitch_deg, -4.0);
}

TEST(Seams, CompareCountsLevelsAndRelativeDifferences) {
  su::Image a = su::make_image(4, 2, 1000.0f, 2000.0f, 3000.0f);
  su::Image b = a;
  ch::BandDiff same = ch::compare_bands(a, b, 1e-4f);
  EXPECT_TRUE(same.ok());
  EXPECT_EQ(same.values_differing, 0);
  EXPECT_EQ(same.max_levels, 0);
  b.pixel(3, 1)[1] = 2000.0f * 1.0005f;  // 5e-4: within both limits at this exposure
  ch::BandDiff small = ch::compare_bands(a, b, 1e-4f);
  EXPECT_TRUE(small.ok());
  EXPECT_EQ(small.values_differing, 1);
  EXPECT_NEAR(small.max_relative, 5e-4, 1e-6);
  EXPECT_EQ(small.worst_x, 3);
  EXPECT_EQ(small.worst_y, 1);
  b.pixel(0, 0)[0] = 1000.0f * 1.05f;  // 5 %: several levels, far past 1e-3
  ch::BandDiff big = ch::compare_bands(a, b, 1e-4f);
  EXPECT_FALSE(big.ok());
  EXPECT_GT(big.max_levels, 1);
  b = a;
  b.pixel(1, 1)[2] = std::nanf("");
  EXPECT_FALSE(ch::compare_bands(a, b, 1e-4f).ok());
  // Below the floor (1e-3 cd/m^2) differences are relative to the floor.
  su::Image dark = su::make_image(1, 1, 0.0f, 0.0f, 0.0f), darker = su::make_image(1, 1, 1e-6f, 0.0f, 0.0f);
  EXPECT_TRUE(ch::compare_bands(dark, darker, 1e-4f).ok());
  EXPECT_EQ(ch::display_level(0.0f, 1.0f), 0);
  EXPECT_EQ(ch::display_level(1e9f, 1.0f), 255);
}

TEST(Seams, StitchCrossFadesTheSharedColumns) {
  // Three 4-column channels of constant values 10, 20, 40 sharing 2 columns: 4 + 2 + 2 = 8 columns.
  std::vector<su::Image> c = {su::make_image(4, 1, 10, 10, 10), su::make_image(4, 1, 20, 20, 20),
                              su::make_image(4, 1, 40, 40, 40)};
  const su::Image p = ch::stitch(c, 2);
  ASSERT_EQ(p.width, 8);
  const float expected[8] = {10, 10, 10 * 0.75f + 20 * 0.25f, 10 * 0.25f + 20 * 0.75f,
                             20 * 0.75f + 40 * 0.25f, 20 * 0.25f + 40 * 0.75f, 40, 40};
  for (int x = 0; x < 8; ++x) EXPECT_FLOAT_EQ(p.pixel(x, 0)[0], expected[x]) << x;
  EXPECT_EQ(ch::stitch(c, 0).width, 12);
  const su::Image crop = ch::crop_columns(c[1], 1, 2);
  EXPECT_EQ(crop.width, 2);
  EXPECT_EQ(crop.pixel(1, 0)[0], 20.0f);
}
