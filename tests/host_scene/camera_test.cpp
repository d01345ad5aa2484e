// Camera maths of atmo_host_scene: orientation, the three depth conventions
// (inverted here independently of the library), geodetic conversion and the
// AtmoViewState it fills.
#include <cmath>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "atmo_host_scene/camera.h"

namespace hs = atmo::host_scene;

namespace {

constexpr double kNear = 0.5;
constexpr double kFar = 150000.0;

glm::dvec3 view_space(const hs::CameraPose& pose, const glm::dvec3& world) {
  return glm::dvec3(hs::view_from_enu(pose) * glm::dvec4(world, 1.0));
}

// Window-space depth of a view-space point (0, 0, -d) as GL would store it.
double window_depth(hs::DepthConvention convention, double d) {
  const glm::dmat4 p = hs::projection(glm::radians(50.0), 16.0 / 9.0, kNear, kFar, convention);
  const glm::dvec4 clip = p * glm::dvec4(0.0, 0.0, -d, 1.0);
  const double ndc = clip.z / clip.w;
  switch (convention) {
    case hs::DepthConvention::Standard: return 0.5 * ndc + 0.5;  // glDepthRange(0, 1), NDC [-1, 1]
    case hs::DepthConvention::Reversed: return ndc;              // ZERO_TO_ONE: window = NDC
    case hs::DepthConvention::Logarithmic:
      // What the fragment shader writes, w = clip.w (C = 1).
      return std::log2(clip.w + 1.0) / std::log2(kFar + 1.0);
  }
  return 0.0;
}

// Independent inverses: window depth -> distance along -z.
double distance_from_depth(hs::DepthConvention convention, double depth) {
  switch (convention) {
    case hs::DepthConvention::Standard: {
      const double ndc = 2.0 * depth - 1.0;
      return 2.0 * kNear * kFar / (kFar + kNear - ndc * (kFar - kNear));
    }
    case hs::DepthConvention::Reversed: return kNear / depth;
    case hs::DepthConvention::Logarithmic: return std::exp2(depth * std::log2(kFar + 1.0)) - 1.0;
  }
  return 0.0;
}

}  // namespace

TEST(Camera, HeadingZeroLooksNorth) {
  hs::CameraPose pose;
  const glm::dvec3 f = hs::forward_enu(pose);
  EXPECT_NEAR(f.x, 0.0, 1e-12);
  EXPECT_NEAR(f.y, 1.0, 1e-12);
  EXPECT_NEAR(f.z, 0.0, 1e-12);
}

TEST(Camera, Heading90LooksEast) {
  hs::CameraPose pose;
  pose.position_enu_m = glm::dvec3(100.0, -50.0, 20.0);
  pose.heading_deg = 90.0;
  const glm::dvec3 f = hs::forward_enu(pose);
  EXPECT_NEAR(f.x, 1.0, 1e-12);
  EXPECT_NEAR(f.y, 0.0, 1e-12);
  // A point 1 km east of the eye is straight ahead (view -z), up is view +y.
  const glm::dvec3 ahead = view_space(pose, pose.position_enu_m + glm::dvec3(1000.0, 0.0, 0.0));
  EXPECT_NEAR(ahead.x, 0.0, 1e-9);
  EXPECT_NEAR(ahead.y, 0.0, 1e-9);
  EXPECT_NEAR(ahead.z, -1000.0, 1e-9);
  const glm::dvec3 above = view_space(pose, pose.position_enu_m + glm::dvec3(0.0, 0.0, 10.0));
  EXPECT_NEAR(above.y, 10.0, 1e-9);
  // North is on the left when facing east.
  const glm::dvec3 north = view_space(pose, pose.position_enu_m + glm::dvec3(0.0, 10.0, 0.0));
  EXPECT_NEAR(north.x, -10.0, 1e-9);
}

TEST(Camera, Heading180LooksSouth) {
  hs::CameraPose pose;
  pose.heading_deg = 180.0;
  EXPECT_NEAR(hs::forward_enu(pose).y, -1.0, 1e-12);
}

TEST(Camera, PitchPositiveLooksUp) {
  hs::CameraPose pose;
  pose.pitch_deg = 10.0;
  const glm::dvec3 f = hs::forward_enu(pose);
  EXPECT_NEAR(f.z, std::sin(glm::radians(10.0)), 1e-12);
  EXPECT_NEAR(f.y, std::cos(glm::radians(10.0)), 1e-12);
  // A point on the horizon ahead now appears below the centre.
  EXPECT_LT(view_space(pose, glm::dvec3(0.0, 1000.0, 0.0)).y, 0.0);
}

