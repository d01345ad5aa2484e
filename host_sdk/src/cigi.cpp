// cigi.cpp — CIGI 3.3 / 4.0 environment packets: decoder, encoder, the
// accumulated environment and its mapping onto the plugin (cigi.h).
//
// Byte layouts, offset from the packet's first byte (docs/CIGI.md has the
// same table with the sources):
//
// CIGI 3.x — header: id u8 @0, size u8 @1. Sources: Boeing CCL 3.3
// (Hadron/cigi-ccl source/Cigi*V3*.cpp Pack/Unpack) and Wireshark
// epan/dissectors/packet-cigi.c (cigi3_add_*, cigi3_3_add_ig_control and the
// hf_ bit masks) agree on every field read here.
//   IG Control (1, 24): major u8 @2, database i8 @3, @4: mode 0x03, timestamp
//     valid 0x04, smoothing 0x08, minor 0xF0; byte-swap magic u16 @6; host
//     frame u32 @8; timestamp u32 @12 (10 µs ticks); last IG frame u32 @16.
//   Celestial (9, 16): hour @2, minute @3, @4: ephemeris 0x01, sun 0x02,
//     moon 0x04, star 0x08, date/time valid 0x10; date u32 @8 (MMDDYYYY);
//     star intensity f32 @12 (%).
//   Atmosphere (10, 32): model enable @2 bit 0; humidity u8 @3 (%); f32 air
//     temperature @4 (°C), visibility @8 (m), horizontal wind @12, vertical
//     wind @16 (m/s), direction @20 (deg), pressure @24 (mb).
//   Region (11, 48): id u16 @2; @4: state 0x03, merge weather 0x04, aerosol
//     0x08, maritime 0x10, terrestrial 0x20; f64 lat @8, lon @16 (deg); f32
//     size x @24, size y @28, corner radius @32 (m), rotation @36 (deg),
//     transition perimeter @40 (m).
//   Weather (12, 56): entity/region id u16 @2; layer u8 @4; humidity u8 @5;
//     @6: weather 0x01, scud 0x02, random winds 0x04, random lightning 0x08,
//     cloud type 0xF0; @7: scope 0x03, severity 0x1C; f32 air temperature @8,
//     visibility @12, scud frequency @16, coverage @20, base elevation @24,
//     thickness @28, transition band @32, horizontal wind @36, vertical wind
//     @40, wind direction @44, pressure @48, aerosol @52 (g/m^3).
//   Start of Frame (101, 24; IG to host): major u8 @2, database i8 @3, IG
//     status u8 @4, @5: IG mode 0x03, timestamp valid 0x04, Earth reference
//     model 0x08, minor 0xF0; byte-swap magic u16 @6; IG frame u32 @8;
//     timestamp u32 @12; last host frame u32 @16; reserved @20. Sources: CCL
//     3.3 source/CigiSOFV3_2.cpp and Rinchi::CIGIPP::StartOfFrame (pack
//     format 'CCCcCCSIIII'); Wireshark's hf_cigi3_2_start_of_frame_* fields
//     come in the same order.
//
// CIGI 4.0 — header: size u16 @0, id u16 @2. Source: CCL 4.0.2
// (captainflasmr/cigi-ccl_4_0 source/Cigi*V4.cpp); the IG Control and the
// byte-order rule also from a Wireshark fork with CIGI 4 (looping40/wireshark
// packet-cigi.c, cigi4_add_tree / cigi4_add_ig_control). The environment
// packets' 4.0 layouts have that one source (CCL 4.0): not checked against
// the SISO-STD-013-2014 text.
//   IG Control (0, 24): major u8 @4, database i8 @5, entity substitution @6
//     bit 0, @7: mode 0x03, timestamp valid 0x04, smoothing 0x08, minor 0xF0;
//     host frame u32 @8; last IG frame u32 @12; timestamp u32 @16.
//   Celestial (8, 24): @4 flags as 3.x; hour @6, minute @7; seconds f32 @8;
//     date u32 @12; star intensity f32 @16.
//   Atmosphere (9, 32): @4: humidity 0x7F, model enable 0x80; f32 air
//     temperature @8, visibility @12, horizontal wind @16, vertical wind @20,
//     direction @24, pressure @28.
//   Region (10, 48): @4 flags as 3.x; id u16 @6; then as 3.x from @8.
//   Weather (11, 72): layer @4, humidity @5, @6 as 3.x (scud = bottom scud),
//     @7: scope 0x03, severity 0x1C, top scud 0x20; entity/region id u16 @8;
//     f32 air temperature @12, visibility @16, bottom scud frequency @20,
//     coverage @24, base elevation @28, thickness @32, bottom transition @36,
//     horizontal wind @40, vertical wind @44, wind direction @48, pressure
//     @52, aerosol @56, top scud frequency @60, top transition @64.
#include "atmo/cigi.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace atmo::cigi {
namespace {

constexpr uint32_t kNoPacketId = 0xFFFFFFFFu;

// Fixed-size reads from one packet whose bounds the caller has checked.
class Reader {
 public:
  Reader(const uint8_t* p, ByteOrder order) : p_(p), order_(order) {}
  uint8_t u8(size_t at) const { return p_[at]; }
  uint16_t u16(size_t at) const {
    return order_ == ByteOrder::Big ? uint16_t(p_[at] << 8 | p_[at + 1]) : uint16_t(p_[at + 1] << 8 | p_[at]);
  }
  uint32_t u32(size_t at) const {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(p_[at + (order_ == ByteOrder::Big ? 3 - i : i)]) << (8 * i);
    return v;
  }
  uint64_t u64(size_t at) const {
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(p_[at + (order_ == ByteOrder::Big ? 7 - i : i)]) << (8 * i);
    return v;
  }
  float f32(size_t at) const {
    const uint32_t bits = u32(at);
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
  }
  double f64(size_t at) const {
    const uint64_t bits = u64(at);
    double d;
    std::memcpy(&d, &bits, sizeof d);
    return d;
  }

 private:
  const uint8_t* p_;
  ByteOrder order_;
};

class Writer {
 public:
  Writer(std::vector<uint8_t>& out, size_t start, ByteOrder order) : out_(out), start_(start), order_(order) {}
  void u8(size_t at, uint8_t v) { out_[start_ + at] = v; }
  void u16(size_t at, uint16_t v) { put(at, v, 2); }
  void u32(size_t at, uint32_t v) { put(at, v, 4); }
  void f32(size_t at, float f) {
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    put(at, bits, 4);
  }
  void f64(size_t at, double d) {
    uint64_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    put(at, bits, 8);
  }

