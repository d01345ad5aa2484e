// The CIGI decoder and encoder (host_sdk cigi.h): golden datagrams written
// byte by byte from the layout table (docs/CIGI.md), round trips in both byte
// orders and both versions, refused and skipped packets.
#include <cmath>
#include <cstring>
#include <limits>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "atmo/cigi.h"

namespace c = atmo::cigi;
using Bytes = std::vector<uint8_t>;

namespace {

// CIGI 3.3, big-endian (the magic 0x80 0x00): IG Control, Celestial Sphere
// Control, Atmosphere Control, Environmental Region Control, Weather Control.
// Written by hand (python struct, '>' formats) from the table, not by the encoder.
const Bytes kGolden33Big = {
    0x01, 0x18, 0x03, 0x05, 0x35, 0x00, 0x80, 0x00,  // IG Control: v3, db 5, operate|ts valid|minor 3, magic
    0x00, 0x00, 0x01, 0x02, 0x00, 0x01, 0x00, 0x00,  // frame 0x102, timestamp 0x10000
    0x00, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00, 0x00,  // last IG frame 7
    0x09, 0x10, 0x0e, 0x1e, 0x1f, 0x00, 0x00, 0x00,  // Celestial: 14:30, all five flags
    0x00, 0x5e, 0xc9, 0xb8, 0x42, 0x48, 0x00, 0x00,  // date 06212024, stars 50 %
    0x0a, 0x20, 0x01, 0x2d, 0xc0, 0xb0, 0x00, 0x00,  // Atmosphere: enable, 45 %, -5.5 °C
    0x45, 0xfa, 0x00, 0x00, 0x40, 0x40, 0x00, 0x00,  // 8000 m, 3 m/s
    0x3f, 0x00, 0x00, 0x00, 0x42, 0xb4, 0x00, 0x00,  // 0.5 m/s, 90°
    0x44, 0x77, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00,  // 990 mb
    0x0b, 0x30, 0x01, 0x2c, 0x25, 0x00, 0x00, 0x00,  // Region 300: active, merge weather, terrestrial
    0x40, 0x47, 0xa0, 0x00, 0x00, 0x00, 0x00, 0x00,  // 47.25°
    0xc0, 0x5e, 0xa0, 0x00, 0x00, 0x00, 0x00, 0x00,  // -122.5°
    0x46, 0x1c, 0x40, 0x00, 0x45, 0x9c, 0x40, 0x00,  // 10 000 x 5 000 m
    0x43, 0xfa, 0x00, 0x00, 0x41, 0xf0, 0x00, 0x00,  // corner 500 m, 30°
    0x44, 0x7a, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // transition 1000 m
    0x0c, 0x38, 0x00, 0x00, 0x01, 0x50, 0x71, 0x08,  // Weather: global layer 1, 80 %, enable, cumulus, severity 2
    0x41, 0x70, 0x00, 0x00, 0x44, 0x7a, 0x00, 0x00,  // 15 °C, 1000 m
    0x00, 0x00, 0x00, 0x00, 0x42, 0x48, 0x00, 0x00,  // scud 0 %, coverage 50 %
    0x44, 0x96, 0x00, 0x00, 0x44, 0xa2, 0x80, 0x00,  // base 1200 m, thickness 1300 m
    0x42, 0xc8, 0x00, 0x00, 0x40, 0xa0, 0x00, 0x00,  // transition 100 m, 5 m/s
    0x00, 0x00, 0x00, 0x00, 0x43, 0x87, 0x00, 0x00,  // 0 m/s, 270°
    0x44, 0x7d, 0x50, 0x00, 0x00, 0x00, 0x00, 0x00,  // 1013.25 mb, aerosol 0
};

// CIGI 4.0, little-endian (size 24 = 0x18 0x00 first): the same packets in
// their 4.0 layouts (python struct, '<' formats).
const Bytes kGolden40Little = {
    0x18, 0x00, 0x00, 0x00, 0x04, 0x05, 0x01, 0x35,  // IG Control: v4, db 5, entity substitution, flags
    0x02, 0x01, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00,  // frame 0x102, last IG frame 7
    0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00,  // timestamp 0x10000
    0x18, 0x00, 0x08, 0x00, 0x1f, 0x00, 0x0e, 0x1e,  // Celestial: flags, 14:30
    0x00, 0x00, 0x78, 0x41, 0xb8, 0xc9, 0x5e, 0x00,  // 15.5 s, date 06212024
    0x00, 0x00, 0x48, 0x42, 0x00, 0x00, 0x00, 0x00,  // stars 50 %
    0x20, 0x00, 0x09, 0x00, 0xad, 0x00, 0x00, 0x00,  // Atmosphere: enable | 45 %
    0x00, 0x00, 0xb0, 0xc0, 0x00, 0x00, 0xfa, 0x45,  // -5.5 °C, 8000 m
    0x00, 0x00, 0x40, 0x40, 0x00, 0x00, 0x00, 0x3f,
    0x00, 0x00, 0xb4, 0x42, 0x00, 0x80, 0x77, 0x44,
    0x30, 0x00, 0x0a, 0x00, 0x25, 0x00, 0x2c, 0x01,  // Region: flags, id 300 at byte 6
    0x00, 0x00, 0x00, 0x00, 0x00, 0xa0, 0x47, 0x40,
    0x00, 0x00, 0x00, 0x00, 0x00, 0xa0, 0x5e, 0xc0,
    0x00, 0x40, 0x1c, 0x46, 0x00, 0x40, 0x9c, 0x45,
    0x00, 0x00, 0xfa, 0x43, 0x00, 0x00, 0xf0, 0x41,
    0x00, 0x00, 0x7a, 0x44, 0x00, 0x00, 0x00, 0x00,
    0x48, 0x00, 0x0b, 0x00, 0x01, 0x50, 0x73, 0x28,  // Weather: layer 1, 80 %, enable|scud|cumulus, sev 2|top scud
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x70, 0x41,  // id 0, reserved, 15 °C
    0x00, 0x00, 0x7a, 0x44, 0x00, 0x00, 0x20, 0x41,  // 1000 m, bottom scud 10 %
    0x00, 0x00, 0x48, 0x42, 0x00, 0x00, 0x96, 0x44,  // 50 %, base 1200 m
    0x00, 0x80, 0xa2, 0x44, 0x00, 0x00, 0xc8, 0x42,  // 1300 m, bottom transition 100 m
    0x00, 0x00, 0xa0, 0x40, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x87, 0x43, 0x00, 0x50, 0x7d, 0x44,
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xc8, 0x41,  // aerosol 0, top scud 25 %
    0x00, 0x00, 0x48, 0x43, 0x00, 0x00, 0x00, 0x00,  // top transition 200 m
};

template <typename T>
const T& as(const c::Event& e) {
  return std::get<T>(e);
}

// The values both golden datagrams carry.
void expect_golden_values(const c::DecodeResult& d, bool v4) {
  ASSERT_TRUE(d.ok()) << d.error->message;
  ASSERT_EQ(d.events.size(), 5u);
  const auto& ig = as<c::IgControl>(d.events[0]);
  EXPECT_EQ(ig.database_id, 5);
  EXPECT_EQ(ig.ig_mode, 1);
  EXPECT_TRUE(ig.timestamp_valid);
  EXPECT_FALSE(ig.smoothing_enable);
  EXPECT_EQ(ig.minor_version, 3);
  EXPECT_EQ(ig.entity_substitution_enable, v4);
  EXPECT_EQ(ig.host_frame_number, 0x102u);
  EXPECT_EQ(ig.timestamp_ticks, 0x10000u);
  EXPECT_EQ(ig.last_ig_frame_number, 7u);

  const auto& cel = as<c::CelestialControl>(d.events[1]);
  EXPECT_EQ(cel.hour, 14);
  EXPECT_EQ(cel.minute, 30);
  EXPECT_EQ(cel.seconds, v4 ? 15.5f : 0.0f);
  EXPECT_EQ(cel.date_mmddyyyy, 6212024u);
  EXPECT_EQ(cel.month(), 6u);
  EXPECT_EQ(cel.day(), 21u);
  EXPECT_EQ(cel.year(), 2024u);
  EXPECT_TRUE(cel.ephemeris_enable && cel.sun_enable && cel.moon_enable && cel.star_enable && cel.date_time_valid);
  EXPECT_EQ(cel.star_intensity_pct, 50.0f);

  const auto& atm = as<c::AtmosphereControl>(d.events[2]);
  EXPECT_TRUE(atm.model_enable);
  EXPECT_EQ(atm.humidity_pct, 45);
  EXPECT_EQ(atm.air_temperature_c, -5.5f);
  EXPECT_EQ(atm.visibility_m, 8000.0f);
  EXPECT_EQ(atm.horizontal_wind_mps, 3.0f);
  EXPECT_EQ(atm.vertical_wind_mps, 0.5f);
  EXPECT_EQ(atm.wind_direction_deg, 90.0f);
  EXPECT_EQ(atm.pressure_hpa, 990.0f);

  const auto& rgn = as<c::RegionControl>(d.events[3]);
  EXPECT_EQ(rgn.region_id, 300);
  EXPECT_EQ(rgn.state, c::kRegionActive);
  EXPECT_TRUE(rgn.merge_weather);
  EXPECT_FALSE(rgn.merge_aerosol);
  EXPECT_FALSE(rgn.merge_maritime);
  EXPECT_TRUE(rgn.merge_terrestrial);
  EXPECT_EQ(rgn.latitude_deg, 47.25);
  EXPECT_EQ(rgn.longitude_deg, -122.5);
  EXPECT_EQ(rgn.size_x_m, 10000.0f);
  EXPECT_EQ(rgn.size_y_m, 5000.0f);
  EXPECT_EQ(rgn.corner_radius_m, 500.0f);
  EXPECT_EQ(rgn.rotation_deg, 30.0f);
  EXPECT_EQ(rgn.transition_perimeter_m, 1000.0f);

  const auto& wx = as<c::WeatherControl>(d.events[4]);
  EXPECT_EQ(wx.entity_region_id, 0);
  EXPECT_EQ(wx.layer_id, 1);
  EXPECT_EQ(wx.humidity_pct, 80);
  EXPECT_TRUE(wx.weather_enable);
  EXPECT_EQ(wx.scud_enable, v4);
  EXPECT_EQ(wx.top_scud_enable, v4);
  EXPECT_FALSE(wx.random_winds_enable);
  EXPECT_FALSE(wx.random_lightning_enable);
  EXPECT_EQ(wx.cloud_type, c::kCumulus);
  EXPECT_EQ(wx.scope, c::kScopeGlobal);
  EXPECT_EQ(wx.severity, 2);
  EXPECT_EQ(wx.air_temperature_c, 15.0f);
  EXPECT_EQ(wx.visibility_m, 1000.0f);
  EXPECT_EQ(wx.scud_frequency_pct, v4 ? 10.0f : 0.0f);
  EXPECT_EQ(wx.coverage_pct, 50.0f);
  EXPECT_EQ(wx.base_elevation_m, 1200.0f);
  EXPECT_EQ(wx.thickness_m, 1300.0f);
  EXPECT_EQ(wx.transition_band_m, 100.0f);
  EXPECT_EQ(wx.horizontal_wind_mps, 5.0f);
  EXPECT_EQ(wx.vertical_wind_mps, 0.0f);
  EXPECT_EQ(wx.wind_direction_deg, 270.0f);
  EXPECT_EQ(wx.pressure_hpa, 1013.25f);
  EXPECT_EQ(wx.aerosol_gpm3, 0.0f);
  EXPECT_EQ(wx.top_scud_frequency_pct, v4 ? 25.0f : 0.0f);
  EXPECT_EQ(wx.top_transition_band_m, v4 ? 200.0f : 100.0f);
}

// The same packets as the golden datagrams, as events.
std::vector<c::Event> golden_events(bool v4) {
  c::DecodeResult d = c::decode(v4 ? kGolden40Little : kGolden33Big);
  EXPECT_TRUE(d.ok());
  return d.events;
}

// Every field set to something other than its default, distinct per field.
std::vector<c::Event> varied_events(bool v4) {
  c::IgControl ig;
  ig.minor_version = v4 ? 0 : 3;
  ig.database_id = -7;
  ig.ig_mode = 2;
  ig.timestamp_valid = true;
  ig.smoothing_enable = true;
  ig.entity_substitution_enable = v4;
  ig.host_frame_number = 0xDEADBEEF;
  ig.timestamp_ticks = 0x89ABCDEF;
  ig.last_ig_frame_number = 0x01020304;
  c::CelestialControl cel;
  cel.hour = 23;
  cel.minute = 59;
  cel.seconds = v4 ? 59.25f : 0.0f;
  cel.date_mmddyyyy = 12312099;
  cel.ephemeris_enable = true;
  cel.moon_enable = true;
  cel.date_time_valid = true;
  cel.star_intensity_pct = 12.5f;
  c::AtmosphereControl atm;
  atm.model_enable = true;
  atm.humidity_pct = 99;
  atm.air_temperature_c = -40.25f;
  atm.visibility_m = 12345.5f;
  atm.horizontal_wind_mps = 17.0f;
  atm.vertical_wind_mps = -2.0f;
  atm.wind_direction_deg = 359.5f;
  atm.pressure_hpa = 1040.5f;
  c::RegionControl rgn;
  rgn.region_id = 0xBEEF;
  rgn.state = c::kRegionDestroyed;
  rgn.merge_aerosol = true;
  rgn.merge_maritime = true;
  rgn.latitude_deg = -33.8688197;
  rgn.longitude_deg = 151.2092955;
  rgn.size_x_m = 1.5f;
  rgn.size_y_m = 2.5f;
  rgn.corner_radius_m = 0.25f;
  rgn.rotation_deg = -45.0f;
  rgn.transition_perimeter_m = 75.0f;
  c::WeatherControl wx;
  wx.entity_region_id = 0xBEEF;
  wx.layer_id = 9;
  wx.humidity_pct = 255;
  wx.weather_enable = true;
  wx.scud_enable = true;
  wx.top_scud_enable = !v4;  // 4.0 carries both; 3.x only equal ones
  wx.random_winds_enable = true;
  wx.random_lightning_enable = true;
  wx.cloud_type = 15;
  wx.scope = c::kScopeRegional;
  wx.severity = 5;
  wx.air_temperature_c = 30.5f;
  wx.visibility_m = 250.0f;
  wx.scud_frequency_pct = 33.0f;
  wx.coverage_pct = 87.5f;
  wx.base_elevation_m = -12.0f;
  wx.thickness_m = 4321.0f;
  wx.transition_band_m = 55.0f;
  wx.horizontal_wind_mps = 9.0f;
  wx.vertical_wind_mps = 1.25f;
  wx.wind_direction_deg = -170.0f;
  wx.pressure_hpa = 1001.0f;
  wx.aerosol_gpm3 = 0.125f;
  wx.top_scud_frequency_pct = v4 ? 66.0f : 33.0f;
  wx.top_transition_band_m = v4 ? 77.0f : 55.0f;
  return {ig, cel, atm, rgn, wx};
}

bool events_equal(const std::vector<c::Event>& a, const std::vector<c::Event>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].index() != b[i].index()) return false;
    const bool same = std::visit(
        [&](const auto& x) { return x == std::get<std::decay_t<decltype(x)>>(b[i]); }, a[i]);
    if (!same) return false;
  }
  return true;
}

