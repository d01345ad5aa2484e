// The eye frame: the same camera given through an ECEF world or a local ENU
// world gives the same orientation, and huge coordinates lose nothing.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "core/geo/eye_frame.h"

using namespace atmo::core;

TEST(EyeFrame, EcefAndEnuWorldsAgree) {
  const Geodetic eye{47.26, 11.35, 900.0};
  glm::dmat3 ecef_from_enu_m = ecef_from_enu(eye.latitude_deg, eye.longitude_deg);
  // Camera looking north-east, pitched up 10°, in ENU.
  glm::dvec3 forward_enu = glm::normalize(glm::dvec3(0.7, 0.7, 0.17));
  glm::dmat4 view_enu = glm::lookAt(glm::dvec3(0), forward_enu, glm::dvec3(0, 0, 1));
  glm::dmat4 view_ecef = glm::lookAt(glm::dvec3(0), ecef_from_enu_m * forward_enu, ecef_from_enu_m[2]);

  CameraInput a;
  a.eye_is_geodetic = true;
  a.eye_geodetic = eye;
  a.world_frame = WorldFrame::Enu;
  a.world_origin = eye;
  a.view_from_world = view_enu;
  a.clip_from_view = glm::perspective(1.0, 1.5, 1.0, 1e5);
  CameraInput b = a;
  b.eye_is_geodetic = false;
  b.eye_ecef_m = ecef_from_geodetic(eye);
  b.world_frame = WorldFrame::Ecef;
  b.view_from_world = view_ecef;
  EyeFrame fa, fb;
  std::string why;
  ASSERT_TRUE(make_eye_frame(a, &fa, &why)) << why;
  ASSERT_TRUE(make_eye_frame(b, &fb, &why)) << why;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(fa.enu_from_view[c][r], fb.enu_from_view[c][r], 1e-9);
  EXPECT_NEAR(fb.eye.height_m, 900.0, 1e-6);
  // The camera's -z axis is the forward direction.
  glm::dvec3 fwd = fa.enu_from_view * glm::dvec3(0, 0, -1);
  EXPECT_NEAR(glm::dot(fwd, forward_enu), 1.0, 1e-12);
}

TEST(EyeFrame, MillimetreMovesAtEcefScaleAreResolved) {
  // An eye 6 378 km from the centre moved 1 mm up: the height must change by 1 mm.
  CameraInput in;
  in.eye_ecef_m = glm::dvec3(6378137.0 + 500.0, 0.0, 0.0);
  in.clip_from_view = glm::perspective(1.0, 1.5, 1.0, 1e5);
  EyeFrame a, b;
  std::string why;
  ASSERT_TRUE(make_eye_frame(in, &a, &why));
  in.eye_ecef_m.x += 0.001;
  ASSERT_TRUE(make_eye_frame(in, &b, &why));
  EXPECT_NEAR(b.eye.height_m - a.eye.height_m, 0.001, 1e-8);
}

TEST(EyeFrame, SingularMatricesAreRefused) {
  CameraInput in;
  in.eye_ecef_m = glm::dvec3(6378137.0, 0.0, 0.0);
  in.view_from_world = glm::dmat4(0.0);
  in.clip_from_view = glm::perspective(1.0, 1.5, 1.0, 1e5);
  EyeFrame f;
  std::string why;
  EXPECT_FALSE(make_eye_frame(in, &f, &why));
  EXPECT_NE(why.find("view_from_world"), std::string::npos);
  in.view_from_world = glm::dmat4(1.0);
  in.clip_from_view = glm::dmat4(0.0);
  EXPECT_FALSE(make_eye_frame(in, &f, &why));
  EXPECT_NE(why.find("clip_from_view"), std::string::npos);
}