 private:
  void put(size_t at, uint64_t v, int n) {
    for (int i = 0; i < n; ++i)
      out_[start_ + at + size_t(order_ == ByteOrder::Big ? n - 1 - i : i)] = uint8_t(v >> (8 * i));
  }
  std::vector<uint8_t>& out_;
  size_t start_;
  ByteOrder order_;
};

std::string id_text(uint32_t id) {
  if (id == kNoPacketId) return "packet";
  return "packet id " + std::to_string(id);
}

DecodeError make_error(uint8_t major, uint32_t id, size_t offset, std::string field, const std::string& what) {
  DecodeError e;
  e.packet_id = id;
  e.offset = offset;
  e.field = std::move(field);
  const char* name = id == kNoPacketId || major == 0 ? "" : packet_name(major, id);
  std::ostringstream s;
  s << "CIGI" << (major ? " " + std::to_string(major) : std::string()) << ": " << (*name ? std::string(name) + " (" + id_text(id) + ")" : id_text(id))
    << " at byte " << offset << ": field '" << e.field << "': " << what;
  e.message = s.str();
  return e;
}

// A float field that is NaN or infinite is refused: it would poison the
// accumulated state and every mapped value after it.
struct FiniteCheck {
  const char* field = nullptr;
  void operator()(const char* name, double v) {
    if (!field && !std::isfinite(v)) field = name;
  }
};

uint8_t bits(uint8_t byte, uint8_t mask, int shift) { return uint8_t((byte & mask) >> shift); }

// ---- decoding one known packet (size already checked) ----------------------

IgControl read_ig_control(const Reader& r, uint8_t major) {
  IgControl p;
  if (major == 3) {
    p.database_id = int8_t(r.u8(3));
    const uint8_t f = r.u8(4);
    p.ig_mode = bits(f, 0x03, 0);
    p.timestamp_valid = f & 0x04;
    p.smoothing_enable = f & 0x08;
    p.minor_version = bits(f, 0xF0, 4);
    p.host_frame_number = r.u32(8);
    p.timestamp_ticks = r.u32(12);
    p.last_ig_frame_number = r.u32(16);
  } else {
    p.database_id = int8_t(r.u8(5));
    p.entity_substitution_enable = r.u8(6) & 0x01;
    const uint8_t f = r.u8(7);
    p.ig_mode = bits(f, 0x03, 0);
    p.timestamp_valid = f & 0x04;
    p.smoothing_enable = f & 0x08;
    p.minor_version = bits(f, 0xF0, 4);
    p.host_frame_number = r.u32(8);
    p.last_ig_frame_number = r.u32(12);
    p.timestamp_ticks = r.u32(16);
  }
  return p;
}

void read_celestial_flags(CelestialControl& p, uint8_t f) {
  p.ephemeris_enable = f & 0x01;
  p.sun_enable = f & 0x02;
  p.moon_enable = f & 0x04;
  p.star_enable = f & 0x08;
  p.date_time_valid = f & 0x10;
}

CelestialControl read_celestial(const Reader& r, uint8_t major, FiniteCheck& fc) {
  CelestialControl p;
  if (major == 3) {
    p.hour = r.u8(2);
    p.minute = r.u8(3);
    read_celestial_flags(p, r.u8(4));
    p.date_mmddyyyy = r.u32(8);
    p.star_intensity_pct = r.f32(12);
  } else {
    read_celestial_flags(p, r.u8(4));
    p.hour = r.u8(6);
    p.minute = r.u8(7);
    p.seconds = r.f32(8);
    p.date_mmddyyyy = r.u32(12);
    p.star_intensity_pct = r.f32(16);
  }
  fc("seconds", p.seconds);
  fc("star field intensity", p.star_intensity_pct);
  return p;
}

AtmosphereControl read_atmosphere(const Reader& r, uint8_t major, FiniteCheck& fc) {
  AtmosphereControl p;
  size_t at;
  if (major == 3) {
    p.model_enable = r.u8(2) & 0x01;
    p.humidity_pct = r.u8(3);
    at = 4;
  } else {
    const uint8_t f = r.u8(4);
    p.humidity_pct = f & 0x7F;
    p.model_enable = f & 0x80;
    at = 8;
  }
  p.air_temperature_c = r.f32(at);
  p.visibility_m = r.f32(at + 4);
  p.horizontal_wind_mps = r.f32(at + 8);
  p.vertical_wind_mps = r.f32(at + 12);
  p.wind_direction_deg = r.f32(at + 16);
  p.pressure_hpa = r.f32(at + 20);
  fc("air temperature", p.air_temperature_c);
  fc("visibility range", p.visibility_m);
  fc("horizontal wind speed", p.horizontal_wind_mps);
  fc("vertical wind speed", p.vertical_wind_mps);
  fc("wind direction", p.wind_direction_deg);
  fc("barometric pressure", p.pressure_hpa);
  return p;
}

RegionControl read_region(const Reader& r, uint8_t major, FiniteCheck& fc) {
  RegionControl p;
  p.region_id = major == 3 ? r.u16(2) : r.u16(6);
  const uint8_t f = r.u8(4);
  p.state = bits(f, 0x03, 0);
  p.merge_weather = f & 0x04;
  p.merge_aerosol = f & 0x08;
  p.merge_maritime = f & 0x10;
  p.merge_terrestrial = f & 0x20;
  p.latitude_deg = r.f64(8);
  p.longitude_deg = r.f64(16);
  p.size_x_m = r.f32(24);
  p.size_y_m = r.f32(28);
  p.corner_radius_m = r.f32(32);
  p.rotation_deg = r.f32(36);
  p.transition_perimeter_m = r.f32(40);
  fc("latitude", p.latitude_deg);
  fc("longitude", p.longitude_deg);
  fc("size x", p.size_x_m);
  fc("size y", p.size_y_m);
  fc("corner radius", p.corner_radius_m);
  fc("rotation", p.rotation_deg);
  fc("transition perimeter", p.transition_perimeter_m);
  return p;
}

WeatherControl read_weather(const Reader& r, uint8_t major, FiniteCheck& fc) {
  WeatherControl p;
  // 3.x: id u16 @2, then layer @4; 4.0: layer @4, id u16 @8. Bytes 4-7 alike.
  p.layer_id = r.u8(4);
  p.humidity_pct = r.u8(5);
  const uint8_t f = r.u8(6);
  p.weather_enable = f & 0x01;
  p.scud_enable = f & 0x02;
  p.random_winds_enable = f & 0x04;
  p.random_lightning_enable = f & 0x08;
  p.cloud_type = bits(f, 0xF0, 4);
  const uint8_t g = r.u8(7);
  p.scope = bits(g, 0x03, 0);
  p.severity = bits(g, 0x1C, 2);
  size_t at;
  if (major == 3) {
    p.entity_region_id = r.u16(2);
    p.top_scud_enable = p.scud_enable;
    at = 8;
  } else {
    p.top_scud_enable = g & 0x20;
    p.entity_region_id = r.u16(8);
    at = 12;
  }
  p.air_temperature_c = r.f32(at);
  p.visibility_m = r.f32(at + 4);
  p.scud_frequency_pct = r.f32(at + 8);
  p.coverage_pct = r.f32(at + 12);
  p.base_elevation_m = r.f32(at + 16);
  p.thickness_m = r.f32(at + 20);
  p.transition_band_m = r.f32(at + 24);
  p.horizontal_wind_mps = r.f32(at + 28);
  p.vertical_wind_mps = r.f32(at + 32);
  p.wind_direction_deg = r.f32(at + 36);
  p.pressure_hpa = r.f32(at + 40);
  p.aerosol_gpm3 = r.f32(at + 44);
  if (major == 3) {
    p.top_scud_frequency_pct = p.scud_frequency_pct;
    p.top_transition_band_m = p.transition_band_m;
  } else {
    p.top_scud_frequency_pct = r.f32(60);
    p.top_transition_band_m = r.f32(64);
  }
  fc("air temperature", p.air_temperature_c);
  fc("visibility range", p.visibility_m);
  fc("scud frequency", p.scud_frequency_pct);
  fc("coverage", p.coverage_pct);
  fc("base elevation", p.base_elevation_m);
  fc("thickness", p.thickness_m);
  fc("transition band", p.transition_band_m);
  fc("horizontal wind speed", p.horizontal_wind_mps);
  fc("vertical wind speed", p.vertical_wind_mps);
  fc("wind direction", p.wind_direction_deg);
  fc("barometric pressure", p.pressure_hpa);
  fc("aerosol concentration", p.aerosol_gpm3);
  fc("top scud frequency", p.top_scud_frequency_pct);
  fc("top transition band", p.top_transition_band_m);
  return p;
}

// The expected size of a packet decoded here, 0 for any other id.
size_t known_size(uint8_t major, uint32_t id) {
  if (major == 3) {
    switch (id) {
      case v3::kIgControlId: return v3::kIgControlSize;
      case v3::kCelestialId: return v3::kCelestialSize;
      case v3::kAtmosphereId: return v3::kAtmosphereSize;
      case v3::kRegionId: return v3::kRegionSize;
      case v3::kWeatherId: return v3::kWeatherSize;
    }
  } else {
    switch (id) {
      case v4::kIgControlId: return v4::kIgControlSize;
      case v4::kCelestialId: return v4::kCelestialSize;
      case v4::kAtmosphereId: return v4::kAtmosphereSize;
      case v4::kRegionId: return v4::kRegionSize;
      case v4::kWeatherId: return v4::kWeatherSize;
    }
  }
  return 0;
}

// Which kind of packet an id is, independent of the version.
enum class Kind { Other, Ig, Celestial, Atmosphere, Region, Weather };
Kind kind_of(uint8_t major, uint32_t id) {
  if (major == 3) {
    switch (id) {
      case v3::kIgControlId: return Kind::Ig;
      case v3::kCelestialId: return Kind::Celestial;
      case v3::kAtmosphereId: return Kind::Atmosphere;
      case v3::kRegionId: return Kind::Region;
      case v3::kWeatherId: return Kind::Weather;
    }
  } else {
    switch (id) {
      case v4::kIgControlId: return Kind::Ig;
      case v4::kCelestialId: return Kind::Celestial;
      case v4::kAtmosphereId: return Kind::Atmosphere;
      case v4::kRegionId: return Kind::Region;
      case v4::kWeatherId: return Kind::Weather;
    }
  }
  return Kind::Other;
}

std::string hex2(uint8_t b) {
  static const char* d = "0123456789abcdef";
  return std::string("0x") + d[b >> 4] + d[b & 15];
}

}  // namespace

