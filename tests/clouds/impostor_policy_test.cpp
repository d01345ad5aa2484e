// The impostor policy (core/clouds/impostor_policy): the billboard covers the
// cloud's silhouette from the eye it is rendered from; the view change
// counts turning and approaching; the direct march's weight is continuous
// and monotonic across the cross-fade band; the update budget takes the
// stalest first and a camera cut re-renders everything at once.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/clouds/impostor_policy.h"

namespace {

using namespace atmo::clouds;

TEST(ImpostorPolicy, BillboardCoversTheSilhouette) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double distance : {1.2, 2.0, 5.0, 50.0}) {
    const double r = 400.0;
    const glm::dvec3 centre(1000.0, -2000.0, 1500.0);
    const glm::dvec3 eye = centre - glm::normalize(glm::dvec3(0.3, 1.0, -0.2)) * (distance * r);
    const Billboard b = make_billboard(eye, centre, r);
    EXPECT_NEAR(glm::length(b.right), 1.0, 1e-12);
    EXPECT_NEAR(glm::dot(b.right, b.up), 0.0, 1e-12);
    EXPECT_NEAR(glm::dot(b.right, centre - eye), 0.0, 1e-6);
    // Rays from the eye to points on the sphere cross the plane inside the square.
    const glm::dvec3 n = glm::normalize(centre - eye);
    double worst = 0.0;
    for (int i = 0; i < 20000; ++i) {
      glm::dvec3 p = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng))) * r + centre;
      const glm::dvec3 ray = p - eye;
      const double t = glm::dot(centre - eye, n) / glm::dot(ray, n);
      if (t <= 0.0) continue;
      const glm::dvec3 hit = eye + ray * t - centre;
      worst = std::max({worst, std::abs(glm::dot(hit, b.right)), std::abs(glm::dot(hit, b.up))});
    }
    EXPECT_LE(worst, b.half_size_m * (1.0 + 1e-9)) << "at " << distance << " radii";
    // ... and the square is not much larger than needed (the silhouette touches its sides).
    EXPECT_GE(worst, b.half_size_m * 0.97) << "at " << distance << " radii";
  }
}

TEST(ImpostorPolicy, ViewChangeCountsTurningAndApproaching) {
  const glm::dvec3 centre(0.0, 5000.0, 0.0);
  const double r = 300.0;
  const glm::dvec3 eye(0.0);
  EXPECT_DOUBLE_EQ(impostor_view_change_rad(eye, eye, centre, r), 0.0);
  // Sideways by 50 m at 5 km: a turn of ~0.573 degrees.
  EXPECT_NEAR(impostor_view_change_rad(eye, glm::dvec3(50.0, 0.0, 0.0), centre, r), std::atan(50.0 / 5000.0), 1e-9);
  // Straight at it by 500 m: the angular radius grows from asin(300/5000) to asin(300/4500).
  EXPECT_NEAR(impostor_view_change_rad(eye, glm::dvec3(0.0, 500.0, 0.0), centre, r),
              std::asin(300.0 / 4500.0) - std::asin(300.0 / 5000.0), 1e-12);
  // Finite at and inside the sphere.
  EXPECT_TRUE(std::isfinite(impostor_view_change_rad(eye, centre, centre, r)));
  EXPECT_TRUE(std::isfinite(impostor_view_change_rad(eye, centre + glm::dvec3(10, 0, 0), centre, r)));
}

TEST(ImpostorPolicy, DirectMarchWeightIsContinuousAndMonotonic) {
  ImpostorSettings s;
  const double r = 500.0, ppr = 300.0;
  double previous = 1.0;
  double largest_step = 0.0;
  for (double d = 0.0; d <= 40.0 * r; d += 5.0) {
    const double w = direct_march_weight(direct_march_need(d, r, ppr, s), s);
    ASSERT_TRUE(std::isfinite(w));
    EXPECT_LE(w, previous + 1e-12) << "at " << d << " m";  // farther never marches more
    largest_step = std::max(largest_step, previous - w);
    previous = w;
  }
  EXPECT_DOUBLE_EQ(direct_march_weight(direct_march_need(0.5 * r, r, ppr, s), s), 1.0);   // inside: direct
  EXPECT_DOUBLE_EQ(direct_march_weight(direct_march_need(40.0 * r, r, ppr, s), s), 0.0);  // far: impostor
  EXPECT_LT(largest_step, 0.05);  // 5 m steps: no jump
  // The resolution metric: a cloud far away but magnified on a dense screen marches.
  EXPECT_DOUBLE_EQ(direct_march_weight(direct_march_need(20.0 * r, r, 1e5, s), s), 1.0);
}

TEST(ImpostorPolicy, BudgetTakesTheStalestAndACutTakesAll) {
  ImpostorSettings s;
  s.updates_per_frame = 2;
  const std::vector<double> staleness = {0.5, 3.0, 1.2, 40.0, 2.0, 0.99, 17.0};
  const std::vector<size_t> chosen = choose_impostor_updates(staleness, s);
  // Cuts (>= 16) always, then the two stalest of the rest.
  ASSERT_EQ(chosen.size(), 4u);
  EXPECT_EQ(chosen[0], 3u);
  EXPECT_EQ(chosen[1], 6u);
  EXPECT_EQ(chosen[2], 1u);
  EXPECT_EQ(chosen[3], 4u);
  s.updates_per_frame = 0;
  EXPECT_EQ(choose_impostor_updates(staleness, s).size(), 2u);
  EXPECT_TRUE(choose_impostor_updates({}, s).empty());
}

}  // namespace
