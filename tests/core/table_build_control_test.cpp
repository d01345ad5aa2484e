// Progress and cancellation of the table builders: progress after every row,
// ending at 1; a stop flag checked before each row ends the build at once with
// an empty table; neither changes the table that comes out.
#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include "core/atmosphere/atmosphere_model.h"

namespace core = atmo::core;
namespace twin = atmo::twin;

namespace {

twin::AtmosphereParameters air() { return core::make_atmosphere_parameters(core::AtmosphereSettings{}, 6371000.0, 1.0); }

bool same(const twin::Lut2D& a, const twin::Lut2D& b) {
  if (a.width != b.width || a.height != b.height || a.texels.size() != b.texels.size()) return false;
  for (size_t i = 0; i < a.texels.size(); ++i)
    if (a.texels[i] != b.texels[i]) return false;
  return true;
}

}  // namespace

TEST(TableBuildControl, ProgressAfterEveryRowEndingAtOneAndTheSameTable) {
  const twin::AtmosphereParameters atm = air();
  std::vector<double> seen;
  core::TableBuildControl control;
  control.progress = [&](double f) { seen.push_back(f); };
  twin::Lut2D t = core::compute_transmittance_table(atm, 64, 16, 64, control);
  ASSERT_EQ(seen.size(), 16u);
  for (size_t i = 1; i < seen.size(); ++i) EXPECT_GT(seen[i], seen[i - 1]);
  EXPECT_EQ(seen.back(), 1.0);
  EXPECT_TRUE(same(t, core::compute_transmittance_table(atm, 64, 16, 64)));

  seen.clear();
  twin::Lut2D ms = core::compute_multiple_scattering_table(atm, t, 8, 8, 8, 8, control);
  ASSERT_EQ(seen.size(), 8u);
  EXPECT_EQ(seen.back(), 1.0);
  EXPECT_TRUE(same(ms, core::compute_multiple_scattering_table(atm, t, 8, 8, 8, 8)));
}

TEST(TableBuildControl, AStopFlagEndsTheBuildBeforeTheNextRow) {
  const twin::AtmosphereParameters atm = air();
  std::atomic<bool> stop{false};
  int rows = 0;
  core::TableBuildControl control;
  control.stop = &stop;
  control.progress = [&](double f) {
    ++rows;
    if (f >= 0.25) stop = true;  // as another thread would, a quarter of the way in
  };
  twin::Lut2D t = core::compute_transmittance_table(atm, 64, 16, 64, control);
  EXPECT_EQ(rows, 4);  // 4 of 16 rows, then it stopped
  EXPECT_EQ(t.width, 0);
  EXPECT_EQ(t.height, 0);
  EXPECT_TRUE(t.texels.empty());

  twin::Lut2D full = core::compute_transmittance_table(atm, 64, 16, 64);
  rows = 0;
  stop = false;
  twin::Lut2D ms = core::compute_multiple_scattering_table(atm, full, 8, 8, 8, 8, control);
  EXPECT_EQ(rows, 2);  // 2 of 8 rows
  EXPECT_EQ(ms.width, 0);

  stop = true;  // set before the build: no row at all
  rows = 0;
  EXPECT_EQ(core::compute_transmittance_table(atm, 64, 16, 64, control).width, 0);
  EXPECT_EQ(rows, 0);
}