c::Version v33() { return c::Version{3, 3}; }
c::Version v40() { return c::Version{4, 0}; }

}  // namespace

TEST(CigiDecode, Golden33BigEndian) {
  const c::DecodeResult d = c::decode(kGolden33Big);
  EXPECT_EQ(d.version.major, 3);
  EXPECT_EQ(d.version.minor, 3);
  EXPECT_EQ(d.byte_order, c::ByteOrder::Big);
  expect_golden_values(d, false);
  EXPECT_TRUE(d.skipped.empty());
  EXPECT_TRUE(d.log.empty());
}

TEST(CigiDecode, Golden40LittleEndian) {
  const c::DecodeResult d = c::decode(kGolden40Little);
  EXPECT_EQ(d.version.major, 4);
  EXPECT_EQ(d.byte_order, c::ByteOrder::Little);
  expect_golden_values(d, true);
}

// The encoder writes the golden bytes exactly (reserved bytes zero).
TEST(CigiEncode, WritesTheGoldenBytes) {
  EXPECT_EQ(c::encode(v33(), c::ByteOrder::Big, golden_events(false)), kGolden33Big);
  EXPECT_EQ(c::encode(v40(), c::ByteOrder::Little, golden_events(true)), kGolden40Little);
}

// A big-endian host's datagram decodes to what a little-endian host's does.
TEST(CigiDecode, ByteSwappedDatagramDecodesTheSame) {
  for (const bool v4 : {false, true}) {
    const std::vector<c::Event> events = golden_events(v4);
    const c::Version v = v4 ? v40() : v33();
    const Bytes big = c::encode(v, c::ByteOrder::Big, events);
    const Bytes little = c::encode(v, c::ByteOrder::Little, events);
    ASSERT_EQ(big.size(), little.size());
    EXPECT_NE(big, little);
    const c::DecodeResult db = c::decode(big);
    const c::DecodeResult dl = c::decode(little);
    ASSERT_TRUE(db.ok() && dl.ok());
    EXPECT_EQ(db.byte_order, c::ByteOrder::Big);
    EXPECT_EQ(dl.byte_order, c::ByteOrder::Little);
    EXPECT_TRUE(events_equal(db.events, dl.events)) << (v4 ? "4.0" : "3.3");
    EXPECT_TRUE(events_equal(db.events, events));
  }
  // The 3.3 magic in each order, and a float field's bytes reversed.
  const Bytes little = c::encode(v33(), c::ByteOrder::Little, golden_events(false));
  EXPECT_EQ(little[6], 0x00);
  EXPECT_EQ(little[7], 0x80);
  // Weather visibility (1000 m) at byte 12 of the packet at 120: 44 7a 00 00 big-endian.
  EXPECT_EQ((Bytes{little.begin() + 132, little.begin() + 136}), (Bytes{0x00, 0x00, 0x7a, 0x44}));
}

