// cigi.h — CIGI environment control for hosts (C++17, library atmo_host_cigi):
// a decoder and an encoder of the environment packets of CIGI 3.3 and 4.0, an
// accumulator of the environment they describe, and the mapping of that
// environment onto the plugin's structs (AtmoFrameState, AtmoAtmosphereState,
// AtmoCloudsState, AtmoFogState). docs/CIGI.md has the field table (what is
// drawn, what is accepted and not drawn), the sources of every byte layout
// and the errors.
//
//   atmo::cigi::EnvironmentState env;
//   atmo::cigi::DecodeResult d = atmo::cigi::decode(datagram, size);   // one UDP datagram
//   if (!d.ok()) log(d.error->message);      // refused whole: env unchanged
//   env.apply(d);
//   atmo::cigi::PluginState s = atmo::cigi::to_plugin(env, inputs);
//   world.set_frame(s.frame); world.set_atmosphere(s.atmosphere); ...
//
// Nothing here touches the network, a clock or the plugin: the host owns the
// socket and the calls. Values keep the wire's types and units (CIGI's °C,
// mb, %, degrees) until to_plugin() converts them to SI.
#ifndef ATMO_CIGI_H
#define ATMO_CIGI_H

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "atmo/atmo.h"

namespace atmo::cigi {

// The byte order of a message's multi-byte fields. CIGI 3 announces it with
// the IG Control's byte-swap magic 0x8000; CIGI 4.0 with the first packet's
// size field (a zero first byte: big-endian).
enum class ByteOrder : uint8_t { Little = 0, Big = 1 };

struct Version {
  uint8_t major = 3;  // 3 or 4
  uint8_t minor = 3;  // 3.x: 2 or 3 (the 24-byte IG Control); 4.x: 0
};

// Packet identifiers and sizes (bytes) of the packets decoded here.
// CIGI 3.x: Boeing CCL (Hadron/cigi-ccl include/CigiBase*.h) and Wireshark
// packet-cigi.c agree. CIGI 4.0: CCL 4.0 (captainflasmr/cigi-ccl_4_0 include/CigiBase*.h).
namespace v3 {
constexpr uint8_t kIgControlId = 1, kCelestialId = 9, kAtmosphereId = 10, kRegionId = 11, kWeatherId = 12;
constexpr uint8_t kIgControlSize = 24, kCelestialSize = 16, kAtmosphereSize = 32, kRegionSize = 48,
                  kWeatherSize = 56;
// IG to host: Start of Frame (3.2/3.3; 3.0/3.1's is 16 bytes and not decoded).
constexpr uint8_t kStartOfFrameId = 101, kStartOfFrameSize = 24;
}  // namespace v3
namespace v4 {
constexpr uint16_t kIgControlId = 0, kCelestialId = 8, kAtmosphereId = 9, kRegionId = 10, kWeatherId = 11;
constexpr uint16_t kIgControlSize = 24, kCelestialSize = 24, kAtmosphereSize = 32, kRegionSize = 48,
                   kWeatherSize = 72;
// IG to host: Start of Frame (CCL 4.0 CigiBaseSOF.h / CigiSOFV4.cpp; id and size confirmed by the Wireshark
// fork's CIGI 4 dissector, which disagrees on where the flags sit: docs/CIGI.md).
constexpr uint16_t kStartOfFrameId = 0xFFFF, kStartOfFrameSize = 24;
}  // namespace v4

// Weather layer identifiers (CIGI 3.3 and 4.0 alike).
enum WeatherLayer : uint8_t {
  kLayerGroundFog = 0, kLayerCloud1 = 1, kLayerCloud2 = 2, kLayerCloud3 = 3, kLayerRain = 4, kLayerSnow = 5,
  kLayerSleet = 6, kLayerHail = 7, kLayerSand = 8, kLayerDust = 9  // 10-255: IG-defined
};
// Weather cloud types (4 bits).
enum CloudType : uint8_t {
  kCloudNone = 0, kAltocumulus = 1, kAltostratus = 2, kCirrocumulus = 3, kCirrostratus = 4, kCirrus = 5,
  kCumulonimbus = 6, kCumulus = 7, kNimbostratus = 8, kStratocumulus = 9, kStratus = 10  // 11-15: user-defined
};
enum Scope : uint8_t { kScopeGlobal = 0, kScopeRegional = 1, kScopeEntity = 2 };
enum RegionState : uint8_t { kRegionInactive = 0, kRegionActive = 1, kRegionDestroyed = 2 };

// IG Control: first packet of every host message.
struct IgControl {
  uint8_t minor_version = 3;        // 3.x: 2 or 3; 4.x: 0
  int8_t database_id = 0;           // 0: no action
  uint8_t ig_mode = 1;              // 0 reset/standby, 1 operate, 2 debug
  bool timestamp_valid = false;
  bool smoothing_enable = false;    // extrapolation/interpolation smoothing
  bool entity_substitution_enable = false;  // 4.0 only (3.x: false)
  uint32_t host_frame_number = 0;
  uint32_t timestamp_ticks = 0;     // 10 µs ticks since a host-chosen reference
  uint32_t last_ig_frame_number = 0;
};

// Celestial Sphere Control.
struct CelestialControl {
  uint8_t hour = 0;                 // 0-23
  uint8_t minute = 0;               // 0-59
  float seconds = 0;                // 4.0 only (3.x: 0); [0, 60)
  uint32_t date_mmddyyyy = 1012000; // month * 1000000 + day * 10000 + year
  bool ephemeris_enable = false;    // the time of day runs (true) or is frozen
  bool sun_enable = false;
  bool moon_enable = false;
  bool star_enable = false;
  bool date_time_valid = false;     // hour, minute (seconds) and date override the IG's time
  float star_intensity_pct = 0;
  unsigned month() const { return date_mmddyyyy / 1000000u; }
  unsigned day() const { return date_mmddyyyy / 10000u % 100u; }
  unsigned year() const { return date_mmddyyyy % 10000u; }
};

// Atmosphere Control: the global air.
struct AtmosphereControl {
  bool model_enable = false;        // an atmospheric model for sensor radiances
  uint8_t humidity_pct = 30;        // 3.x: 8 bits; 4.0: 7 bits (0-127)
  float air_temperature_c = 0;
  float visibility_m = 64373.76f;   // global visibility range
  float horizontal_wind_mps = 0;
  float vertical_wind_mps = 0;
  float wind_direction_deg = 0;     // from true north
  float pressure_hpa = 1013.25f;    // mb = hPa
};

// Environmental Region Control: a rounded rectangle on the ground.
struct RegionControl {
  uint16_t region_id = 0;
  uint8_t state = kRegionInactive;  // RegionState
  bool merge_weather = false;       // merge (true) or use the last region's (false) in overlaps
  bool merge_aerosol = false;
  bool merge_maritime = false;
  bool merge_terrestrial = false;
  double latitude_deg = 0;          // centre, geodetic
  double longitude_deg = 0;
  float size_x_m = 0;
  float size_y_m = 0;
  float corner_radius_m = 0;
  float rotation_deg = 0;           // yaw from true north
  float transition_perimeter_m = 0;
};

// Weather Control: one weather layer, global, in a region or on an entity.
// 4.0 splits the scud and transition band into bottom and top; a 3.x packet
// decodes with top = bottom (as CCL 4.0 converts it).
struct WeatherControl {
  uint16_t entity_region_id = 0;    // region (Scope regional) or entity (Scope entity); 0 for global
  uint8_t layer_id = 0;             // WeatherLayer
  uint8_t humidity_pct = 0;
  bool weather_enable = false;
  bool scud_enable = false;         // 4.0: bottom scud
  bool top_scud_enable = false;     // 4.0 only (3.x: = scud_enable)
  bool random_winds_enable = false;
  bool random_lightning_enable = false;
  uint8_t cloud_type = kCloudNone;  // CloudType, 4 bits
  uint8_t scope = kScopeGlobal;     // Scope, 2 bits
  uint8_t severity = 0;             // 0-5, 3 bits
  float air_temperature_c = 0;
  float visibility_m = 0;           // through the layer
  float scud_frequency_pct = 0;     // 4.0: bottom
  float coverage_pct = 0;
  float base_elevation_m = 0;       // m above MSL
  float thickness_m = 0;
  float transition_band_m = 0;      // 4.0: bottom
  float horizontal_wind_mps = 0;
  float vertical_wind_mps = 0;
  float wind_direction_deg = 0;
  float pressure_hpa = 1013.25f;
  float aerosol_gpm3 = 0;           // g/m^3
  float top_scud_frequency_pct = 0; // 4.0 only (3.x: = scud_frequency_pct)
  float top_transition_band_m = 0;  // 4.0 only (3.x: = transition_band_m)
};

using Event = std::variant<IgControl, CelestialControl, AtmosphereControl, RegionControl, WeatherControl>;

bool operator==(const IgControl& a, const IgControl& b);
bool operator==(const CelestialControl& a, const CelestialControl& b);
bool operator==(const AtmosphereControl& a, const AtmosphereControl& b);
bool operator==(const RegionControl& a, const RegionControl& b);
bool operator==(const WeatherControl& a, const WeatherControl& b);
inline bool operator!=(const IgControl& a, const IgControl& b) { return !(a == b); }
inline bool operator!=(const CelestialControl& a, const CelestialControl& b) { return !(a == b); }
inline bool operator!=(const AtmosphereControl& a, const AtmosphereControl& b) { return !(a == b); }
inline bool operator!=(const RegionControl& a, const RegionControl& b) { return !(a == b); }
inline bool operator!=(const WeatherControl& a, const WeatherControl& b) { return !(a == b); }

// Why a datagram was refused: the packet, where it starts and the field.
struct DecodeError {
  uint32_t packet_id = 0;   // 0xFFFFFFFF where the header itself could not be read
  size_t offset = 0;        // of the packet's first byte in the datagram
  std::string field;        // e.g. "packet size", "byte-swap magic", "visibility range"
  std::string message;      // the whole sentence, for a log
};

// A packet the decoder skipped (not an environment packet, or unknown).
struct SkippedPacket {
  uint32_t packet_id = 0;
  size_t offset = 0;
  size_t size = 0;
};

// One datagram decoded. A refused datagram has an error and no events: none
// of its packets may reach the environment, so every channel sees all of a
// message or none of it.
struct DecodeResult {
  std::optional<DecodeError> error;
  Version version;
  ByteOrder byte_order = ByteOrder::Little;
  std::vector<Event> events;            // in the datagram's order
  std::vector<SkippedPacket> skipped;
  std::vector<std::string> log;         // one line listing the skipped packets, if any
  bool ok() const { return !error.has_value(); }
};

// Decodes one host-to-IG message (a datagram): its first packet must be an
// IG Control of CIGI 3.2/3.3 (24 bytes) or 4.0. Never reads outside
// [data, data + size) and always ends (every step advances >= 2 bytes).
DecodeResult decode(const uint8_t* data, size_t size);
inline DecodeResult decode(const std::vector<uint8_t>& bytes) { return decode(bytes.data(), bytes.size()); }

// Builds a message packet by packet (tests, host emulators). Each add()
// throws std::invalid_argument for a value the version cannot carry (a
// 4.0 humidity above 127, a cloud type above 15, ...); it does not check that
// the IG Control comes first (so tests can build bad messages).
class Encoder {
 public:
  Encoder(Version version, ByteOrder order);
  Encoder& add(const Event& event);
  // A packet of any id and size with a zero body (size >= the header's 2 or 4 bytes).
  Encoder& add_raw(uint32_t packet_id, size_t size);
  const std::vector<uint8_t>& bytes() const { return bytes_; }

