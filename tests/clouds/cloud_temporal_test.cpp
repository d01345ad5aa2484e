// The temporal upsampling's CPU half (core/clouds/cloud_temporal.h): the
// traced pixel of each 2x2 block visits all four in four passes; the
// reprojection matrix against projecting a world point with the last frame's
// camera built independently (glm::lookAt in a world frame); the history
// rules (frame numbers, cuts, image size); the cost levels in order.
#include "core/clouds/cloud_temporal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

namespace {

using namespace atmo::clouds;

TEST(CloudTemporal, EveryPixelOfABlockIsTracedOnceInFourPasses) {
  for (uint64_t start : {0ull, 1ull, 7ull, 1000001ull}) {
    std::set<std::pair<int, int>> seen;
    for (uint64_t k = start; k < start + 4; ++k) {
      const glm::ivec2 o = temporal_trace_offset(k);
      ASSERT_TRUE(o.x == 0 || o.x == 1);
      ASSERT_TRUE(o.y == 0 || o.y == 1);
      seen.insert({o.x, o.y});
    }
    EXPECT_EQ(seen.size(), 4u) << "from pass " << start;
  }
}

// A camera in a world frame (the clouds' ENU): eye, heading (from north,
// clockwise) and pitch; the eye's ENU axes are the clouds' turned by `tilt`
// about the east axis (an eye far from the clouds' origin on the curved Earth).
struct Pose {
  glm::dvec3 eye;
  double heading_rad, pitch_rad, tilt_rad;
};

TemporalView view_of(const Pose& p, int w = 320, int h = 180) {
  TemporalView v;
  v.eye_in_clouds_m = p.eye;
  // eye ENU from clouds: a rotation about x by -tilt.
  v.eye_enu_from_clouds = glm::dmat3(glm::rotate(glm::dmat4(1.0), -p.tilt_rad, glm::dvec3(1, 0, 0)));
  const glm::dvec3 forward(std::sin(p.heading_rad) * std::cos(p.pitch_rad),
                           std::cos(p.heading_rad) * std::cos(p.pitch_rad), std::sin(p.pitch_rad));
  v.view_from_enu = glm::dmat3(glm::lookAt(glm::dvec3(0.0), forward, glm::dvec3(0, 0, 1)));
  v.clip_from_view = glm::perspective(glm::radians(60.0), double(w) / h, 1.0, 1e5);
  v.width = w;
  v.height = h;
  return v;
}

TEST(CloudTemporal, ReprojectionMatchesTheLastCameraOnWorldPoints) {
  const Pose now_pose{{1200.0, -300.0, 1700.0}, 0.3, 0.05, 0.002};
  const Pose last_pose{{1195.0, -308.0, 1702.0}, 0.25, 0.04, 0.0021};
  const TemporalView now = view_of(now_pose), last = view_of(last_pose);
  const glm::dmat4 m = last_clip_from_eye_enu(last, now);
  // The last camera as a world (clouds' frame) view matrix, built on its own.
  const glm::dmat3 clouds_from_last_enu = glm::transpose(last.eye_enu_from_clouds);
  const glm::dvec3 fwd =
      clouds_from_last_enu * glm::dvec3(std::sin(last_pose.heading_rad) * std::cos(last_pose.pitch_rad),
                                        std::cos(last_pose.heading_rad) * std::cos(last_pose.pitch_rad),
                                        std::sin(last_pose.pitch_rad));
  const glm::dmat4 last_view_world =
      glm::lookAt(last_pose.eye, last_pose.eye + fwd, clouds_from_last_enu * glm::dvec3(0, 0, 1));
  double worst = 0.0;
  for (int i = 0; i < 50; ++i) {
    // Points 50 m to 40 km in front of the eye, in now's eye ENU.
    const double d = 50.0 * std::pow(800.0, i / 49.0);
    const glm::dvec3 x = d * glm::normalize(glm::dvec3(std::sin(0.3 + 0.01 * i), std::cos(0.3 - 0.013 * i), 0.05));
    const glm::dvec3 world = now.eye_in_clouds_m + glm::transpose(now.eye_enu_from_clouds) * x;
    const glm::dvec4 a = m * glm::dvec4(x, 1.0);
    const glm::dvec4 b = last.clip_from_view * last_view_world * glm::dvec4(world, 1.0);
    worst = std::max(worst, glm::length(glm::dvec2(a) / a.w - glm::dvec2(b) / b.w));
  }
  std::printf("reprojection against the last camera: largest NDC difference %.3g\n", worst);
  EXPECT_LT(worst, 1e-9);
}

TEST(CloudTemporal, HistoryIsKeptBetweenFramesAndDroppedAtCuts) {
  const Pose p{{0.0, 0.0, 1700.0}, 0.0, 0.0, 0.0};
  TemporalView last = view_of(p), now = view_of(p);
  last.host_frame_number = 41;
  now.host_frame_number = 42;
  EXPECT_TRUE(temporal_history_usable(last, now));
  now.host_frame_number = 41;  // a host that does not count frames
  EXPECT_TRUE(temporal_history_usable(last, now));
  now.host_frame_number = 44;  // frames skipped
  EXPECT_FALSE(temporal_history_usable(last, now));
  now.host_frame_number = 40;  // back in time
  EXPECT_FALSE(temporal_history_usable(last, now));
  now.host_frame_number = 42;
  // Moves: 250 m/s at 10 Hz is kept; a jump over the cut distance is not.
  now.eye_in_clouds_m.y += 25.0;
  EXPECT_TRUE(temporal_history_usable(last, now));
  now.eye_in_clouds_m.y = kTemporalCutDistanceM + 1.0;
  EXPECT_FALSE(temporal_history_usable(last, now));
  // Turns: 90 deg/s at 10 Hz is kept, past the cut angle not (yaw and pitch).
  for (double yaw_deg : {9.0, 31.0})
    for (bool pitch : {false, true}) {
      Pose q = p;
      (pitch ? q.pitch_rad : q.heading_rad) = glm::radians(yaw_deg);
      now = view_of(q);
      now.host_frame_number = 42;
      EXPECT_EQ(temporal_history_usable(last, now), yaw_deg < 30.0) << yaw_deg << (pitch ? " pitch" : " yaw");
    }
  // Another image size or projection.
  now = view_of(p, 322, 180);
  now.host_frame_number = 42;
  EXPECT_FALSE(temporal_history_usable(last, now));
  now = view_of(p);
  now.host_frame_number = 42;
  now.clip_from_view = glm::perspective(glm::radians(40.0), 320.0 / 180.0, 1.0, 1e5);
  EXPECT_FALSE(temporal_history_usable(last, now));
  // Other content (a rebuilt clipmap, relit clouds).
  now = view_of(p);
  now.host_frame_number = 42;
  now.content_version = last.content_version + 1;
  EXPECT_FALSE(temporal_history_usable(last, now));
  // No history yet (size 0).
  EXPECT_FALSE(temporal_history_usable(TemporalView{}, view_of(p)));
}

TEST(CloudTemporal, QualityLevelsCostMoreAsTheyRise) {
  auto rays_steps = [](CloudQuality q) {
    const CloudViewCost c = cloud_view_cost(q);
    return c.max_steps * (c.temporal ? 0.25 : 1.0) / double(c.divisor * c.divisor);
  };
  const CloudQuality order[] = {CloudQuality::kLow, CloudQuality::kMedium, CloudQuality::kHigh, CloudQuality::kFull};
  for (int i = 0; i + 1 < 4; ++i) EXPECT_LT(rays_steps(order[i]), rays_steps(order[i + 1])) << i;
  EXPECT_TRUE(cloud_view_cost(kDefaultCloudQuality).temporal);
}

}  // namespace
