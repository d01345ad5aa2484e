// make_cigi_seeds.cpp — writes the CIGI fuzz target's seed corpus
// (fuzz/corpus/cigi/): valid datagrams of CIGI 3.3 and 4.0 in both byte
// orders with every environment packet, skipped packets, a clouds-and-fog
// message and the IG's Start of Frame, so mutations start from real layouts.
// Run once by hand:
//   build-fuzz/fuzz/fuzz_make_cigi_seeds fuzz/corpus/cigi
#include <string>
#include <vector>

#include "atmo/cigi.h"
#include "seed_writer.h"

namespace c = atmo::cigi;

namespace {

void write(const std::string& path, const std::vector<uint8_t>& bytes) {
  atmo_fuzz::write_seed(path, std::string(bytes.begin(), bytes.end()));
}

std::vector<c::Event> everything(bool v4) {
  c::IgControl ig;
  ig.minor_version = v4 ? 0 : 3;
  ig.timestamp_valid = true;
  ig.host_frame_number = 100;
  ig.timestamp_ticks = 123456;
  c::CelestialControl cel;
  cel.hour = 14;
  cel.minute = 30;
  cel.date_mmddyyyy = 6212024;
  cel.ephemeris_enable = cel.sun_enable = cel.moon_enable = cel.star_enable = cel.date_time_valid = true;
  cel.star_intensity_pct = 50;
  c::AtmosphereControl atm;
  atm.visibility_m = 8000;
  c::RegionControl rgn;
  rgn.region_id = 3;
  rgn.state = c::kRegionActive;
  rgn.latitude_deg = 47.5;
  rgn.longitude_deg = 8.5;
  rgn.size_x_m = rgn.size_y_m = 10000;
  c::WeatherControl rain;
  rain.layer_id = c::kLayerRain;
  rain.scope = c::kScopeRegional;
  rain.entity_region_id = 3;
  rain.weather_enable = true;
  rain.visibility_m = 3000;
  return {ig, cel, atm, rgn, rain};
}

std::vector<c::Event> clouds_and_fog() {
  c::IgControl ig;
  std::vector<c::Event> e{ig};
  const float base[4] = {400, 1200, 3000, 9000}, thick[4] = {150, 1300, 800, 500};
  const uint8_t type[4] = {c::kCloudNone, c::kCumulus, c::kStratus, c::kCirrus};
  for (uint8_t layer = 0; layer < 4; ++layer) {
    c::WeatherControl w;
    w.layer_id = layer;
    w.weather_enable = true;
    w.cloud_type = type[layer];
    w.coverage_pct = 50;
    w.visibility_m = layer == 0 ? 300 : 100;
    w.base_elevation_m = base[layer];
    w.thickness_m = thick[layer];
    e.push_back(w);
  }
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = atmo_fuzz::seed_dir(argc, argv);
  const c::Version v33{3, 3}, v40{4, 0};
  write(dir + "/v33_little_all_packets", c::encode(v33, c::ByteOrder::Little, everything(false)));
  write(dir + "/v33_big_all_packets", c::encode(v33, c::ByteOrder::Big, everything(false)));
  write(dir + "/v40_little_all_packets", c::encode(v40, c::ByteOrder::Little, everything(true)));
  write(dir + "/v40_big_all_packets", c::encode(v40, c::ByteOrder::Big, everything(true)));
  write(dir + "/v33_clouds_and_fog", c::encode(v33, c::ByteOrder::Little, clouds_and_fog()));
  write(dir + "/v40_clouds_and_fog", c::encode(v40, c::ByteOrder::Big, clouds_and_fog()));
  {  // packets the decoder skips by their size
    c::Encoder e3(v33, c::ByteOrder::Big);
    e3.add(c::IgControl{}).add_raw(2, 48).add(c::AtmosphereControl{}).add_raw(201, 16);
    write(dir + "/v33_skipped_packets", e3.bytes());
    c::Encoder e4(v40, c::ByteOrder::Little);
    e4.add(c::IgControl{}).add_raw(1, 56).add(c::AtmosphereControl{}).add_raw(0x8000, 16);
    write(dir + "/v40_skipped_packets", e4.bytes());
  }
  {  // the IG's answer (decode_ig_message): a Start of Frame, alone and with a HAT/HOT Response after it
    c::StartOfFrame sof;
    sof.timestamp_valid = true;
    sof.ig_frame_number = 41;
    sof.last_host_frame_number = 100;
    write(dir + "/v33_sof_big", c::encode_start_of_frame(sof, c::ByteOrder::Big));
    std::vector<uint8_t> with_response = c::encode_start_of_frame(sof, c::ByteOrder::Little);
    with_response.insert(with_response.end(), {102, 16});
    with_response.resize(with_response.size() + 14, 0);
    write(dir + "/v33_sof_little_and_response", with_response);
  }
  return 0;
}
