// The accumulated CIGI environment and its mapping onto the plugin's structs
// (host_sdk cigi.h; docs/CIGI.md).
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "atmo/cigi.h"
#include "atmo_scenario/units.h"

namespace c = atmo::cigi;

namespace {

c::IgControl ig_at(uint32_t frame, uint32_t ticks, bool valid = true) {
  c::IgControl ig;
  ig.host_frame_number = frame;
  ig.timestamp_ticks = ticks;
  ig.timestamp_valid = valid;
  return ig;
}

c::CelestialControl date_time(unsigned month, unsigned day, unsigned year, uint8_t hour, uint8_t minute,
                              bool ephemeris) {
  c::CelestialControl cel;
  cel.date_mmddyyyy = month * 1000000u + day * 10000u + year;
  cel.hour = hour;
  cel.minute = minute;
  cel.date_time_valid = true;
  cel.ephemeris_enable = ephemeris;
  cel.star_enable = true;
  return cel;
}

c::WeatherControl cloud(uint8_t layer, uint8_t type, float coverage, float base, float thickness) {
  c::WeatherControl w;
  w.layer_id = layer;
  w.weather_enable = true;
  w.cloud_type = type;
  w.coverage_pct = coverage;
  w.base_elevation_m = base;
  w.thickness_m = thickness;
  w.top_transition_band_m = w.transition_band_m;
  return w;
}

bool has_note(const c::PluginState& s, const std::string& part) {
  for (const std::string& n : s.notes)
    if (n.find(part) != std::string::npos) return true;
  return false;
}

// 2024-06-21T14:30:00Z
constexpr double kSolstice = 1718980200.0;

}  // namespace

TEST(CigiTime, CivilDatesToPosixSeconds) {
  EXPECT_EQ(*c::utc_from_civil(1970, 1, 1, 0, 0, 0), 0.0);
  EXPECT_EQ(*c::utc_from_civil(2000, 1, 1, 0, 0, 0), 946684800.0);
  EXPECT_EQ(*c::utc_from_civil(2024, 6, 21, 14, 30, 0), kSolstice);
  EXPECT_EQ(*c::utc_from_civil(2024, 2, 29, 23, 59, 59.5), 1709251199.5);
  EXPECT_EQ(*c::utc_from_civil(1, 1, 1, 0, 0, 0), -62135596800.0);      // the plugin's lower bound
  EXPECT_EQ(*c::utc_from_civil(9999, 12, 31, 23, 59, 59), 253402300799.0);  // and its upper
  EXPECT_FALSE(c::utc_from_civil(2023, 2, 29, 0, 0, 0));
  EXPECT_FALSE(c::utc_from_civil(2100, 2, 29, 0, 0, 0));  // not a leap year
  EXPECT_TRUE(c::utc_from_civil(2000, 2, 29, 0, 0, 0));   // a leap year
  EXPECT_FALSE(c::utc_from_civil(2024, 13, 1, 0, 0, 0));
  EXPECT_FALSE(c::utc_from_civil(2024, 4, 31, 0, 0, 0));
  EXPECT_FALSE(c::utc_from_civil(0, 1, 1, 0, 0, 0));
  EXPECT_FALSE(c::utc_from_civil(2024, 1, 1, 24, 0, 0));
  EXPECT_FALSE(c::utc_from_civil(2024, 1, 1, 0, 60, 0));
  EXPECT_FALSE(c::utc_from_civil(2024, 1, 1, 0, 0, 60.0));
}

TEST(CigiTime, DateTimeValidSetsTheTimeElseTheHostsStands) {
  c::EnvironmentState env;
  c::MappingInputs in;
  in.host_utc_posix_s = 1.0e9;
  EXPECT_EQ(c::to_plugin(env, in).frame.utc_posix_s, 1.0e9);
  EXPECT_FALSE(c::to_plugin(env, in).time_from_cigi);

  c::CelestialControl no_date = date_time(6, 21, 2024, 14, 30, false);
  no_date.date_time_valid = false;
  env.apply(ig_at(1, 0));
  env.apply(no_date);
  EXPECT_EQ(c::to_plugin(env, in).frame.utc_posix_s, 1.0e9);

  env.apply(date_time(6, 21, 2024, 14, 30, false));
  const c::PluginState s = c::to_plugin(env, in);
  EXPECT_TRUE(s.time_from_cigi);
  EXPECT_EQ(s.frame.utc_posix_s, kSolstice);
  EXPECT_EQ(s.frame.header.type, uint32_t(ATMO_TYPE_FRAME_STATE));
  EXPECT_EQ(s.frame.header.struct_size, sizeof(AtmoFrameState));
  EXPECT_EQ(s.frame.host_frame_number, 1u);

  // CIGI 4.0 carries seconds.
  c::CelestialControl with_seconds = date_time(6, 21, 2024, 14, 30, false);
  with_seconds.seconds = 12.5f;
  env.apply(with_seconds);
  EXPECT_EQ(c::to_plugin(env, in).frame.utc_posix_s, kSolstice + 12.5);
}