// CIGI 3's byte-swap magic at bytes 6-7 of an IG Control or a Start of Frame: the sender writes 0x8000 in its
// own byte order. Nothing for neither order.
std::optional<ByteOrder> swap_magic_order(const uint8_t* p) {
  if (p[6] == 0x80 && p[7] == 0x00) return ByteOrder::Big;
  if (p[6] == 0x00 && p[7] == 0x80) return ByteOrder::Little;
  return std::nullopt;
}
DecodeError bad_swap_magic(uint32_t id, size_t offset, const uint8_t* p) {
  return make_error(3, id, offset, "byte-swap magic",
                    "bytes " + hex2(p[6]) + " " + hex2(p[7]) +
                        " are neither 0x80 0x00 (big-endian) nor 0x00 0x80 (little-endian)");
}

// A CIGI 4.0 message's first packet, `size_field` bytes with id `id`: its 16-bit size comes first, and "a zero
// in the leftmost byte" means big-endian (CCL 4.0 CigiIGCtrlV4::Unpack; the Wireshark fork's cigi4_add_tree).
// The id's two bytes are the same in either order for the ids it is used with (0 and 0xFFFF).
std::optional<ByteOrder> v4_first_packet_order(const uint8_t* data, size_t size, uint16_t size_field, uint16_t id) {
  if (size < 4 || data[2] != uint8_t(id >> 8) || data[3] != uint8_t(id)) return std::nullopt;
  if (data[0] == 0 && data[1] == size_field) return ByteOrder::Big;
  if (data[0] == size_field && data[1] == 0) return ByteOrder::Little;
  return std::nullopt;
}

// The header of the packet at `offset`: its id and size, checked against the
// datagram (a header that fits, a size of at least the header that does not run
// past the end). CIGI 3: id and size bytes; 4.0: 16-bit size then id in `order`.
struct PacketHeader {
  uint32_t id = kNoPacketId;
  size_t size = 0;
  std::optional<DecodeError> error;
};
PacketHeader read_packet_header(const uint8_t* data, size_t size, size_t offset, uint8_t major, ByteOrder order) {
  PacketHeader h;
  const size_t header = major == 3 ? 2 : 4;
  const size_t left = size - offset;
  if (left < header) {
    h.error = make_error(major, kNoPacketId, offset, "packet header",
                         std::to_string(left) + " bytes left, a packet header needs " + std::to_string(header));
    return h;
  }
  const uint8_t* p = data + offset;
  if (major == 3) {
    h.id = p[0];
    h.size = p[1];
  } else {
    const Reader r(p, order);
    h.size = r.u16(0);
    h.id = r.u16(2);
  }
  if (h.size == 0) {
    h.error = make_error(major, h.id, offset, "packet size", "size 0");
  } else if (h.size < header) {
    h.error = make_error(major, h.id, offset, "packet size",
                         "size " + std::to_string(h.size) + " is below the " + std::to_string(header) + "-byte header");
  } else if (h.size > left) {
    h.error = make_error(major, h.id, offset, "packet size",
                         "size " + std::to_string(h.size) + " runs past the datagram's end (" + std::to_string(left) +
                             " bytes left)");
  }
  return h;
}

const char* packet_name(uint8_t major, uint32_t id) {
  if ((major == 3 && id == v3::kStartOfFrameId) || (major == 4 && id == v4::kStartOfFrameId)) return "Start of Frame";
  switch (kind_of(major, id)) {
    case Kind::Ig: return "IG Control";
    case Kind::Celestial: return "Celestial Sphere Control";
    case Kind::Atmosphere: return "Atmosphere Control";
    case Kind::Region: return "Environmental Region Control";
    case Kind::Weather: return "Weather Control";
    case Kind::Other: break;
  }
  return "";
}