TEST(Camera, RollPositiveTiltsUpToTheRight) {
  hs::CameraPose pose;
  pose.roll_deg = 20.0;
  const glm::dmat3 r = hs::enu_from_camera_rotation(pose);
  const glm::dvec3 up = r[1];
  EXPECT_GT(up.x, 0.0);  // heading north: right is east
  EXPECT_NEAR(hs::forward_enu(pose).y, 1.0, 1e-12);
}

TEST(Camera, RotationIsOrthonormal) {
  hs::CameraPose pose;
  pose.heading_deg = 37.0;
  pose.pitch_deg = -12.0;
  pose.roll_deg = 5.0;
  const glm::dmat3 r = hs::enu_from_camera_rotation(pose);
  const glm::dmat3 identity = glm::transpose(r) * r;
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(identity[c][k], c == k ? 1.0 : 0.0, 1e-12);
  }
  EXPECT_NEAR(glm::determinant(r), 1.0, 1e-12);
}

TEST(Camera, ViewMovesEyeToOrigin) {
  hs::CameraPose pose;
  pose.position_enu_m = glm::dvec3(1234.5, -987.25, 321.0);
  pose.heading_deg = 213.0;
  pose.pitch_deg = 7.0;
  const glm::dvec3 v = view_space(pose, pose.position_enu_m);
  EXPECT_NEAR(glm::length(v), 0.0, 1e-9);
}

TEST(Projection, DepthsInvertBackToDistance) {
  for (hs::DepthConvention convention :
       {hs::DepthConvention::Standard, hs::DepthConvention::Reversed, hs::DepthConvention::Logarithmic}) {
    for (double d : {0.6, 1.0, 10.0, 250.0, 1000.0, 12345.0, 80000.0, 149000.0}) {
      const double depth = window_depth(convention, d);
      EXPECT_GE(depth, 0.0) << hs::to_string(convention) << " d=" << d;
      EXPECT_LE(depth, 1.0) << hs::to_string(convention) << " d=" << d;
      EXPECT_NEAR(distance_from_depth(convention, depth), d, 1e-4 * d) << hs::to_string(convention) << " d=" << d;
    }
  }
}

TEST(Projection, ReversedMapsNearToOneAndFarTowardsZero) {
  EXPECT_NEAR(window_depth(hs::DepthConvention::Reversed, kNear), 1.0, 1e-12);
  EXPECT_LT(window_depth(hs::DepthConvention::Reversed, 1e9), 1e-9);
  EXPECT_NEAR(window_depth(hs::DepthConvention::Standard, kNear), 0.0, 1e-12);
  EXPECT_NEAR(window_depth(hs::DepthConvention::Standard, kFar), 1.0, 1e-9);
  EXPECT_NEAR(window_depth(hs::DepthConvention::Logarithmic, kFar), 1.0, 1e-12);
}

TEST(Projection, LogarithmicDepthHelperMatchesTheFormula) {
  for (double d : {1.0, 100.0, 5000.0}) {
    EXPECT_NEAR(hs::logarithmic_depth(d, kFar), std::log2(d + 1.0) / std::log2(kFar + 1.0), 1e-15);
  }
}

TEST(Projection, AspectAndFieldOfView) {
  const double vfov = glm::radians(60.0);
  const glm::dmat4 p = hs::projection(vfov, 2.0, kNear, kFar, hs::DepthConvention::Reversed);
  // A point at the top edge of the field of view lands at NDC y = 1.
  const double d = 100.0;
  const glm::dvec4 clip = p * glm::dvec4(0.0, d * std::tan(0.5 * vfov), -d, 1.0);
  EXPECT_NEAR(clip.y / clip.w, 1.0, 1e-12);
  const glm::dvec4 side = p * glm::dvec4(2.0 * d * std::tan(0.5 * vfov), 0.0, -d, 1.0);
  EXPECT_NEAR(side.x / side.w, 1.0, 1e-12);
}