TEST(CigiRoundTrip, EveryFieldInBothVersionsAndOrders) {
  for (const bool v4 : {false, true}) {
    for (const c::ByteOrder order : {c::ByteOrder::Little, c::ByteOrder::Big}) {
      const std::vector<c::Event> events = varied_events(v4);
      const Bytes bytes = c::encode(v4 ? v40() : v33(), order, events);
      const c::DecodeResult d = c::decode(bytes);
      ASSERT_TRUE(d.ok()) << d.error->message;
      EXPECT_EQ(d.version.major, v4 ? 4 : 3);
      EXPECT_EQ(d.byte_order, order);
      EXPECT_TRUE(events_equal(d.events, events)) << (v4 ? "4.0 " : "3.3 ") << int(order);
      // Decoding is a function of the bytes: re-encoding what was decoded gives them back.
      EXPECT_EQ(c::encode(d.version, d.byte_order, d.events), bytes);
    }
  }
}

// 3.x has one scud and one transition band: they decode into both.
TEST(CigiDecode, Cigi3WeatherFillsTopFromBottom) {
  c::WeatherControl w;
  w.scud_enable = true;
  w.top_scud_enable = true;
  w.scud_frequency_pct = 40;
  w.top_scud_frequency_pct = 40;
  w.transition_band_m = 150;
  w.top_transition_band_m = 150;
  const c::DecodeResult d = c::decode(c::encode(v33(), c::ByteOrder::Little, {c::IgControl{}, w}));
  ASSERT_TRUE(d.ok());
  const auto& got = as<c::WeatherControl>(d.events[1]);
  EXPECT_TRUE(got.top_scud_enable);
  EXPECT_EQ(got.top_scud_frequency_pct, 40.0f);
  EXPECT_EQ(got.top_transition_band_m, 150.0f);
}