bool operator==(const IgControl& a, const IgControl& b) {
  return std::tie(a.minor_version, a.database_id, a.ig_mode, a.timestamp_valid, a.smoothing_enable,
                  a.entity_substitution_enable, a.host_frame_number, a.timestamp_ticks, a.last_ig_frame_number) ==
         std::tie(b.minor_version, b.database_id, b.ig_mode, b.timestamp_valid, b.smoothing_enable,
                  b.entity_substitution_enable, b.host_frame_number, b.timestamp_ticks, b.last_ig_frame_number);
}
bool operator==(const CelestialControl& a, const CelestialControl& b) {
  return std::tie(a.hour, a.minute, a.seconds, a.date_mmddyyyy, a.ephemeris_enable, a.sun_enable, a.moon_enable,
                  a.star_enable, a.date_time_valid, a.star_intensity_pct) ==
         std::tie(b.hour, b.minute, b.seconds, b.date_mmddyyyy, b.ephemeris_enable, b.sun_enable, b.moon_enable,
                  b.star_enable, b.date_time_valid, b.star_intensity_pct);
}
bool operator==(const AtmosphereControl& a, const AtmosphereControl& b) {
  return std::tie(a.model_enable, a.humidity_pct, a.air_temperature_c, a.visibility_m, a.horizontal_wind_mps,
                  a.vertical_wind_mps, a.wind_direction_deg, a.pressure_hpa) ==
         std::tie(b.model_enable, b.humidity_pct, b.air_temperature_c, b.visibility_m, b.horizontal_wind_mps,
                  b.vertical_wind_mps, b.wind_direction_deg, b.pressure_hpa);
}
bool operator==(const RegionControl& a, const RegionControl& b) {
  return std::tie(a.region_id, a.state, a.merge_weather, a.merge_aerosol, a.merge_maritime, a.merge_terrestrial,
                  a.latitude_deg, a.longitude_deg, a.size_x_m, a.size_y_m, a.corner_radius_m, a.rotation_deg,
                  a.transition_perimeter_m) ==
         std::tie(b.region_id, b.state, b.merge_weather, b.merge_aerosol, b.merge_maritime, b.merge_terrestrial,
                  b.latitude_deg, b.longitude_deg, b.size_x_m, b.size_y_m, b.corner_radius_m, b.rotation_deg,
                  b.transition_perimeter_m);
}
bool operator==(const WeatherControl& a, const WeatherControl& b) {
  return std::tie(a.entity_region_id, a.layer_id, a.humidity_pct, a.weather_enable, a.scud_enable,
                  a.top_scud_enable, a.random_winds_enable, a.random_lightning_enable, a.cloud_type, a.scope,
                  a.severity, a.air_temperature_c, a.visibility_m, a.scud_frequency_pct, a.coverage_pct,
                  a.base_elevation_m, a.thickness_m, a.transition_band_m, a.horizontal_wind_mps,
                  a.vertical_wind_mps, a.wind_direction_deg, a.pressure_hpa, a.aerosol_gpm3,
                  a.top_scud_frequency_pct, a.top_transition_band_m) ==
         std::tie(b.entity_region_id, b.layer_id, b.humidity_pct, b.weather_enable, b.scud_enable,
                  b.top_scud_enable, b.random_winds_enable, b.random_lightning_enable, b.cloud_type, b.scope,
                  b.severity, b.air_temperature_c, b.visibility_m, b.scud_frequency_pct, b.coverage_pct,
                  b.base_elevation_m, b.thickness_m, b.transition_band_m, b.horizontal_wind_mps,
                  b.vertical_wind_mps, b.wind_direction_deg, b.pressure_hpa, b.aerosol_gpm3,
                  b.top_scud_frequency_pct, b.top_transition_band_m);
}

// ---- decode ------------------------------------------------------------------

DecodeResult decode(const uint8_t* data, size_t size) {
  DecodeResult out;
  auto refuse = [&out](DecodeError e) {
    out.error = std::move(e);
    out.events.clear();
    out.skipped.clear();
    out.log.clear();
    return out;
  };
  // major 0 in an error: the version is not known yet.
  if (data == nullptr || size == 0) return refuse(make_error(0, kNoPacketId, 0, "datagram", "empty datagram"));

  // The version and byte order come from the first packet, which must be an
  // IG Control: CIGI 3.x has id 1 in byte 0 and the major version in byte 2;
  // CIGI 4.0 has size 24 in bytes 0-1 (little- or big-endian), id 0 in bytes
  // 2-3 and the major version in byte 4.
  uint8_t major = 0;
  if (size >= 3 && data[0] == v3::kIgControlId) {
    major = 3;
    out.version.major = 3;
    if (data[2] != 3) {
      return refuse(make_error(3, v3::kIgControlId, 0, "major version",
                               "version " + std::to_string(data[2]) + "; only CIGI 3 (3.2, 3.3) and 4.0 are decoded"));
    }
  } else if (const auto order = v4_first_packet_order(data, size, v4::kIgControlSize, v4::kIgControlId);
             order && size >= 5) {
    major = 4;
    out.version.major = 4;
    out.byte_order = *order;
    if (data[4] != 4) {
      return refuse(make_error(4, v4::kIgControlId, 0, "major version",
                               "version " + std::to_string(data[4]) + "; only CIGI 3 (3.2, 3.3) and 4.0 are decoded"));
    }
  } else {
    std::ostringstream s;
    s << "the first packet must be an IG Control (CIGI 3: id 1, version 3; CIGI 4.0: size 24, id 0, version 4); the "
      << size << "-byte datagram starts";
    for (size_t i = 0; i < std::min<size_t>(size, 5); ++i) s << ' ' << hex2(data[i]);
    return refuse(make_error(0, kNoPacketId, 0, "IG Control", s.str()));
  }

  bool order_known = major == 4;
  size_t offset = 0;
  while (offset < size) {
    const uint8_t* p = data + offset;
    const PacketHeader h = read_packet_header(data, size, offset, major, out.byte_order);
    if (h.error) return refuse(*h.error);
    const uint32_t id = h.id;
    const size_t psize = h.size;
    const Kind kind = kind_of(major, id);
    if (offset == 0 && kind != Kind::Ig) {
      return refuse(make_error(major, id, offset, "packet id", "the first packet must be an IG Control"));
    }
    if (kind == Kind::Other) {
      out.skipped.push_back({id, offset, psize});
      offset += psize;
      continue;
    }
    const size_t want = known_size(major, id);
    if (psize != want) {
      std::string why = "size " + std::to_string(psize) + " is not the CIGI " + std::to_string(major) + " size " +
                        std::to_string(want);
      if (major == 3 && kind == Kind::Ig && psize == 16) {
        why += " (a CIGI 3.0/3.1 IG Control: only 3.2 and 3.3, whose IG Control is 24 bytes, are decoded)";
      } else if (psize < want) {
        why += " (truncated)";
      } else {
        why += " (a packet of another CIGI version?)";
      }
      return refuse(make_error(major, id, offset, "packet size", why));
    }
    if (major == 3 && kind == Kind::Ig) {
      const std::optional<ByteOrder> magic = swap_magic_order(p);
      if (!magic) return refuse(bad_swap_magic(id, offset, p));
      const ByteOrder order = *magic;
      if (order_known && order != out.byte_order) {
        return refuse(make_error(major, id, offset, "byte-swap magic", "the byte order changed within the datagram"));
      }
      out.byte_order = order;
      order_known = true;
    }
    if (kind == Kind::Ig && p[major == 3 ? 2 : 4] != major) {
      return refuse(make_error(major, id, offset, "major version",
                               "version " + std::to_string(p[major == 3 ? 2 : 4]) + " in a CIGI " +
                                   std::to_string(major) + " datagram"));
    }
    const Reader r(p, out.byte_order);
    FiniteCheck fc;
    switch (kind) {
      case Kind::Ig: {
        IgControl ig = read_ig_control(r, major);
        if (offset == 0) out.version.minor = ig.minor_version;
        out.events.emplace_back(ig);
        break;
      }
      case Kind::Celestial: out.events.emplace_back(read_celestial(r, major, fc)); break;
      case Kind::Atmosphere: out.events.emplace_back(read_atmosphere(r, major, fc)); break;
      case Kind::Region: out.events.emplace_back(read_region(r, major, fc)); break;
      case Kind::Weather: out.events.emplace_back(read_weather(r, major, fc)); break;
      case Kind::Other: break;
    }
    if (fc.field) return refuse(make_error(major, id, offset, fc.field, "not a finite number"));
    offset += psize;
  }

  if (!out.skipped.empty()) {
    // One line per datagram, not per packet: a frame of a busy host carries
    // hundreds of entity packets.
    std::ostringstream s;
    s << "CIGI " << int(major) << ": skipped " << out.skipped.size() << " packet(s) not decoded here:";
    const size_t shown = std::min<size_t>(out.skipped.size(), 8);
    for (size_t i = 0; i < shown; ++i) {
      const SkippedPacket& k = out.skipped[i];
      s << (i ? ", " : " ") << "id " << k.packet_id << " at byte " << k.offset << " (" << k.size << " bytes)";
    }
    if (shown < out.skipped.size()) s << " and " << out.skipped.size() - shown << " more";
    out.log.push_back(s.str());
  }
  return out;
}

