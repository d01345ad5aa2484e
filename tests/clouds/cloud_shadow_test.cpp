// The clouds' shadow map (core/clouds/cloud_shadow) against an independent
// march of the field's summed extinction (field_density_at, fine steps)
// along the light from ground points; the affine uv map slides a point along
// the light; a grazing light or no clouds gives no shadow; a thick deck
// shadows to (near) black. The direct transmittance along one ray
// (core/clouds/cloud_transmittance, get_lighting's Sun at the eye) against the
// same independent march, and its buckets against visiting every box.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/clouds/cloud_shadow.h"
#include "core/clouds/cloud_transmittance.h"
#include "core/clouds/procedural_clouds.h"
#include "core/atmosphere/shader_twin.h"

#include <glm/gtc/matrix_transform.hpp>

namespace {

using namespace atmo::clouds;

CloudField cumulus_field() {
  CloudLayerSpec spec;
  spec.coverage_oktas = 4;
  spec.base_m = 1000.0;
  spec.top_m = 2000.0;
  spec.area_size_m = 4000.0;
  spec.seed = 5;
  spec.max_total_voxels = 1u << 20;
  return generate_cloud_layer(spec).field;
}

glm::dvec3 light(double elevation_deg, double azimuth_deg) {
  const double e = glm::radians(elevation_deg), a = glm::radians(azimuth_deg);
  return {std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e)};
}

// exp(-integral of sigma_t) from g towards the light, fine midpoint steps,
// over `length` metres (default: up to 4 km above g).
double reference_transmittance(const CloudField& f, const glm::dvec3& g, const glm::dvec3& l, double length = 0.0) {
  const double extinction = f.prototypes[0].optics.extinction_per_m;
  const double dt = 2.0;
  if (length <= 0.0) length = 4000.0 / l.z;
  double tau = 0.0;
  for (double t = 0.5 * dt; t < length; t += dt) tau += field_density_at(f, g + l * t) * dt * extinction;
  return std::exp(-tau);
}

TEST(CloudShadow, MatchesAMarchOfTheField) {
  const CloudField f = cumulus_field();
  for (double elevation : {30.0, 60.0, 90.0}) {
    const glm::dvec3 l = light(elevation, 135.0);
    const CloudShadowMap map = compute_cloud_shadow_map(f, l, 256, 1e5, 0.5f);
    ASSERT_EQ(map.size, 256);
    std::mt19937 rng(1);
    std::uniform_int_distribution<int> texel(0, map.size - 1);
    double worst = 0.0, mean = 0.0, shadowed = 0.0;
    const int n = 400;
    for (int i = 0; i < n; ++i) {
      const int x = texel(rng), y = texel(rng);
      const glm::dvec3 g(map.corner_enu_m.x + (x + 0.5) * map.texel_m, map.corner_enu_m.y + (y + 0.5) * map.texel_m, 0.0);
      const double ref = reference_transmittance(f, g, l);
      const double got = map.transmittance[static_cast<size_t>(y) * map.size + x];
      worst = std::max(worst, std::abs(got - ref));
      mean += std::abs(got - ref) / n;
      shadowed += ref < 0.5 ? 1.0 / n : 0.0;
    }
    std::printf("light %2.0f deg up: map %d^2 of %.0f m texels; |T - T_ref| mean %.4f, worst %.4f (%.0f %% of samples shadowed)\n",
                elevation, map.size, map.texel_m, mean, worst, 100.0 * shadowed);
    EXPECT_GT(shadowed, 0.05);  // the samples do hit shadows
    EXPECT_LT(mean, 0.005);
    EXPECT_LT(worst, 0.05);
  }
}

TEST(CloudShadow, APointSlidesAlongTheLight) {
  const CloudField f = cumulus_field();
  const glm::dvec3 l = light(40.0, 200.0);
  const CloudShadowMap map = compute_cloud_shadow_map(f, l, 128);
  const glm::dvec3 ground(300.0, -200.0, 0.0);
  for (double h : {0.0, 500.0, 900.0})
    EXPECT_NEAR(sample_cloud_shadow(map, ground + l * (h / l.z)), sample_cloud_shadow(map, ground), 1e-9) << h;
  EXPECT_EQ(sample_cloud_shadow(map, glm::dvec3(1e7, 0.0, 0.0)), 1.0);  // off the map: no shadow
}