 private:
  Version version_;
  ByteOrder order_;
  std::vector<uint8_t> bytes_;
};
std::vector<uint8_t> encode(Version version, ByteOrder order, const std::vector<Event>& events);

// ---------------------------------------------------------------------------
// The IG's answer: Start of Frame, CIGI 3.2/3.3 and 4.0. 3.x layout: CCL 3.3
// CigiSOFV3_2::Pack/Unpack and Rinchi::CIGIPP::StartOfFrame agree; Wireshark's
// packet-cigi.c names the same fields in the same order. 4.0 layout: CCL 4.0
// CigiSOFV4 (flags in byte 7, IG status in byte 6, 16-bit condition flags at
// 20, written 0); only its id and size are confirmed elsewhere (docs/CIGI.md).

// Start of Frame: "Every IG-to-Host message must contain exactly one Start of
// Frame packet. This packet must be the first packet in the message" (the ICD
// as Rinchi::CIGIPP quotes it).
struct StartOfFrame {
  uint8_t minor_version = 3;        // 3.x: 2 or 3; 4.x: 0
  int8_t database_id = 0;           // 0: the IG controls the database; < 0 loading; -128: cannot be loaded
  uint8_t ig_status = 0;            // an IG-specific error code; 0: none
  uint8_t ig_mode = 1;              // 0 reset/standby, 1 operate, 2 debug, 3 offline maintenance
  bool timestamp_valid = false;
  bool earth_model_host_defined = false;  // Earth Reference Model: WGS 84 (false) or the host's
  uint32_t ig_frame_number = 0;     // the IG adds one every message
  uint32_t timestamp_ticks = 0;     // 10 µs ticks since an IG-chosen reference
  // "the value of the Host Frame Number attribute in the last IG Control
  // packet received from the Host ... an acknowledgement that the IG received
  // the last message".
  uint32_t last_host_frame_number = 0;
};
bool operator==(const StartOfFrame& a, const StartOfFrame& b);
inline bool operator!=(const StartOfFrame& a, const StartOfFrame& b) { return !(a == b); }

// The 24-byte packet of CIGI `major_version` 3 (the magic 0x8000 written in
// it) or 4 (the byte order is the size field's) in `order`. Throws
// std::invalid_argument for a mode above 3, a minor version above 15 or a
// major version other than 3 and 4. Answer a host in its own version.
std::vector<uint8_t> encode_start_of_frame(const StartOfFrame& sof, ByteOrder order, uint8_t major_version = 3);

// One IG-to-host message (a datagram) decoded: its Start of Frame; the
// packets after it are skipped by their size (listed), as decode() does.
struct IgMessage {
  std::optional<DecodeError> error;  // refused: sof is the default
  Version version;                   // 3.x or 4.0, from the Start of Frame
  ByteOrder byte_order = ByteOrder::Big;
  StartOfFrame sof;
  std::vector<SkippedPacket> skipped;
  bool ok() const { return !error.has_value(); }
};
// Refused (with the packet, byte and field named, as decode()'s errors): an
// empty datagram, a first packet that is not a 24-byte CIGI 3 or 4.0 Start of
// Frame (a 3.0/3.1 one of 16 bytes by name), a bad byte-swap magic or major
// version, a packet size of 0 / below the header / past the end, a second
// Start of Frame. Reads only inside [data, data + size).
IgMessage decode_ig_message(const uint8_t* data, size_t size);
inline IgMessage decode_ig_message(const std::vector<uint8_t>& b) { return decode_ig_message(b.data(), b.size()); }

// ---------------------------------------------------------------------------
// The environment the messages describe, accumulated.

struct WeatherKey {
  uint8_t scope = kScopeGlobal;
  uint16_t id = 0;          // region or entity; 0 for global
  uint8_t layer_id = 0;
  bool operator<(const WeatherKey& o) const;
};

class EnvironmentState {
 public:
  // Applies a datagram's events in order. A refused datagram changes nothing
  // (returns false).
  bool apply(const DecodeResult& datagram);
  void apply(const Event& event);