// ---- encode ------------------------------------------------------------------

namespace {

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("atmo::cigi::Encoder: ") + what);
}

// Writes a header and returns a Writer over the new packet's bytes.
Writer begin_packet(std::vector<uint8_t>& out, uint8_t major, ByteOrder order, uint32_t id, size_t size) {
  const size_t start = out.size();
  out.resize(start + size, 0);
  Writer w(out, start, order);
  if (major == 3) {
    w.u8(0, uint8_t(id));
    w.u8(1, uint8_t(size));
  } else {
    w.u16(0, uint16_t(size));
    w.u16(2, uint16_t(id));
  }
  return w;
}

uint8_t celestial_flags(const CelestialControl& p) {
  return uint8_t((p.ephemeris_enable ? 0x01 : 0) | (p.sun_enable ? 0x02 : 0) | (p.moon_enable ? 0x04 : 0) |
                 (p.star_enable ? 0x08 : 0) | (p.date_time_valid ? 0x10 : 0));
}

uint8_t region_flags(const RegionControl& p) {
  return uint8_t((p.state & 0x03) | (p.merge_weather ? 0x04 : 0) | (p.merge_aerosol ? 0x08 : 0) |
                 (p.merge_maritime ? 0x10 : 0) | (p.merge_terrestrial ? 0x20 : 0));
}

}  // namespace

Encoder::Encoder(Version version, ByteOrder order) : version_(version), order_(order) {
  require(version.major == 3 || version.major == 4, "major version must be 3 or 4");
}

Encoder& Encoder::add_raw(uint32_t packet_id, size_t size) {
  const size_t header = version_.major == 3 ? 2 : 4;
  require(size >= header, "a packet holds at least its header");
  require(version_.major == 3 ? packet_id <= 0xFF && size <= 0xFF : packet_id <= 0xFFFF && size <= 0xFFFF,
          "packet id or size too large for the version's header");
  begin_packet(bytes_, version_.major, order_, packet_id, size);
  return *this;
}

Encoder& Encoder::add(const Event& event) {
  const uint8_t major = version_.major;
  const bool v3x = major == 3;
  std::visit(
      [&](const auto& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, IgControl>) {
          require(p.ig_mode <= 3, "IG mode is 2 bits");
          require(p.minor_version <= 15, "minor version is 4 bits");
          require(!(v3x && p.entity_substitution_enable), "entity substitution is CIGI 4.0 only");
          Writer w = begin_packet(bytes_, major, order_, v3x ? v3::kIgControlId : v4::kIgControlId,
                                  v3x ? v3::kIgControlSize : v4::kIgControlSize);
          const uint8_t f = uint8_t(p.ig_mode | (p.timestamp_valid ? 0x04 : 0) | (p.smoothing_enable ? 0x08 : 0) |
                                    (p.minor_version << 4));
          if (v3x) {
            w.u8(2, 3);
            w.u8(3, uint8_t(p.database_id));
            w.u8(4, f);
            w.u16(6, 0x8000);  // in the message's byte order: the IG's test for swapping
            w.u32(8, p.host_frame_number);
            w.u32(12, p.timestamp_ticks);
            w.u32(16, p.last_ig_frame_number);
          } else {
            w.u8(4, 4);
            w.u8(5, uint8_t(p.database_id));
            w.u8(6, p.entity_substitution_enable ? 0x01 : 0);
            w.u8(7, f);
            w.u32(8, p.host_frame_number);
            w.u32(12, p.last_ig_frame_number);
            w.u32(16, p.timestamp_ticks);
          }
        } else if constexpr (std::is_same_v<T, CelestialControl>) {
          require(!(v3x && p.seconds != 0), "seconds are CIGI 4.0 only");
          Writer w = begin_packet(bytes_, major, order_, v3x ? v3::kCelestialId : v4::kCelestialId,
                                  v3x ? v3::kCelestialSize : v4::kCelestialSize);
          if (v3x) {
            w.u8(2, p.hour);
            w.u8(3, p.minute);
            w.u8(4, celestial_flags(p));
            w.u32(8, p.date_mmddyyyy);
            w.f32(12, p.star_intensity_pct);
          } else {
            w.u8(4, celestial_flags(p));
            w.u8(6, p.hour);
            w.u8(7, p.minute);
            w.f32(8, p.seconds);
            w.u32(12, p.date_mmddyyyy);
            w.f32(16, p.star_intensity_pct);
          }
        } else if constexpr (std::is_same_v<T, AtmosphereControl>) {
          require(v3x || p.humidity_pct <= 127, "CIGI 4.0 humidity is 7 bits (0-127)");
          Writer w = begin_packet(bytes_, major, order_, v3x ? v3::kAtmosphereId : v4::kAtmosphereId,
                                  v3x ? v3::kAtmosphereSize : v4::kAtmosphereSize);
          size_t at;
          if (v3x) {
            w.u8(2, p.model_enable ? 0x01 : 0);
            w.u8(3, p.humidity_pct);
            at = 4;
          } else {
            w.u8(4, uint8_t(p.humidity_pct | (p.model_enable ? 0x80 : 0)));
            at = 8;
          }
          w.f32(at, p.air_temperature_c);
          w.f32(at + 4, p.visibility_m);
          w.f32(at + 8, p.horizontal_wind_mps);
          w.f32(at + 12, p.vertical_wind_mps);
          w.f32(at + 16, p.wind_direction_deg);
          w.f32(at + 20, p.pressure_hpa);
        } else if constexpr (std::is_same_v<T, RegionControl>) {
          require(p.state <= 3, "region state is 2 bits");
          Writer w = begin_packet(bytes_, major, order_, v3x ? v3::kRegionId : v4::kRegionId,
                                  v3x ? v3::kRegionSize : v4::kRegionSize);
          w.u16(v3x ? 2 : 6, p.region_id);
          w.u8(4, region_flags(p));
          w.f64(8, p.latitude_deg);
          w.f64(16, p.longitude_deg);
          w.f32(24, p.size_x_m);
          w.f32(28, p.size_y_m);
          w.f32(32, p.corner_radius_m);
          w.f32(36, p.rotation_deg);
          w.f32(40, p.transition_perimeter_m);
        } else if constexpr (std::is_same_v<T, WeatherControl>) {
          require(p.cloud_type <= 15, "cloud type is 4 bits");
          require(p.scope <= 3, "scope is 2 bits");
          require(p.severity <= 7, "severity is 3 bits");
          // 3.x carries one scud and one transition band: top must equal bottom.
          require(!v3x || (p.top_scud_enable == p.scud_enable &&
                           p.top_scud_frequency_pct == p.scud_frequency_pct &&
                           p.top_transition_band_m == p.transition_band_m),
                  "CIGI 3 has one scud and one transition band: top must equal bottom");
          Writer w = begin_packet(bytes_, major, order_, v3x ? v3::kWeatherId : v4::kWeatherId,
                                  v3x ? v3::kWeatherSize : v4::kWeatherSize);
          w.u8(4, p.layer_id);
          w.u8(5, p.humidity_pct);
          w.u8(6, uint8_t((p.weather_enable ? 0x01 : 0) | (p.scud_enable ? 0x02 : 0) |
                          (p.random_winds_enable ? 0x04 : 0) | (p.random_lightning_enable ? 0x08 : 0) |
                          (p.cloud_type << 4)));
          w.u8(7, uint8_t(p.scope | (p.severity << 2) | (!v3x && p.top_scud_enable ? 0x20 : 0)));
          size_t at;
          if (v3x) {
            w.u16(2, p.entity_region_id);
            at = 8;
          } else {
            w.u16(8, p.entity_region_id);
            at = 12;
          }
          w.f32(at, p.air_temperature_c);
          w.f32(at + 4, p.visibility_m);
          w.f32(at + 8, p.scud_frequency_pct);
          w.f32(at + 12, p.coverage_pct);
          w.f32(at + 16, p.base_elevation_m);
          w.f32(at + 20, p.thickness_m);
          w.f32(at + 24, p.transition_band_m);
          w.f32(at + 28, p.horizontal_wind_mps);
          w.f32(at + 32, p.vertical_wind_mps);
          w.f32(at + 36, p.wind_direction_deg);
          w.f32(at + 40, p.pressure_hpa);
          w.f32(at + 44, p.aerosol_gpm3);
          if (!v3x) {
            w.f32(60, p.top_scud_frequency_pct);
            w.f32(64, p.top_transition_band_m);
          }
        }
      },
      event);
  return *this;
}