TEST(CigiTime, AnInvalidDateIsLoggedAndIgnored) {
  c::EnvironmentState env;
  env.apply(date_time(6, 21, 2024, 14, 30, false));
  env.apply(date_time(2, 30, 2024, 14, 30, false));
  ASSERT_EQ(env.log.size(), 1u);
  EXPECT_NE(env.log[0].find("2302024"), std::string::npos) << env.log[0];
  EXPECT_EQ(*env.utc_posix_s(), kSolstice);
}

// The ephemeris model runs the time on the IG Control timestamps (10 µs
// ticks) and freezes it when disabled.
TEST(CigiTime, TheEphemerisRunsOnTimestampsAndFreezes) {
  c::EnvironmentState env;
  env.apply(ig_at(1, 1000));
  env.apply(date_time(6, 21, 2024, 14, 30, true));
  env.apply(ig_at(2, 1000 + 100000));  // 1 s later
  EXPECT_DOUBLE_EQ(*env.utc_posix_s(), kSolstice + 1.0);

  // Disabled (date invalid, so only the flag changes): frozen at the time reached.
  c::CelestialControl freeze = date_time(1, 1, 2000, 0, 0, false);
  freeze.date_time_valid = false;
  env.apply(freeze);
  env.apply(ig_at(3, 1000 + 500000));
  EXPECT_DOUBLE_EQ(*env.utc_posix_s(), kSolstice + 1.0);

  // Re-enabled: runs on from there.
  c::CelestialControl run = freeze;
  run.ephemeris_enable = true;
  env.apply(run);
  env.apply(ig_at(4, 1000 + 700000));
  EXPECT_DOUBLE_EQ(*env.utc_posix_s(), kSolstice + 3.0);

  // The 32-bit counter wraps: the unsigned difference still counts forward.
  env.apply(ig_at(5, 0xFFFFFF00u));
  env.apply(run);
  const uint64_t before = env.time_set->elapsed_ticks;
  env.apply(ig_at(6, 0x100u));
  EXPECT_EQ(env.time_set->elapsed_ticks - before, 512u);

  // Without valid timestamps the time does not run.
  env.apply(ig_at(7, 0, false));
  env.apply(run);
  const double frozen = *env.utc_posix_s();
  env.apply(ig_at(8, 99999999, false));
  EXPECT_EQ(*env.utc_posix_s(), frozen);
}

TEST(CigiState, RegionsAndWeatherLayersById) {
  c::EnvironmentState env;
  c::RegionControl r;
  r.region_id = 7;
  r.state = c::kRegionActive;
  env.apply(r);
  c::WeatherControl rain;
  rain.layer_id = c::kLayerRain;
  rain.scope = c::kScopeRegional;
  rain.entity_region_id = 7;
  env.apply(rain);
  c::WeatherControl global1 = cloud(1, c::kCumulus, 50, 1000, 500);
  global1.entity_region_id = 99;  // ignored for global scope
  env.apply(global1);
  env.apply(cloud(1, c::kStratus, 100, 800, 400));  // replaces layer 1
  EXPECT_EQ(env.regions.size(), 1u);
  ASSERT_EQ(env.weather.size(), 2u);
  EXPECT_EQ((env.weather.at(c::WeatherKey{c::kScopeGlobal, 0, 1}).cloud_type), c::kStratus);
  EXPECT_EQ((env.weather.count(c::WeatherKey{c::kScopeRegional, 7, c::kLayerRain})), 1u);

  r.state = c::kRegionDestroyed;
  env.apply(r);
  EXPECT_TRUE(env.regions.empty());
  EXPECT_EQ(env.weather.size(), 1u);  // the region's rain went with it
}

