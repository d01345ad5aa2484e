// Terrain of atmo_host_scene without GL: determinism, runway area, lights.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "atmo_host_scene/terrain.h"

namespace hs = atmo::host_scene;

namespace {
hs::TerrainOptions small(uint64_t seed) {
  hs::TerrainOptions o;
  o.seed = seed;
  o.grid = 64;  // enough to test, quick to build
  return o;
}
}  // namespace

TEST(Terrain, SameSeedSameHeights) {
  const hs::Terrain a(small(42)), b(small(42));
  ASSERT_EQ(a.heights().size(), 64u * 64u);
  EXPECT_EQ(a.heights(), b.heights());
  for (double e : {-15000.0, -3210.5, 0.0, 8000.25, 17000.0}) {
    EXPECT_EQ(a.height_at(e, 0.37 * e + 5000.0), b.height_at(e, 0.37 * e + 5000.0));
  }
}

TEST(Terrain, DifferentSeedDifferentHeights) {
  const hs::Terrain a(small(1)), b(small(2));
  EXPECT_NE(a.heights(), b.heights());
}

TEST(Terrain, HeightsWithinReliefAndHilly) {
  const hs::Terrain t(small(7));
  const auto [lo, hi] = std::minmax_element(t.heights().begin(), t.heights().end());
  EXPECT_GE(*lo, 0.0f);
  EXPECT_LE(*hi, static_cast<float>(t.options().relief_m) + 1e-3f);
  EXPECT_GT(*hi, 0.2f * static_cast<float>(t.options().relief_m));  // there are hills
}

TEST(Terrain, RunwayAreaIsFlat) {
  hs::TerrainOptions o = small(3);
  o.grid = 256;
  const hs::Terrain t(o);
  // Runway heading 90: along east. The whole strip and the approach lights' area.
  for (double e = -2500.0; e <= 1500.0; e += 100.0) {
    for (double n : {-100.0, -22.5, 0.0, 22.5, 100.0}) EXPECT_EQ(t.height_at(e, n), 0.0) << e << "," << n;
  }
}

TEST(Terrain, LightPointCount) {
  const hs::Terrain t(hs::TerrainOptions{});  // default grid: the flat area is resolved
  const int edge = 2 * (static_cast<int>(3000.0 / hs::kEdgeLightSpacingM) + 1);
  const size_t expected = static_cast<size_t>(hs::kApproachBars * hs::kApproachBarLights + hs::kCrossbarLights +
                                              2 * hs::kThresholdLights + edge);
  EXPECT_EQ(expected, 304u);
  ASSERT_EQ(t.light_points().size(), expected);
  for (const hs::LightPoint& l : t.light_points()) {
    EXPECT_GT(l.intensity_cd, 0.0f);
    // Lights sit on the flat ground, dropped with the curvature.
    const double drop = hs::curvature_drop_m(l.position_enu_m.x, l.position_enu_m.y);
    EXPECT_NEAR(l.position_enu_m.z, 0.5 - drop, 1e-9);
    EXPECT_NEAR(l.position_enu_m.y, 0.0, 40.0);  // near the runway axis (east-west)
  }
  // Approach lights lie before the approach (west) end.
  EXPECT_LT(t.light_points().front().position_enu_m.x, -1500.0);
}

TEST(Terrain, KindNoneIsEmpty) {
  hs::TerrainOptions o;
  o.kind = hs::TerrainOptions::Kind::None;
  const hs::Terrain t(o);
  EXPECT_TRUE(t.heights().empty());
  EXPECT_TRUE(t.light_points().empty());
  EXPECT_EQ(t.height_at(100.0, 100.0), 0.0);
}

TEST(Terrain, CurvatureDrop) {
  EXPECT_NEAR(hs::curvature_drop_m(10000.0, 0.0), 1e8 / (2.0 * 6371000.0), 1e-9);
  EXPECT_NEAR(hs::curvature_drop_m(3000.0, 4000.0), 25e6 / (2.0 * 6371000.0), 1e-9);
}

TEST(Lighting, FromAtmo) {
  AtmoLighting l{};
  l.sun_direction_enu[0] = 0.0;
  l.sun_direction_enu[1] = 0.0;
  l.sun_direction_enu[2] = 2.0;  // not unit: normalised
  l.sun_elevation_rad = 1.5707963267948966;
  l.sun_illuminance_lux[0] = l.sun_illuminance_lux[1] = l.sun_illuminance_lux[2] = 100000.0;
  l.sky_illuminance_horizontal_lux[0] = 9000.0;
  l.sky_illuminance_horizontal_lux[1] = 12000.0;
  l.sky_illuminance_horizontal_lux[2] = 20000.0;
  const hs::SceneLighting s = hs::lighting_from_atmo(l);
  EXPECT_NEAR(s.sun_direction_enu.z, 1.0, 1e-12);
  // The terrain's ambient is the plugin's sky illuminance (plus a starlight floor).
  EXPECT_NEAR(s.sky_ambient_lux.y, 12000.0, 0.01);
  EXPECT_NEAR(s.sky_ambient_lux.z, 20000.0, 0.01);

  l.sun_elevation_rad = -0.3;  // -17 deg: night
  l.sun_illuminance_lux[0] = l.sun_illuminance_lux[1] = l.sun_illuminance_lux[2] = 0.0;
  l.sky_illuminance_horizontal_lux[0] = l.sky_illuminance_horizontal_lux[1] = l.sky_illuminance_horizontal_lux[2] = 0.0;
  const hs::SceneLighting night = hs::lighting_from_atmo(l);
  EXPECT_LT(night.sky_ambient_lux.y, 0.1);
  EXPECT_GT(night.sky_ambient_lux.y, 0.0);
}