std::vector<uint8_t> encode(Version version, ByteOrder order, const std::vector<Event>& events) {
  Encoder e(version, order);
  for (const Event& ev : events) e.add(ev);
  return e.bytes();
}

// ---- Start of Frame (CIGI 3.2/3.3, IG to host) --------------------------------

bool operator==(const StartOfFrame& a, const StartOfFrame& b) {
  return std::tie(a.minor_version, a.database_id, a.ig_status, a.ig_mode, a.timestamp_valid,
                  a.earth_model_host_defined, a.ig_frame_number, a.timestamp_ticks, a.last_host_frame_number) ==
         std::tie(b.minor_version, b.database_id, b.ig_status, b.ig_mode, b.timestamp_valid,
                  b.earth_model_host_defined, b.ig_frame_number, b.timestamp_ticks, b.last_host_frame_number);
}

std::vector<uint8_t> encode_start_of_frame(const StartOfFrame& sof, ByteOrder order, uint8_t major_version) {
  require(major_version == 3 || major_version == 4, "major version is 3 or 4");
  require(sof.ig_mode <= 3, "IG mode is 2 bits");
  require(sof.minor_version <= 15, "minor version is 4 bits");
  const uint8_t flags = uint8_t(sof.ig_mode | (sof.timestamp_valid ? 0x04 : 0) |
                                (sof.earth_model_host_defined ? 0x08 : 0) | (sof.minor_version << 4));
  std::vector<uint8_t> out;
  if (major_version == 3) {
    Writer w = begin_packet(out, 3, order, v3::kStartOfFrameId, v3::kStartOfFrameSize);
    w.u8(2, 3);
    w.u8(3, uint8_t(sof.database_id));
    w.u8(4, sof.ig_status);
    w.u8(5, flags);
    w.u16(6, 0x8000);  // in the message's byte order: the host's test for swapping
    w.u32(8, sof.ig_frame_number);
    w.u32(12, sof.timestamp_ticks);
    w.u32(16, sof.last_host_frame_number);
    return out;  // bytes 20-23 reserved, zero
  }
  Writer w = begin_packet(out, 4, order, v4::kStartOfFrameId, v4::kStartOfFrameSize);
  w.u8(4, 4);
  w.u8(5, uint8_t(sof.database_id));
  w.u8(6, sof.ig_status);
  w.u8(7, flags);
  w.u32(8, sof.ig_frame_number);
  w.u32(12, sof.timestamp_ticks);
  w.u32(16, sof.last_host_frame_number);
  return out;  // bytes 20-21: condition flags (none raised), 22-23 reserved
}

IgMessage decode_ig_message(const uint8_t* data, size_t size) {
  IgMessage out;
  auto refuse = [&out](DecodeError e) {
    out.error = std::move(e);
    out.sof = StartOfFrame{};
    out.skipped.clear();
    return out;
  };
  if (data == nullptr || size == 0) return refuse(make_error(0, kNoPacketId, 0, "datagram", "empty datagram"));
  // CIGI 3: id 101 in byte 0, the size in byte 1. CIGI 4.0: the 16-bit size 24 first (a zero leftmost byte:
  // big-endian), then the id 0xFFFF.
  uint8_t major = 0;
  if (size >= 2 && data[0] == v3::kStartOfFrameId) {
    major = 3;
  } else if (const auto order = v4_first_packet_order(data, size, v4::kStartOfFrameSize, v4::kStartOfFrameId)) {
    major = 4;
    out.byte_order = *order;
  } else {
    std::ostringstream s;
    s << "the first packet of an IG message must be a Start of Frame (CIGI 3: id 101; CIGI 4.0: size 24, id "
         "0xFFFF); the "
      << size << "-byte datagram starts";
    for (size_t i = 0; i < std::min<size_t>(size, 5); ++i) s << ' ' << hex2(data[i]);
    return refuse(make_error(0, kNoPacketId, 0, "Start of Frame", s.str()));
  }
  out.version.major = major;
  const uint32_t id = major == 3 ? v3::kStartOfFrameId : v4::kStartOfFrameId;
  const size_t psize = major == 3 ? data[1] : v4::kStartOfFrameSize;
  if (psize != v3::kStartOfFrameSize) {
    std::string why = "size " + std::to_string(psize);
    if (psize == 16) {
      why += " is a CIGI 3.0/3.1 Start of Frame: only 3.2 and 3.3, of 24 bytes, are decoded";
    } else if (psize > size) {
      why += " runs past the datagram's end (" + std::to_string(size) + " bytes left)";
    } else {
      why += " is not the CIGI 3 size 24";
      if (psize < v3::kStartOfFrameSize) why += " (truncated)";
    }
    return refuse(make_error(3, id, 0, "packet size", why));
  }
  if (size < psize) {
    return refuse(make_error(major, id, 0, "packet size",
                             "size 24 runs past the datagram's end (" + std::to_string(size) + " bytes left)"));
  }
  const size_t version_at = major == 3 ? 2 : 4;
  if (data[version_at] != major) {
    return refuse(make_error(major, id, 0, "major version",
                             "version " + std::to_string(data[version_at]) +
                                 (major == 3 ? " in a CIGI 3 Start of Frame" : " in a CIGI 4.0 Start of Frame")));
  }
  if (major == 3) {
    const std::optional<ByteOrder> magic = swap_magic_order(data);
    if (!magic) return refuse(bad_swap_magic(id, 0, data));
    out.byte_order = *magic;
  }
  const Reader r(data, out.byte_order);
  StartOfFrame& sof = out.sof;
  sof.database_id = int8_t(r.u8(major == 3 ? 3 : 5));
  sof.ig_status = r.u8(major == 3 ? 4 : 6);
  const uint8_t f = r.u8(major == 3 ? 5 : 7);
  sof.ig_mode = bits(f, 0x03, 0);
  sof.timestamp_valid = f & 0x04;
  sof.earth_model_host_defined = f & 0x08;
  sof.minor_version = bits(f, 0xF0, 4);
  out.version.minor = sof.minor_version;
  sof.ig_frame_number = r.u32(8);
  sof.timestamp_ticks = r.u32(12);
  sof.last_host_frame_number = r.u32(16);

  // The rest of the message (HAT/HOT responses, ...): skipped by size.
  for (size_t offset = psize; offset < size;) {
    const PacketHeader h = read_packet_header(data, size, offset, major, out.byte_order);
    if (h.error) return refuse(*h.error);
    const uint32_t pid = h.id;
    const size_t n = h.size;
    if (pid == id) {
      return refuse(make_error(major, pid, offset, "packet id", "a second Start of Frame in one message"));
    }
    out.skipped.push_back({pid, offset, n});
    offset += n;
  }
  return out;
}