TEST(CloudShadow, NoShadowWithoutCloudsOrWithAGrazingLight) {
  const CloudShadowMap none = compute_cloud_shadow_map(CloudField{}, light(45.0, 0.0));
  EXPECT_EQ(none.size, 0);
  EXPECT_EQ(sample_cloud_shadow(none, glm::dvec3(0.0)), 1.0);
  const CloudShadowMap grazing = compute_cloud_shadow_map(cumulus_field(), light(0.5, 90.0), 64);
  for (float t : grazing.transmittance) ASSERT_EQ(t, 1.0f);
  const CloudShadowMap below = compute_cloud_shadow_map(cumulus_field(), light(-10.0, 90.0), 64);
  for (float t : below.transmittance) ASSERT_EQ(t, 1.0f);
}

CloudField overcast_field() {
  CloudLayerSpec spec;
  spec.type = CloudLayerType::Overcast;
  spec.coverage_oktas = 8;
  spec.base_m = 600.0;
  spec.top_m = 1100.0;
  spec.area_size_m = 6000.0;
  spec.seed = 3;
  return generate_cloud_layer(spec).field;
}

TEST(CloudShadow, AnOvercastDeckShadowsTheGround) {
  const CloudField f = overcast_field();
  const CloudShadowMap map = compute_cloud_shadow_map(f, light(45.0, 180.0), 128);
  const double t = sample_cloud_shadow(map, glm::dvec3(0.0, 0.0, 0.0));
  std::printf("under the deck's centre: direct transmittance %.2e\n", t);
  EXPECT_LT(t, 1e-3);
  EXPECT_GE(t, 0.0);
}

// Rows shared among threads (the maps a host waits for): the same map.
TEST(CloudShadow, ThreadsGiveTheSameMap) {
  const CloudField f = cumulus_field();
  const CloudShadowMap one = compute_cloud_shadow_map(f, light(20.0, 150.0), 96);
  for (int threads : {2, 3, 200}) {
    const CloudShadowMap many = compute_cloud_shadow_map(f, light(20.0, 150.0), 96, 1e5, 1.0f, threads);
    EXPECT_EQ(many.transmittance, one.transmittance) << threads << " threads";
    EXPECT_EQ(many.corner_enu_m, one.corner_enu_m);
  }
  double shaded = 0.0;
  for (float t : one.transmittance) shaded += 1.0 - t;
  EXPECT_GT(shaded, 1.0);  // the map holds shadows (the comparison compares something)
}

// The sky passes' lookup (functions.glsl cloud_shadowing_at, its C++ twin)
// through cloud_shadow_uvz_from, for points given relative to an eye in a
// turned and shifted frame, against sample_cloud_shadow at the same points in
// the clouds' frame: equal below the clouds, 1 above them, a linear fade
// between base and top.
TEST(CloudShadow, TheSkyPassesLookupIsTheMapsOwn) {
  const CloudField f = cumulus_field();
  const CloudShadowMap map = compute_cloud_shadow_map(f, light(40.0, 150.0), 128);
  atmo::twin::Lut2D lut;
  lut.width = lut.height = map.size;
  for (float t : map.transmittance) lut.texels.push_back(glm::vec3(t));
  // The eye's frame: turned 30 degrees about the vertical, 2 km east of the clouds' origin, 300 m up.
  glm::dmat4 clouds_from_eye(glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(30.0), glm::dvec3(0, 0, 1))));
  clouds_from_eye[3] = glm::dvec4(2000.0, 0.0, 300.0, 1.0);
  atmo::twin::CloudShadowing cs;
  cs.uv_from_eye_enu = glm::mat4(cloud_shadow_uvz_from(map, clouds_from_eye));
  cs.base_m = 1000.0f;
  cs.top_m = 2000.0f;
  cs.enabled = 1;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> across(-4000.0, 4000.0), up(-300.0, 2500.0);
  double worst = 0.0;
  int shadowed = 0;
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 p_eye(across(rng), across(rng), up(rng));
    const glm::dvec3 p = glm::dvec3(clouds_from_eye * glm::dvec4(p_eye, 1.0));
    const double below = sample_cloud_shadow(map, p);
    const double within = std::clamp((p.z - 1000.0) / 1000.0, 0.0, 1.0);
    const double expected = p.z >= 2000.0 ? 1.0 : below + (1.0 - below) * within;
    const double got = atmo::twin::cloud_shadowing_at(cs, lut, glm::vec3(p_eye));
    worst = std::max(worst, std::abs(got - expected));
    shadowed += expected < 0.5 ? 1 : 0;
  }
  std::printf("sky passes' shadow lookup against the map's: worst |difference| %.2e (%d of 2000 points in shadow)\n",
              worst, shadowed);
  EXPECT_LT(worst, 2e-3);  // float matrix and texel weights against double
  EXPECT_GT(shadowed, 20);
  cs.enabled = 0;
  EXPECT_EQ(atmo::twin::cloud_shadowing_at(cs, lut, glm::vec3(0.0f)), 1.0f);
}