TEST(CigiEncode, RefusesWhatTheVersionCannotCarry) {
  c::Encoder e3(v33(), c::ByteOrder::Little), e4(v40(), c::ByteOrder::Little);
  c::WeatherControl split;
  split.top_transition_band_m = 10;  // bottom 0
  EXPECT_THROW(e3.add(split), std::invalid_argument);
  EXPECT_NO_THROW(e4.add(split));
  c::AtmosphereControl humid;
  humid.humidity_pct = 128;
  EXPECT_THROW(e4.add(humid), std::invalid_argument);
  EXPECT_NO_THROW(e3.add(humid));
  c::WeatherControl type16;
  type16.cloud_type = 16;
  EXPECT_THROW(e3.add(type16), std::invalid_argument);
  c::CelestialControl seconds;
  seconds.seconds = 1;
  EXPECT_THROW(e3.add(seconds), std::invalid_argument);
  EXPECT_THROW(e3.add_raw(300, 8), std::invalid_argument);
  EXPECT_THROW(e4.add_raw(7, 2), std::invalid_argument);
}

// ---- skipped and refused ----------------------------------------------------

TEST(CigiDecode, UnknownPacketsAreSkippedBySize) {
  for (const bool v4 : {false, true}) {
    c::Encoder e(v4 ? v40() : v33(), c::ByteOrder::Big);
    e.add(c::IgControl{});
    e.add_raw(v4 ? 1 : 2, v4 ? 56 : 48);  // Entity Control: not decoded here
    e.add(c::AtmosphereControl{});
    e.add_raw(v4 ? 0x8123 : 201, 16);     // a user-defined packet
    e.add(c::WeatherControl{});
    const c::DecodeResult d = c::decode(e.bytes());
    ASSERT_TRUE(d.ok()) << d.error->message;
    ASSERT_EQ(d.events.size(), 3u);
    EXPECT_TRUE(std::holds_alternative<c::AtmosphereControl>(d.events[1]));
    EXPECT_TRUE(std::holds_alternative<c::WeatherControl>(d.events[2]));
    ASSERT_EQ(d.skipped.size(), 2u);
    EXPECT_EQ(d.skipped[0].packet_id, v4 ? 1u : 2u);
    EXPECT_EQ(d.skipped[0].offset, 24u);
    EXPECT_EQ(d.skipped[1].packet_id, v4 ? 0x8123u : 201u);
    EXPECT_EQ(d.skipped[1].size, 16u);
    ASSERT_EQ(d.log.size(), 1u);
    EXPECT_NE(d.log[0].find("skipped 2 packet(s)"), std::string::npos) << d.log[0];
    EXPECT_NE(d.log[0].find(v4 ? "id 33059 at byte" : "id 201 at byte"), std::string::npos) << d.log[0];
  }
}