TEST(CigiState, ARefusedDatagramChangesNothing) {
  c::EnvironmentState env;
  std::vector<uint8_t> b = c::encode(c::Version{3, 3}, c::ByteOrder::Little,
                                     {c::IgControl{}, c::AtmosphereControl{}, cloud(1, c::kCumulus, 50, 1, 1)});
  b.pop_back();
  const c::DecodeResult d = c::decode(b);
  ASSERT_FALSE(d.ok());
  EXPECT_FALSE(env.apply(d));
  EXPECT_FALSE(env.ig_control || env.atmosphere);
  EXPECT_TRUE(env.weather.empty());
}

// ---- mapping ------------------------------------------------------------------

TEST(CigiMapping, VisibilityFromAtmosphereControlWins) {
  c::EnvironmentState env;
  c::MappingInputs in;
  EXPECT_EQ(c::to_plugin(env, in).atmosphere.visibility_m, 0.0);  // the plugin's default
  EXPECT_EQ(c::to_plugin(env, in).atmosphere.header.type, uint32_t(ATMO_TYPE_ATMOSPHERE_STATE));

  c::WeatherControl dust;
  dust.layer_id = c::kLayerDust;
  dust.weather_enable = true;
  dust.visibility_m = 3000;
  env.apply(dust);
  c::WeatherControl rain = dust;
  rain.layer_id = c::kLayerRain;
  rain.visibility_m = 1500;
  env.apply(rain);
  EXPECT_EQ(c::to_plugin(env, in).atmosphere.visibility_m, 1500.0);  // no Atmosphere Control: the lowest

  c::AtmosphereControl atm;
  atm.visibility_m = 9000;
  env.apply(atm);
  EXPECT_EQ(c::to_plugin(env, in).atmosphere.visibility_m, 9000.0);

  atm.visibility_m = 10;
  env.apply(atm);
  const c::PluginState s = c::to_plugin(env, in);
  EXPECT_EQ(s.atmosphere.visibility_m, 50.0);
  EXPECT_TRUE(has_note(s, "clamped to 50 m")) << (s.notes.empty() ? "" : s.notes[0]);
  atm.visibility_m = 0;
  env.apply(atm);
  EXPECT_EQ(c::to_plugin(env, in).atmosphere.visibility_m, 0.0);
}

TEST(CigiMapping, CloudLayersOneToThree) {
  c::EnvironmentState env;
  env.apply(cloud(1, c::kCumulus, 50, 1200, 1300));
  env.apply(cloud(2, c::kNimbostratus, 100, 3000, 1000));
  env.apply(cloud(3, c::kCirrus, 30, 9000, 500));
  c::WeatherControl regional = cloud(1, c::kStratus, 100, 500, 200);
  regional.scope = c::kScopeRegional;
  env.apply(regional);  // accepted, not drawn
  c::MappingInputs in;
  in.clouds_origin_geodetic[0] = 47.0;
  in.clouds_origin_geodetic[1] = 8.0;
  in.clouds_origin_geodetic[2] = 400.0;  // the origin 400 m above the ellipsoid
  in.geoid_undulation_m = 50.0;          // MSL 50 m above the ellipsoid here
  const c::PluginState s = c::to_plugin(env, in);
  ASSERT_EQ(s.cloud_layer_count, 3u);
  const AtmoCloudLayer& cu = s.cloud_layers[0];
  EXPECT_EQ(cu.header.type, uint32_t(ATMO_TYPE_CLOUD_LAYER));
  EXPECT_EQ(cu.header.struct_size, sizeof(AtmoCloudLayer));
  EXPECT_EQ(cu.type, uint32_t(ATMO_CLOUD_CUMULUS));
  EXPECT_EQ(cu.coverage_oktas, 4);
  EXPECT_EQ(cu.base_m, 1200.0 + 50.0 - 400.0);
  EXPECT_EQ(cu.top_m, 2500.0 + 50.0 - 400.0);
  EXPECT_EQ(cu.seed, 1u);
  EXPECT_EQ(s.cloud_layers[1].type, uint32_t(ATMO_CLOUD_OVERCAST));
  EXPECT_EQ(s.cloud_layers[1].coverage_oktas, 8);
  EXPECT_EQ(s.cloud_layers[2].type, uint32_t(ATMO_CLOUD_CIRRUS));
  EXPECT_EQ(s.cloud_layers[2].coverage_oktas, 2);

  const AtmoCloudsState cs = s.clouds_state();
  EXPECT_EQ(cs.header.type, uint32_t(ATMO_TYPE_CLOUDS_STATE));
  EXPECT_EQ(cs.layers, s.cloud_layers.data());
  EXPECT_EQ(cs.layer_count, 3u);
  EXPECT_EQ(cs.layer_size, sizeof(AtmoCloudLayer));
  EXPECT_EQ(cs.origin_geodetic[0], 47.0);
  EXPECT_EQ(cs.origin_geodetic[2], 400.0);
}