  // The last IG Control; its timestamp runs the ephemeris clock.
  std::optional<IgControl> ig_control;
  // The last Celestial Sphere Control (its enables, star intensity).
  std::optional<CelestialControl> celestial;
  // The time the last valid date/time set (UTC POSIX seconds) and the 10 µs
  // ticks the ephemeris model has run since: every IG Control adds the ticks
  // since the one before while the model is enabled and both timestamps are
  // valid (an integer count: no rounding builds up).
  struct TimeSet {
    double utc_posix_s = 0;
    uint64_t elapsed_ticks = 0;
    uint32_t last_ticks = 0;      // the last IG Control's timestamp
    bool last_valid = false;
  };
  std::optional<TimeSet> time_set;
  std::optional<AtmosphereControl> atmosphere;
  std::map<uint16_t, RegionControl> regions;   // Destroyed regions are erased
  std::map<WeatherKey, WeatherControl> weather;
  // Lines about packets that were decoded but could not be used (an invalid
  // date, ...). The caller clears it.
  std::vector<std::string> log;

  // The simulation time CIGI set: the last valid date/time, run on by the
  // IG Control timestamps while the ephemeris model is enabled, frozen while
  // it is disabled (TimeSet). nullopt: no valid date/time received — the
  // host's time stands.
  std::optional<double> utc_posix_s() const;
};

// ---------------------------------------------------------------------------
// Mapping onto the plugin.

struct MappingInputs {
  double host_utc_posix_s = 0;        // the host's time: used while CIGI set none
  double clouds_origin_geodetic[3] = {0, 0, 0};  // the clouds' ENU origin: lat deg, lon deg, h m (WGS84)
  double geoid_undulation_m = 0;      // N at the origin: height above the ellipsoid = MSL + N
  double cloud_area_size_m = 0;       // AtmoCloudLayer.area_size_m of global layers; 0: the plugin's 20 km
};

struct PluginState {
  AtmoFrameState frame{};             // utc_posix_s, host_frame_number (IG Control's)
  bool time_from_cigi = false;        // utc from CIGI (else the host's)
  AtmoAtmosphereState atmosphere{};   // visibility_m; 0: the plugin's default
  std::array<AtmoCloudLayer, 3> cloud_layers{};
  uint32_t cloud_layer_count = 0;
  double clouds_origin_geodetic[3] = {0, 0, 0};
  AtmoFogState fog{};                 // all zero but the header: no fog
  bool night_sky = true;              // Star Field Enable: the host skips ATMO_PASS_NIGHT_SKY when false
  std::vector<std::string> notes;     // layers not drawn or clamped, and why
  // The clouds' struct over cloud_layers: valid while this object lives and
  // is neither moved nor copied.
  AtmoCloudsState clouds_state() const;
};

PluginState to_plugin(const EnvironmentState& env, const MappingInputs& inputs);

// Helpers the mapping uses (tested on their own).
// UTC POSIX seconds of a Gregorian date and time; nullopt if invalid (year 1-9999).
std::optional<double> utc_from_civil(unsigned year, unsigned month, unsigned day, unsigned hour, unsigned minute,
                                     double seconds);
// Coverage in % to oktas as a METAR reports them (WMO code 2700): 0 only for
// none, 8 only for full, any trace at least 1 and any gap at most 7.
int coverage_pct_to_oktas(double coverage_pct);
// The plugin's cloud type for a CIGI cloud type; nullopt: none drawn (None, 11-15).
std::optional<AtmoCloudLayerType> plugin_cloud_type(uint8_t cigi_cloud_type);
// A packet's name ("Weather Control", "Start of Frame") or "" for one not decoded here.
const char* packet_name(uint8_t major_version, uint32_t packet_id);

}  // namespace atmo::cigi

#endif  // ATMO_CIGI_H