namespace {

c::DecodeError refused(const Bytes& b) {
  const c::DecodeResult d = c::decode(b);
  EXPECT_FALSE(d.ok());
  EXPECT_TRUE(d.events.empty());
  return d.error.value_or(c::DecodeError{});
}

Bytes golden_with(size_t at, uint8_t value) {
  Bytes b = kGolden33Big;
  b[at] = value;
  return b;
}

}  // namespace

TEST(CigiDecode, RefusesSizeZero) {
  const c::DecodeError e = refused(golden_with(25, 0));  // the Celestial packet's size
  EXPECT_EQ(e.packet_id, 9u);
  EXPECT_EQ(e.offset, 24u);
  EXPECT_EQ(e.field, "packet size");
  EXPECT_NE(e.message.find("Celestial Sphere Control (packet id 9) at byte 24"), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("size 0"), std::string::npos) << e.message;
}

TEST(CigiDecode, RefusesASizePastTheEnd) {
  Bytes b = kGolden33Big;
  b.resize(b.size() - 8);  // the Weather packet now runs past the end
  const c::DecodeError e = refused(b);
  EXPECT_EQ(e.packet_id, 12u);
  EXPECT_EQ(e.offset, 120u);
  EXPECT_EQ(e.field, "packet size");
  EXPECT_NE(e.message.find("runs past the datagram's end (48 bytes left)"), std::string::npos) << e.message;
}