TEST(Geodetic, EnuRoundTrip) {
  const hs::Geodetic origin{47.4647, 8.5492, 432.0};
  const hs::Geodetic at_origin = hs::geodetic_from_enu(origin, glm::dvec3(0.0));
  EXPECT_NEAR(at_origin.latitude_deg, origin.latitude_deg, 1e-12);
  EXPECT_NEAR(at_origin.longitude_deg, origin.longitude_deg, 1e-12);
  EXPECT_NEAR(at_origin.height_m, origin.height_m, 1e-6);

  const hs::Geodetic north = hs::geodetic_from_enu(origin, glm::dvec3(0.0, 1000.0, 0.0));
  EXPECT_NEAR(north.latitude_deg - origin.latitude_deg, 1000.0 / 111150.0, 2e-4);
  EXPECT_NEAR(north.height_m - origin.height_m, 1000.0 * 1000.0 / (2.0 * 6371000.0), 0.01);  // curvature

  const glm::dvec3 p(-12345.6, 7890.1, 2500.0);
  const glm::dvec3 back = hs::enu_from_geodetic(origin, hs::geodetic_from_enu(origin, p));
  EXPECT_NEAR(glm::length(back - p), 0.0, 1e-6);
}

TEST(ViewState, FilledForEnuWorld) {
  hs::ViewSetup setup;
  setup.world_origin = {47.4647, 8.5492, 432.0};
  setup.pose.position_enu_m = glm::dvec3(-3000.0, 0.0, 150.0);
  setup.pose.heading_deg = 90.0;
  setup.viewport = {0, 0, 1280, 720};
  setup.depth_texture = 7;
  setup.depth_convention = hs::DepthConvention::Logarithmic;
  setup.far_m = 100000.0;
  setup.exposure_scale = 0.25;
  const AtmoViewState s = hs::make_view_state(setup);
  EXPECT_EQ(s.header.type, static_cast<uint32_t>(ATMO_TYPE_VIEW_STATE));
  EXPECT_EQ(s.header.struct_size, sizeof(AtmoViewState));
  EXPECT_EQ(s.header.next, nullptr);
  EXPECT_EQ(s.eye_kind, static_cast<uint32_t>(ATMO_POSITION_GEODETIC));
  EXPECT_EQ(s.world_frame, static_cast<uint32_t>(ATMO_WORLD_ENU));
  const hs::Geodetic eye = hs::eye_geodetic(setup);
  EXPECT_DOUBLE_EQ(s.eye_geodetic[0], eye.latitude_deg);
  EXPECT_DOUBLE_EQ(s.eye_geodetic[1], eye.longitude_deg);
  EXPECT_DOUBLE_EQ(s.eye_geodetic[2], eye.height_m);
  EXPECT_LT(eye.longitude_deg, setup.world_origin.longitude_deg);  // 3 km west
  EXPECT_DOUBLE_EQ(s.world_origin_geodetic[2], 432.0);
  const glm::dmat4 view = hs::view_from_enu(setup.pose);
  const glm::dmat4 proj = hs::clip_from_view(setup);
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      EXPECT_DOUBLE_EQ(s.view_from_world[c * 4 + r], view[c][r]);
      EXPECT_DOUBLE_EQ(s.clip_from_view[c * 4 + r], proj[c][r]);
    }
  }
  EXPECT_EQ(s.viewport[2], 1280);
  EXPECT_EQ(s.viewport[3], 720);
  EXPECT_EQ(s.depth_texture, 7u);
  EXPECT_EQ(s.depth_convention, static_cast<uint32_t>(ATMO_DEPTH_LOGARITHMIC));
  EXPECT_DOUBLE_EQ(s.far_plane_m, 100000.0);
  EXPECT_DOUBLE_EQ(s.log_depth_coefficient, 1.0);
  EXPECT_EQ(s.output_encoding, static_cast<uint32_t>(ATMO_OUTPUT_LINEAR_HDR));
  EXPECT_DOUBLE_EQ(s.exposure_scale, 0.25);

  setup.depth_convention = hs::DepthConvention::Reversed;
  const AtmoViewState r = hs::make_view_state(setup);
  EXPECT_EQ(r.depth_convention, static_cast<uint32_t>(ATMO_DEPTH_REVERSED_ZERO_TO_ONE));
  EXPECT_EQ(r.far_plane_m, 0.0);
}

TEST(Exposure, Ev100) {
  EXPECT_DOUBLE_EQ(hs::exposure_scale_from_ev100(15.0), 1.0 / (1.2 * 32768.0));
}

TEST(DepthConventionNames, Parse) {
  hs::DepthConvention c{};
  EXPECT_TRUE(hs::parse_depth_convention("log", &c));
  EXPECT_EQ(c, hs::DepthConvention::Logarithmic);
  EXPECT_TRUE(hs::parse_depth_convention("reversed", &c));
  EXPECT_EQ(c, hs::DepthConvention::Reversed);
  EXPECT_TRUE(hs::parse_depth_convention("standard", &c));
  EXPECT_EQ(c, hs::DepthConvention::Standard);
  EXPECT_FALSE(hs::parse_depth_convention("bogus", &c));
}