// One ray from an eye below, inside or above a 4-okta cumulus layer
// (1-2 km) towards lights 3-90 degrees up, against the independent fine march
// of the field's summed density (2 m steps, 6 km of ray): |T - T_ref|, and
// the bucketed boxes against a single bucket holding every box (the same
// boxes, so equal to rounding): a bucket the ray's track crosses is never
// missed.
TEST(CloudRayTransmittance, MatchesAFineMarchOfTheField) {
  const CloudField f = cumulus_field();
  const CloudRayIndex index = build_cloud_ray_index(f);
  const CloudRayIndex one_bucket = build_cloud_ray_index(f, 1);
  ASSERT_GT(index.nx * index.ny, 1);
  ASSERT_EQ(one_bucket.nx * one_bucket.ny, 1);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> across(-2500.0, 2500.0), height(0.0, 2600.0), elevation(3.0, 90.0),
      azimuth(0.0, 360.0);
  double worst = 0.0, mean = 0.0, worst_bucket = 0.0, shadowed = 0;
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 eye(across(rng), across(rng), height(rng));
    const glm::dvec3 l = light(elevation(rng), azimuth(rng));
    const double t = transmittance_along_ray(f, index, eye, l, 1e300, 0.5);
    const double ref = reference_transmittance(f, eye, l, 6000.0);
    const double all = transmittance_along_ray(f, one_bucket, eye, l, 1e300, 0.5);
    worst = std::max(worst, std::abs(t - ref));
    mean += std::abs(t - ref) / n;
    worst_bucket = std::max(worst_bucket, std::abs(t - all));
    if (ref < 0.99) ++shadowed;
  }
  std::printf("one ray through 4-okta cumulus, %d rays (%.0f through cloud): |T - T_ref| mean %.2e, worst %.2e; "
              "buckets against every box: worst %.1e\n",
              n, shadowed, mean, worst, worst_bucket);
  EXPECT_GT(shadowed, 0.1 * n);  // the rays do cross clouds
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(mean, 1e-3);
  EXPECT_LT(worst_bucket, 1e-12);
}

// Under a 500 m overcast deck and inside it 50 m above its base, the Sun
// is gone (< 1e-6: tau > 13.8; a 300 m deck's thinnest column has tau
// 11.5); above the deck, beside it or with the ray stopped short of it,
// nothing is in the way (exactly 1).
TEST(CloudRayTransmittance, ADeckHidesTheSunFromBelowAndInside) {
  const CloudField f = overcast_field();
  const CloudRayIndex index = build_cloud_ray_index(f);
  for (double e : {20.0, 45.0, 90.0}) {  // lower, the ray from the centre leaves the 6 km deck's side first
    const double below = transmittance_along_ray(f, index, glm::dvec3(0.0, 0.0, 100.0), light(e, 180.0));
    const double inside = transmittance_along_ray(f, index, glm::dvec3(0.0, 0.0, 650.0), light(e, 180.0));
    std::printf("sun %2.0f deg: below the deck T %.1e, inside %.1e\n", e, below, inside);
    EXPECT_LT(below, 1e-6);
    EXPECT_LT(inside, 1e-6);
    EXPECT_GE(below, 0.0);
  }
  EXPECT_EQ(transmittance_along_ray(f, index, glm::dvec3(0.0, 0.0, 1200.0), light(20.0, 180.0)), 1.0);
  EXPECT_EQ(transmittance_along_ray(f, index, glm::dvec3(20000.0, 0.0, 100.0), light(60.0, 90.0)), 1.0);
  EXPECT_EQ(transmittance_along_ray(f, index, glm::dvec3(0.0, 0.0, 100.0), light(90.0, 0.0), 400.0), 1.0);
  EXPECT_EQ(transmittance_along_ray(CloudField{}, build_cloud_ray_index(CloudField{}), glm::dvec3(0.0),
                                    light(45.0, 0.0)),
            1.0);
}

}  // namespace