TEST(CigiDecode, RefusesASizeBelowThePacketsMinimum) {
  // A Weather Control that claims 40 bytes, followed by 16 more bytes.
  const c::DecodeError e = refused(golden_with(121, 40));
  EXPECT_EQ(e.packet_id, 12u);
  EXPECT_EQ(e.offset, 120u);
  EXPECT_NE(e.message.find("size 40 is not the CIGI 3 size 56 (truncated)"), std::string::npos) << e.message;
  // Below the header itself.
  const c::DecodeError h = refused(golden_with(121, 1));
  EXPECT_NE(h.message.find("below the 2-byte header"), std::string::npos) << h.message;
}

TEST(CigiDecode, RefusesAPacketOfTheOtherVersion) {
  // A 4.0-sized (72-byte) Weather Control in a 3.3 datagram.
  Bytes b = kGolden33Big;
  b[121] = 72;
  b.resize(b.size() + 16, 0);
  const c::DecodeError e = refused(b);
  EXPECT_NE(e.message.find("size 72 is not the CIGI 3 size 56 (a packet of another CIGI version?)"),
            std::string::npos)
      << e.message;
  // A CIGI 3.0/3.1 IG Control (16 bytes).
  c::Encoder old(v33(), c::ByteOrder::Big);
  old.add_raw(1, 16);
  Bytes o = old.bytes();
  o[2] = 3;
  o[6] = 0x80;
  const c::DecodeError e16 = refused(o);
  EXPECT_NE(e16.message.find("3.0/3.1 IG Control"), std::string::npos) << e16.message;
  // An IG Control of major version 2; a 4.0 framing with major version 3.
  const c::DecodeError v2 = refused(golden_with(2, 2));
  EXPECT_EQ(v2.field, "major version");
  Bytes f = kGolden40Little;
  f[4] = 3;
  EXPECT_EQ(refused(f).field, "major version");
}

