// Relighting the clouds (abi/cloud_relight, abi/cloud_inputs relight_clouds):
// the first lighting is immediate; later, when the light moves past the
// threshold, the call that notices starts a worker and returns at once with
// the old grids untouched; the first call after the worker ends swaps in
// grids equal (bit for bit) to a direct computation for the new light (each
// grid's own depths plus core/clouds/field_light's neighbours). A
// move under the threshold does nothing; replacing or destroying the clouds
// while a job runs cancels and joins it (ASan/UBSan builds run this too).
#include <gtest/gtest.h>

#include <cmath>

#include "abi/cloud_inputs.h"
#include "core/clouds/field_light.h"
#include "core/clouds/procedural_clouds.h"

namespace {

namespace clouds = atmo::clouds;

atmo::abi::ContextClouds make_clouds() {
  clouds::CloudLayerSpec spec;
  spec.coverage_oktas = 3;
  spec.base_m = 1000.0;
  spec.top_m = 1800.0;
  spec.area_size_m = 3000.0;
  spec.seed = 7;
  spec.max_total_voxels = 300000;  // coarse: the test is about threads, not detail
  atmo::abi::ContextClouds c;
  c.field = clouds::generate_cloud_layer(spec).field;
  c.depths.resize(c.field.prototypes.size());
  for (size_t p = 0; p < c.field.prototypes.size(); ++p)
    clouds::compute_ambient_depths(c.field.prototypes[p], &c.depths[p]);
  return c;
}

glm::dvec3 sun(double elevation_deg, double azimuth_deg) {
  const double e = glm::radians(elevation_deg), a = glm::radians(azimuth_deg);
  return {std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e)};
}

// The grids equal a fresh computation for `dir`, every voxel's three depths.
void expect_lit_for(const atmo::abi::ContextClouds& c, const glm::dvec3& dir) {
  std::vector<clouds::LightDepths> all;
  for (const clouds::CloudVolume& v : c.field.prototypes) all.push_back(clouds::compute_light_depths(v, dir));
  clouds::add_field_light_depths(c.field, dir, &all);
  for (size_t p = 0; p < c.field.prototypes.size(); ++p) {
    const clouds::LightDepths& fresh = all[p];
    ASSERT_EQ(fresh.tau.size(), c.depths[p].tau.size());
    for (size_t i = 0; i < fresh.tau.size(); ++i) ASSERT_EQ(fresh.tau[i], c.depths[p].tau[i]) << "prototype " << p;
  }
}

TEST(CloudRelight, FirstNowThenOnAWorkerWithoutStallingTheCaller) {
  atmo::abi::ContextClouds c = make_clouds();
  ASSERT_GT(c.field.prototypes.size(), 0u);
  const glm::dvec3 a = sun(30.0, 120.0), b = sun(36.0, 128.0);
  EXPECT_TRUE(atmo::abi::relight_clouds(&c, a));  // never lit: at once
  EXPECT_FALSE(c.relighting());
  expect_lit_for(c, a);
  const uint64_t v = c.version;
  // Under the 0.5 degree threshold: nothing.
  EXPECT_FALSE(atmo::abi::relight_clouds(&c, sun(30.3, 120.0)));
  EXPECT_FALSE(c.relighting());
  // Past it: a job starts; the grids and version stay as they were.
  EXPECT_FALSE(atmo::abi::relight_clouds(&c, b));
  ASSERT_TRUE(c.relighting());
  EXPECT_EQ(c.version, v);
  expect_lit_for(c, a);
  c.relight.job->wait();
  std::printf("relight of %zu prototypes on the worker: %.1f ms\n", c.field.prototypes.size(),
              c.relight.job->elapsed_ms());
  EXPECT_TRUE(atmo::abi::relight_clouds(&c, b));  // swapped in
  EXPECT_FALSE(c.relighting());
  EXPECT_EQ(c.version, v + 1);
  EXPECT_EQ(c.lit_direction_enu, b);
  expect_lit_for(c, b);
}

TEST(CloudRelight, ReplacingOrDestroyingTheCloudsStopsTheJob) {
  for (int round = 0; round < 3; ++round) {
    atmo::abi::ContextClouds c = make_clouds();
    atmo::abi::relight_clouds(&c, sun(20.0, 90.0));
    atmo::abi::relight_clouds(&c, sun(60.0, 200.0));
    ASSERT_TRUE(c.relighting());
    if (round == 0) c.relight.reset();                // cancelled and joined
    if (round == 1) c = make_clouds();                // set_clouds: move-assigned over a running job
    EXPECT_EQ(c.relighting(), round == 2);
  }  // round 2: destroyed with the job running
}

}  // namespace