TEST(CigiMapping, CloudLayersThePluginCannotDrawAreNamed) {
  c::EnvironmentState env;
  env.apply(cloud(1, c::kCloudNone, 50, 1000, 500));
  env.apply(cloud(2, 12, 50, 1000, 500));           // user-defined type
  env.apply(cloud(3, c::kStratus, 50, 1000, 0));    // no thickness
  c::MappingInputs in;
  c::PluginState s = c::to_plugin(env, in);
  EXPECT_EQ(s.cloud_layer_count, 0u);
  EXPECT_EQ(s.clouds_state().layers, nullptr);
  EXPECT_TRUE(has_note(s, "cloud layer 1: cloud type 0"));
  EXPECT_TRUE(has_note(s, "cloud layer 2: cloud type 12"));
  EXPECT_TRUE(has_note(s, "cloud layer 3: thickness 0"));

  // A thickness below the base's rounding: top == base (found by fuzz_cigi).
  c::EnvironmentState thin;
  thin.apply(cloud(1, c::kStratus, 50, 1200.008f, 1.5e-38f));
  s = c::to_plugin(thin, in);
  EXPECT_EQ(s.cloud_layer_count, 0u);
  EXPECT_TRUE(has_note(s, "does not lift the top above the base"));

  c::EnvironmentState high;
  high.apply(cloud(1, c::kCirrus, 50, 19000, 3000));  // top clamped
  high.apply(cloud(2, c::kCumulus, 50, 100, 500));    // base below the origin
  c::WeatherControl off = cloud(3, c::kCumulus, 50, 2000, 500);
  off.weather_enable = false;
  high.apply(off);
  in.clouds_origin_geodetic[2] = 300;
  s = c::to_plugin(high, in);
  ASSERT_EQ(s.cloud_layer_count, 1u);
  EXPECT_EQ(s.cloud_layers[0].top_m, 20000.0);
  EXPECT_TRUE(has_note(s, "clamped to 20000 m"));
  EXPECT_TRUE(has_note(s, "cloud layer 2: base -200"));
}

TEST(CigiMapping, CloudTypesAndCoverage) {
  EXPECT_EQ(c::plugin_cloud_type(c::kCumulus), ATMO_CLOUD_CUMULUS);
  EXPECT_EQ(c::plugin_cloud_type(c::kAltocumulus), ATMO_CLOUD_CUMULUS);
  EXPECT_EQ(c::plugin_cloud_type(c::kCumulonimbus), ATMO_CLOUD_CUMULUS);
  EXPECT_EQ(c::plugin_cloud_type(c::kStratus), ATMO_CLOUD_STRATUS);
  EXPECT_EQ(c::plugin_cloud_type(c::kStratocumulus), ATMO_CLOUD_STRATUS);
  EXPECT_EQ(c::plugin_cloud_type(c::kAltostratus), ATMO_CLOUD_STRATUS);
  EXPECT_EQ(c::plugin_cloud_type(c::kNimbostratus), ATMO_CLOUD_OVERCAST);
  EXPECT_EQ(c::plugin_cloud_type(c::kCirrus), ATMO_CLOUD_CIRRUS);
  EXPECT_EQ(c::plugin_cloud_type(c::kCirrostratus), ATMO_CLOUD_CIRRUS);
  EXPECT_EQ(c::plugin_cloud_type(c::kCirrocumulus), ATMO_CLOUD_CIRRUS);
  EXPECT_FALSE(c::plugin_cloud_type(c::kCloudNone));
  for (uint8_t t = 11; t <= 15; ++t) EXPECT_FALSE(c::plugin_cloud_type(t));

  EXPECT_EQ(c::coverage_pct_to_oktas(0), 0);
  EXPECT_EQ(c::coverage_pct_to_oktas(-5), 0);
  EXPECT_EQ(c::coverage_pct_to_oktas(1), 1);
  EXPECT_EQ(c::coverage_pct_to_oktas(50), 4);
  EXPECT_EQ(c::coverage_pct_to_oktas(99), 7);
  EXPECT_EQ(c::coverage_pct_to_oktas(100), 8);
  EXPECT_EQ(c::coverage_pct_to_oktas(150), 8);
  // The scenario loader's rule, so a CIGI host and a scenario file agree.
  for (int pct = -10; pct <= 110; ++pct) {
    EXPECT_EQ(c::coverage_pct_to_oktas(pct), atmo::scenario::units::fraction_to_okta_code(pct / 100.0)) << pct;
  }
}

