// Relighting the clouds (abi/cloud_relight, abi/cloud_inputs relight_clouds):
// the first lighting is immediate; later, when the light moves past the
// threshold, the call that notices starts a worker and returns at once with
// the old grids untouched; the first call after the worker ends swaps in
// grids equal (bit for bit) to a direct computation for the new light (each
// grid's own depths plus core/clouds/field_light's neighbours). A
// move under the threshold does nothing; replacing or destroying the clouds
// while a job runs cancels and joins it (ASan/UBSan builds run this too).
// The streamed layer march (ATMO_CLOUD_SETUP_STREAM): a draft at once, the
// full lighting and each cell's clipmap from workers, ending equal to a
// direct build; ATMO_CLOUD_SETUP_WAIT leaves no job behind.
#include <gtest/gtest.h>

#include <algorithm>
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

// A worker's relight lands at the host frame it is due (ATMO_DEFERRED_FRAMES after it started), not when it
// ends: every channel switches on the same frame.
TEST(CloudRelight, FirstNowThenOnAWorkerAtItsFrameWithoutStallingTheCaller) {
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
  const uint64_t started = c.frame;
  for (uint64_t f = started; f < started + ATMO_DEFERRED_FRAMES; ++f) {
    c.frame = f;
    EXPECT_FALSE(atmo::abi::relight_clouds(&c, b)) << "done, but not due at frame " << f;
    EXPECT_TRUE(c.relighting());
    expect_lit_for(c, a);
  }
  c.frame = started + ATMO_DEFERRED_FRAMES;
  EXPECT_TRUE(atmo::abi::relight_clouds(&c, b));  // swapped in at its frame
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


// --- The streamed layer march (ATMO_CLOUD_SETUP_STREAM) -------------------

namespace stream {

bool same_clipmap(const clouds::CloudClipmap& a, const clouds::CloudClipmap& b) {
  if (a.levels.size() != b.levels.size() || a.cell != b.cell) return false;
  for (size_t l = 0; l < a.levels.size(); ++l)
    if (a.levels[l].a != b.levels[l].a || a.levels[l].b != b.levels[l].b || a.levels[l].nx != b.levels[l].nx)
      return false;
  return true;
}

// The first pass lights and resamples the half-resolution draft at once and
// leaves the field's whole lighting to the worker; once it lands, the
// clipmap is rebuilt on a worker while the draft's is still drawn, and ends
// equal (bit for bit) to one built directly from the full lighting. An eye
// in another cell gets its clipmap the same way: the old one until then.
TEST(CloudStreamedSetUp, DraftFirstThenTheFullFieldFromTheWorkers) {
  atmo::abi::ContextClouds c = make_clouds();
  c.settings.layer = true;
  c.sides.assign(c.field.prototypes.size(), {});
  atmo::abi::prepare_draft(&c);
  ASSERT_EQ(c.draft.prototypes.size(), c.field.prototypes.size());
  EXPECT_EQ(c.draft.prototypes[0].voxel_size_m, 2.0f * c.field.prototypes[0].voxel_size_m);
  const glm::dvec3 light = sun(35.0, 140.0), eye(0.0, 0.0, 1400.0);

  EXPECT_TRUE(atmo::abi::relight_clouds(&c, light));
  EXPECT_FALSE(c.full_lit);
  EXPECT_TRUE(c.relighting());  // the field's lighting runs on the worker
  EXPECT_TRUE(atmo::abi::update_clipmap(&c, eye));
  ASSERT_FALSE(c.clipmap.levels.empty());  // the draft's, at once
  EXPECT_EQ(c.clipmap.levels[0].nx, c.settings.clipmap.size / 2);
  float finest = 1e30f;
  for (const clouds::CloudVolume& v : c.field.prototypes) finest = std::min(finest, v.voxel_size_m);
  EXPECT_EQ(c.clipmap.levels[0].voxel_m, 2.0 * finest);
  EXPECT_FALSE(c.settled());

  atmo::abi::wait_for_cloud_jobs(&c);
  EXPECT_TRUE(atmo::abi::relight_clouds(&c, light));  // the full grids swapped in
  EXPECT_TRUE(c.full_lit);
  expect_lit_for(c, light);
  const uint64_t draft_clipmap = c.clipmap_version;
  EXPECT_FALSE(atmo::abi::update_clipmap(&c, eye));  // a worker builds the full clipmap; the draft's stays
  EXPECT_EQ(c.clipmap_version, draft_clipmap);
  EXPECT_EQ(c.clipmap.levels[0].nx, c.settings.clipmap.size / 2);
  atmo::abi::wait_for_cloud_jobs(&c);
  EXPECT_TRUE(atmo::abi::update_clipmap(&c, eye));
  EXPECT_TRUE(c.settled());
  const auto mips = clouds::build_prototype_mips(c.field, c.depths, light);
  const clouds::ClipmapGeometry g = clouds::clipmap_geometry(c.field, c.settings.clipmap);
  const glm::ivec2 cell = clouds::clipmap_cell(g, eye);
  EXPECT_TRUE(same_clipmap(c.clipmap, clouds::build_clipmap(c.field, mips, c.ray_index, c.settings.clipmap, g, cell)));

  // Into the next cell: the old clipmap until the worker's is ready.
  const glm::dvec3 moved = eye + glm::dvec3(1.5 * g.cell_m, 0.0, 0.0);
  const glm::ivec2 next = clouds::clipmap_cell(g, moved);
  ASSERT_NE(next, cell);
  EXPECT_FALSE(atmo::abi::update_clipmap(&c, moved));
  EXPECT_EQ(c.clipmap.cell, cell);
  atmo::abi::wait_for_cloud_jobs(&c);
  EXPECT_TRUE(atmo::abi::update_clipmap(&c, moved));
  EXPECT_EQ(c.clipmap.cell, next);
  EXPECT_TRUE(same_clipmap(c.clipmap, clouds::build_clipmap(c.field, mips, c.ray_index, c.settings.clipmap, g, next)));
}

// settings.wait: no draft; every pass has the full lighting and the clipmap for its cell.
TEST(CloudStreamedSetUp, WaitingHasNoDraftAndNoJobLeft) {
  atmo::abi::ContextClouds c = make_clouds();
  c.settings.layer = true;
  c.settings.wait = true;
  const glm::dvec3 eye(0.0, 0.0, 1400.0);
  EXPECT_TRUE(atmo::abi::relight_clouds(&c, sun(35.0, 140.0)));
  EXPECT_TRUE(c.full_lit);
  EXPECT_TRUE(atmo::abi::update_clipmap(&c, eye));
  EXPECT_TRUE(c.settled());
  // A relight past the threshold, and a move into another cell: done when the call returns.
  EXPECT_TRUE(atmo::abi::relight_clouds(&c, sun(45.0, 150.0)));
  EXPECT_FALSE(c.relighting());
  EXPECT_TRUE(atmo::abi::update_clipmap(&c, eye + glm::dvec3(1.5 * c.clipmap_geometry.cell_m, 0.0, 0.0)));
  EXPECT_TRUE(c.settled());
}

// Replacing or destroying the clouds while both jobs run stops them.
TEST(CloudStreamedSetUp, ReplacingTheCloudsStopsBothJobs) {
  for (int round = 0; round < 2; ++round) {
    atmo::abi::ContextClouds c = make_clouds();
    c.settings.layer = true;
    atmo::abi::prepare_draft(&c);
    const glm::dvec3 eye(0.0, 0.0, 1400.0);
    atmo::abi::relight_clouds(&c, sun(20.0, 90.0));
    atmo::abi::update_clipmap(&c, eye);
    atmo::abi::update_clipmap(&c, eye + glm::dvec3(1.5 * c.clipmap_geometry.cell_m, 0.0, 0.0));
    ASSERT_TRUE(c.clipmap_job.job != nullptr);
    ASSERT_TRUE(c.relighting());
    if (round == 0) {
      c = make_clouds();  // set_clouds: move-assigned over the running jobs
      EXPECT_FALSE(c.relighting());
      EXPECT_TRUE(c.clipmap_job.job == nullptr);
    }
  }  // round 1: destroyed with both running
}

}  // namespace stream

}  // namespace