TEST(CigiDecode, RefusesABadByteSwapMagic) {
  const c::DecodeError e = refused(golden_with(6, 0x12));
  EXPECT_EQ(e.field, "byte-swap magic");
  EXPECT_EQ(e.offset, 0u);
  EXPECT_NE(e.message.find("0x12 0x00"), std::string::npos) << e.message;
  // A second IG Control in the other byte order.
  Bytes b = kGolden33Big;
  const Bytes ig = c::encode(v33(), c::ByteOrder::Little, {c::IgControl{}});
  b.insert(b.end(), ig.begin(), ig.end());
  EXPECT_NE(refused(b).message.find("byte order changed"), std::string::npos);
}

TEST(CigiDecode, RefusesAMessageNotStartingWithIgControl) {
  const Bytes b = c::encode(v33(), c::ByteOrder::Little, {c::AtmosphereControl{}, c::IgControl{}});
  const c::DecodeError e = refused(b);
  EXPECT_EQ(e.field, "IG Control");
  EXPECT_NE(e.message.find("the first packet must be an IG Control"), std::string::npos) << e.message;
  EXPECT_EQ(refused({}).field, "datagram");
  const c::DecodeError one = refused({0x01});  // too short to say its version
  EXPECT_EQ(one.field, "IG Control");
  EXPECT_NE(one.message.find("CIGI: packet at byte 0: field 'IG Control'"), std::string::npos) << one.message;
  EXPECT_NE(one.message.find("the 1-byte datagram starts 0x01"), std::string::npos) << one.message;
  // A CIGI 2 IG Control (id 1, 16 bytes, version 2).
  const c::DecodeError v2 = refused({0x01, 0x10, 0x02, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  EXPECT_NE(v2.message.find("version 2; only CIGI 3 (3.2, 3.3) and 4.0 are decoded"), std::string::npos)
      << v2.message;
}

TEST(CigiDecode, RefusesNonFiniteNumbers) {
  Bytes b = kGolden33Big;
  // Weather visibility range (packet at 120, field at +12) := NaN.
  b[132] = 0x7f;
  b[133] = 0xc0;
  const c::DecodeError e = refused(b);
  EXPECT_EQ(e.packet_id, 12u);
  EXPECT_EQ(e.offset, 120u);
  EXPECT_EQ(e.field, "visibility range");
  // Region latitude := +Inf.
  Bytes r = kGolden33Big;
  const uint8_t inf[8] = {0x7f, 0xf0, 0, 0, 0, 0, 0, 0};
  std::memcpy(&r[72 + 8], inf, 8);
  EXPECT_EQ(refused(r).field, "latitude");
}

// Every prefix of a valid datagram is refused or, at a packet boundary,
// decodes that many packets; nothing reads past the prefix (ASan build).
TEST(CigiDecode, EveryTruncationIsHandled) {
  for (const Bytes* golden : {&kGolden33Big, &kGolden40Little}) {
    size_t boundaries = 0;
    for (size_t n = 1; n < golden->size(); ++n) {
      const Bytes prefix(golden->begin(), golden->begin() + n);
      const c::DecodeResult d = c::decode(prefix);
      if (d.ok()) {
        ++boundaries;
        EXPECT_FALSE(d.events.empty());
      } else {
        EXPECT_TRUE(d.events.empty());
        EXPECT_FALSE(d.error->message.empty());
      }
    }
    EXPECT_EQ(boundaries, 4u);  // after the IG, Celestial, Atmosphere and Region packets
  }
}

// Any single byte changed: decoded or refused, never anything else.
TEST(CigiDecode, EverySingleByteChangeIsHandled) {
  for (const Bytes* golden : {&kGolden33Big, &kGolden40Little}) {
    for (size_t i = 0; i < golden->size(); ++i) {
      for (const uint8_t v : {0x00, 0x01, 0x7f, 0x80, 0xff}) {
        Bytes b = *golden;
        b[i] = v;
        const c::DecodeResult d = c::decode(b);
        EXPECT_EQ(d.ok(), !d.error.has_value());
        if (!d.ok()) {
          EXPECT_TRUE(d.events.empty());
        }
      }
    }
  }
}