TEST(CigiMapping, GroundFogFromLayerZero) {
  c::EnvironmentState env;
  c::MappingInputs in;
  in.geoid_undulation_m = 30;
  EXPECT_EQ(c::to_plugin(env, in).fog.visibility_m, 0.0);  // no fog
  c::WeatherControl fog;
  fog.layer_id = c::kLayerGroundFog;
  fog.weather_enable = true;
  fog.visibility_m = 400;
  fog.base_elevation_m = 100;
  fog.thickness_m = 150;
  env.apply(fog);
  c::PluginState s = c::to_plugin(env, in);
  EXPECT_EQ(s.fog.header.type, uint32_t(ATMO_TYPE_FOG_STATE));
  EXPECT_EQ(s.fog.visibility_m, 400.0);
  EXPECT_EQ(s.fog.top_height_m, 100.0 + 150.0 + 30.0);  // above the ellipsoid

  fog.visibility_m = 2;
  env.apply(fog);
  s = c::to_plugin(env, in);
  EXPECT_EQ(s.fog.visibility_m, 10.0);
  EXPECT_TRUE(has_note(s, "ground fog: visibility 2 m clamped to 10 m"));

  fog.weather_enable = false;
  env.apply(fog);
  EXPECT_EQ(c::to_plugin(env, in).fog.visibility_m, 0.0);

  fog.weather_enable = true;
  fog.thickness_m = 0;
  env.apply(fog);
  s = c::to_plugin(env, in);
  EXPECT_EQ(s.fog.visibility_m, 0.0);
  EXPECT_TRUE(has_note(s, "ground fog: thickness 0 m: not drawn"));
}

TEST(CigiMapping, StarFieldEnableSaysWhetherToDrawTheNightSky) {
  c::EnvironmentState env;
  c::MappingInputs in;
  EXPECT_TRUE(c::to_plugin(env, in).night_sky);
  c::CelestialControl cel = date_time(6, 21, 2024, 14, 30, false);
  cel.star_enable = false;
  env.apply(cel);
  EXPECT_FALSE(c::to_plugin(env, in).night_sky);
}

// A whole message from bytes to the plugin's structs.
TEST(CigiMapping, FromADatagram) {
  c::IgControl ig = ig_at(4242, 0);
  c::AtmosphereControl atm;
  atm.visibility_m = 20000;
  const std::vector<uint8_t> bytes =
      c::encode(c::Version{4, 0}, c::ByteOrder::Big,
                {ig, date_time(12, 24, 2023, 18, 5, false), atm, cloud(2, c::kStratocumulus, 75, 900, 300)});
  c::EnvironmentState env;
  const c::DecodeResult d = c::decode(bytes);
  ASSERT_TRUE(env.apply(d)) << d.error->message;
  const c::PluginState s = c::to_plugin(env, c::MappingInputs{});
  EXPECT_EQ(s.frame.host_frame_number, 4242u);
  EXPECT_EQ(s.frame.utc_posix_s, *c::utc_from_civil(2023, 12, 24, 18, 5, 0));
  EXPECT_EQ(s.atmosphere.visibility_m, 20000.0);
  ASSERT_EQ(s.cloud_layer_count, 1u);
  EXPECT_EQ(s.cloud_layers[0].type, uint32_t(ATMO_CLOUD_STRATUS));
  EXPECT_EQ(s.cloud_layers[0].coverage_oktas, 6);
  EXPECT_EQ(s.cloud_layers[0].base_m, 900.0);
  EXPECT_EQ(s.cloud_layers[0].top_m, 1200.0);
  EXPECT_EQ(s.cloud_layers[0].seed, 2u);
}