// ---- the accumulated environment ------------------------------------------

bool WeatherKey::operator<(const WeatherKey& o) const {
  return std::tie(scope, id, layer_id) < std::tie(o.scope, o.id, o.layer_id);
}

std::optional<double> utc_from_civil(unsigned year, unsigned month, unsigned day, unsigned hour, unsigned minute,
                                     double seconds) {
  static const unsigned kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  if (year < 1 || year > 9999 || month < 1 || month > 12) return std::nullopt;
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  const unsigned dim = kDays[month - 1] + (month == 2 && leap ? 1 : 0);
  if (day < 1 || day > dim || hour > 23 || minute > 59 || !(seconds >= 0.0 && seconds < 60.0)) return std::nullopt;
  // Days from 1970-01-01 in the proleptic Gregorian calendar (H. Hinnant's
  // days_from_civil, public domain).
  const int64_t y = int64_t(year) - (month <= 2 ? 1 : 0);
  const int64_t era = y / 400;  // y >= 0 here
  const int64_t yoe = y - era * 400;
  const int64_t mp = month > 2 ? month - 3 : month + 9;
  const int64_t doy = (153 * mp + 2) / 5 + day - 1;
  const int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  const int64_t days = era * 146097 + doe - 719468;
  return double(days) * 86400.0 + hour * 3600.0 + minute * 60.0 + seconds;
}

std::optional<double> EnvironmentState::utc_posix_s() const {
  if (!time_set) return std::nullopt;
  // 10 µs ticks (Wireshark's CIGI 3.3 IG Control timestamp field).
  return time_set->utc_posix_s + double(time_set->elapsed_ticks) * 1e-5;
}

bool EnvironmentState::apply(const DecodeResult& datagram) {
  if (!datagram.ok()) return false;
  for (const Event& e : datagram.events) apply(e);
  return true;
}

void EnvironmentState::apply(const Event& event) {
  std::visit(
      [&](const auto& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, IgControl>) {
          // The ephemeris runs by the host's timestamps, under the enable in
          // force since the last IG Control. The unsigned difference survives
          // the counter's wrap every 2^32 ticks (11.9 h).
          if (time_set) {
            if (celestial && celestial->ephemeris_enable && time_set->last_valid && p.timestamp_valid) {
              time_set->elapsed_ticks += uint32_t(p.timestamp_ticks - time_set->last_ticks);
            }
            time_set->last_ticks = p.timestamp_ticks;
            time_set->last_valid = p.timestamp_valid;
          }
          ig_control = p;
        } else if constexpr (std::is_same_v<T, CelestialControl>) {
          if (p.date_time_valid) {
            const std::optional<double> t =
                utc_from_civil(p.year(), p.month(), p.day(), p.hour, p.minute, double(p.seconds));
            if (t) {
              TimeSet set;
              set.utc_posix_s = *t;
              set.last_ticks = ig_control ? ig_control->timestamp_ticks : 0;
              set.last_valid = ig_control && ig_control->timestamp_valid;
              time_set = set;
            } else {
              std::ostringstream s;
              s << "CIGI Celestial Sphere Control: date/time " << p.date_mmddyyyy << " (MMDDYYYY) " << int(p.hour)
                << ':' << int(p.minute) << ':' << p.seconds << " is not a valid UTC date and time: ignored";
              log.push_back(s.str());
            }
          }
          celestial = p;
        } else if constexpr (std::is_same_v<T, AtmosphereControl>) {
          atmosphere = p;
        } else if constexpr (std::is_same_v<T, RegionControl>) {
          if (p.state == kRegionDestroyed) {
            regions.erase(p.region_id);
            // The region's weather goes with it.
            for (auto it = weather.begin(); it != weather.end();) {
              if (it->first.scope == kScopeRegional && it->first.id == p.region_id) {
                it = weather.erase(it);
              } else {
                ++it;
              }
            }
          } else {
            regions[p.region_id] = p;
          }
        } else if constexpr (std::is_same_v<T, WeatherControl>) {
          WeatherKey k;
          k.scope = p.scope;
          k.id = p.scope == kScopeGlobal ? 0 : p.entity_region_id;
          k.layer_id = p.layer_id;
          weather[k] = p;
        }
      },
      event);
}

// ---- mapping onto the plugin ----------------------------------------------

int coverage_pct_to_oktas(double coverage_pct) {
  // The rule of atmo_scenario's fraction_to_okta_code (tools/scenario units.h).
  const double f = coverage_pct / 100.0;
  if (!(f > 0.0)) return 0;
  if (f >= 1.0) return 8;
  return std::clamp(static_cast<int>(std::lround(f * 8.0)), 1, 7);
}

std::optional<AtmoCloudLayerType> plugin_cloud_type(uint8_t t) {
  switch (t) {
    case kCumulus:
    case kAltocumulus:     // heaped, separate clouds higher up: the nearest shape
    case kCumulonimbus:    // no anvil, no precipitation: a cumulus field
      return ATMO_CLOUD_CUMULUS;
    case kStratus:
    case kStratocumulus:
    case kAltostratus:
      return ATMO_CLOUD_STRATUS;
    case kNimbostratus:
      return ATMO_CLOUD_OVERCAST;
    case kCirrus:
    case kCirrostratus:
    case kCirrocumulus:
      return ATMO_CLOUD_CIRRUS;
    default:
      return std::nullopt;  // None, user-defined 11-15
  }
}

AtmoCloudsState PluginState::clouds_state() const {
  AtmoCloudsState s{};
  s.header.type = ATMO_TYPE_CLOUDS_STATE;
  s.header.struct_size = sizeof(AtmoCloudsState);
  s.header.next = nullptr;
  for (int i = 0; i < 3; ++i) s.origin_geodetic[i] = clouds_origin_geodetic[i];
  s.layers = cloud_layer_count ? cloud_layers.data() : nullptr;
  s.layer_count = cloud_layer_count;
  s.layer_size = sizeof(AtmoCloudLayer);
  return s;
}

namespace {

// The plugin's valid ranges (atmo.h).
constexpr double kMinUtc = -62135596800.0, kMaxUtc = 253402300799.0;
constexpr double kMinVisibility = 50.0, kMaxVisibility = 500000.0;
constexpr double kMinFogVisibility = 10.0, kMaxFogVisibility = 100000.0;
constexpr double kMinFogTop = -500.0, kMaxHeight = 20000.0;

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

PluginState to_plugin(const EnvironmentState& env, const MappingInputs& in) {
  PluginState out;
  out.frame.header.type = ATMO_TYPE_FRAME_STATE;
  out.frame.header.struct_size = sizeof(AtmoFrameState);
  out.atmosphere.header.type = ATMO_TYPE_ATMOSPHERE_STATE;
  out.atmosphere.header.struct_size = sizeof(AtmoAtmosphereState);
  out.fog.header.type = ATMO_TYPE_FOG_STATE;
  out.fog.header.struct_size = sizeof(AtmoFogState);
  for (int i = 0; i < 3; ++i) out.clouds_origin_geodetic[i] = in.clouds_origin_geodetic[i];

  // Time: CIGI's date/time when one was valid, else the host's.
  out.frame.utc_posix_s = in.host_utc_posix_s;
  if (const std::optional<double> t = env.utc_posix_s()) {
    if (*t >= kMinUtc && *t <= kMaxUtc) {
      out.frame.utc_posix_s = *t;
      out.time_from_cigi = true;
    } else {
      out.notes.push_back("time: CIGI's " + num(*t) + " s is outside the plugin's range; the host's time stands");
    }
  }
  if (env.ig_control) out.frame.host_frame_number = env.ig_control->host_frame_number;
  out.night_sky = !env.celestial || env.celestial->star_enable;

  // Visibility: Atmosphere Control's global visibility wins; without one, the
  // lowest of the enabled global precipitation and obscurant layers (4-9).
  double vis = 0;
  const char* vis_from = nullptr;
  if (env.atmosphere) {
    vis = env.atmosphere->visibility_m;
    vis_from = "Atmosphere Control";
  } else {
    for (const auto& [key, w] : env.weather) {
      if (key.scope != kScopeGlobal || key.layer_id < kLayerRain || key.layer_id > kLayerDust || !w.weather_enable)
        continue;
      if (w.visibility_m > 0 && (vis == 0 || w.visibility_m < vis)) {
        vis = w.visibility_m;
        vis_from = "a global weather layer";
      }
    }
  }
  if (vis_from) {
    if (!(vis > 0)) {
      out.notes.push_back(std::string("visibility: ") + vis_from + "'s " + num(vis) +
                          " m is not a visibility; the plugin's default stands");
      vis = 0;
    } else if (vis < kMinVisibility || vis > kMaxVisibility) {
      const double c = std::clamp(vis, kMinVisibility, kMaxVisibility);
      out.notes.push_back(std::string("visibility: ") + vis_from + "'s " + num(vis) + " m clamped to " + num(c) +
                          " m (the plugin's range)");
      vis = c;
    }
  }
  out.atmosphere.visibility_m = vis;

  // Cloud layers 1-3, global scope, enabled.
  const double up_from_msl = in.geoid_undulation_m - in.clouds_origin_geodetic[2];
  for (uint8_t layer = kLayerCloud1; layer <= kLayerCloud3; ++layer) {
    const auto it = env.weather.find(WeatherKey{kScopeGlobal, 0, layer});
    if (it == env.weather.end() || !it->second.weather_enable) continue;
    const WeatherControl& w = it->second;
    const std::string name = "cloud layer " + std::to_string(layer);
    const std::optional<AtmoCloudLayerType> type = plugin_cloud_type(w.cloud_type);
    if (!type) {
      out.notes.push_back(name + ": cloud type " + std::to_string(w.cloud_type) + " has no plugin type: not drawn");
      continue;
    }
    if (!(w.thickness_m > 0)) {
      out.notes.push_back(name + ": thickness " + num(w.thickness_m) + " m: not drawn");
      continue;
    }
    const double base = double(w.base_elevation_m) + up_from_msl;
    double top = base + double(w.thickness_m);
    if (base < 0 || base >= kMaxHeight) {
      out.notes.push_back(name + ": base " + num(base) +
                          " m above the clouds' origin is outside the plugin's [0, 20000): not drawn");
      continue;
    }
    if (top > kMaxHeight) {
      out.notes.push_back(name + ": top " + num(top) + " m clamped to 20000 m");
      top = kMaxHeight;
    }
    if (!(top > base)) {  // a thickness lost in the base's rounding (found by fuzz_cigi)
      out.notes.push_back(name + ": thickness " + num(w.thickness_m) + " m does not lift the top above the base: "
                          "not drawn");
      continue;
    }
    AtmoCloudLayer& c = out.cloud_layers[out.cloud_layer_count++];
    c = AtmoCloudLayer{};
    c.header.type = ATMO_TYPE_CLOUD_LAYER;
    c.header.struct_size = sizeof(AtmoCloudLayer);
    c.type = uint32_t(*type);
    c.coverage_oktas = coverage_pct_to_oktas(w.coverage_pct);
    c.base_m = base;
    c.top_m = top;
    c.area_size_m = in.cloud_area_size_m;
    c.seed = layer;  // the same clouds on every channel and every run
  }

  // Ground fog: layer 0, global scope, enabled.
  const auto fog = env.weather.find(WeatherKey{kScopeGlobal, 0, kLayerGroundFog});
  if (fog != env.weather.end() && fog->second.weather_enable) {
    const WeatherControl& w = fog->second;
    double fv = w.visibility_m;
    double top = double(w.base_elevation_m) + double(w.thickness_m) + in.geoid_undulation_m;
    if (!(fv > 0)) {
      out.notes.push_back("ground fog: visibility " + num(fv) + " m: not drawn");
    } else if (!(w.thickness_m > 0)) {
      out.notes.push_back("ground fog: thickness " + num(w.thickness_m) + " m: not drawn");
    } else if (top < kMinFogTop) {
      out.notes.push_back("ground fog: top " + num(top) + " m below the plugin's -500 m: not drawn");
    } else {
      if (fv < kMinFogVisibility || fv > kMaxFogVisibility) {
        const double c = std::clamp(fv, kMinFogVisibility, kMaxFogVisibility);
        out.notes.push_back("ground fog: visibility " + num(fv) + " m clamped to " + num(c) + " m");
        fv = c;
      }
      if (top > kMaxHeight) {
        out.notes.push_back("ground fog: top " + num(top) + " m clamped to 20000 m");
        top = kMaxHeight;
      }
      // 0 would mean "no top" to the plugin.
      if (std::abs(top) < 0.01) top = 0.01;
      out.fog.visibility_m = fv;
      out.fog.top_height_m = top;
    }
  }
  return out;
}

}  // namespace atmo::cigi
