// cigi_fuzz.cpp — the CIGI decoder (host_sdk cigi.h) on any bytes as one
// datagram, and what a host does with a decoded one: apply it to an
// environment and map that onto the plugin's structs. Contract: decoded xor
// refused; a refused datagram has no events and an error naming a byte inside
// it; every decoded number is finite and re-encodes to the same events
// (decode(encode(decode(x))) == decode(x)); the mapped structs lie inside
// the plugin's documented ranges (atmo.h), whatever the packets said. The
// same bytes as an IG-to-host message (decode_ig_message, the Start of
// Frame): decoded xor refused, and a decoded Start of Frame re-encodes to
// its own bytes.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <variant>
#include <vector>

#include "atmo/cigi.h"
#include "fuzz_check.h"

namespace c = atmo::cigi;

namespace {

bool same_events(const std::vector<c::Event>& a, const std::vector<c::Event>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].index() != b[i].index()) return false;
    if (!std::visit([&](const auto& x) { return x == std::get<std::decay_t<decltype(x)>>(b[i]); }, a[i]))
      return false;
  }
  return true;
}

void check_mapped(const c::PluginState& s) {
  FUZZ_CHECK(std::isfinite(s.frame.utc_posix_s) && s.frame.utc_posix_s >= -62135596800.0 &&
                 s.frame.utc_posix_s <= 253402300799.0,
             "frame time inside the plugin's range");
  const double v = s.atmosphere.visibility_m;
  FUZZ_CHECK(v == 0 || (v >= 50 && v <= 500000), "visibility 0 (default) or in [50, 500 000] m");
  FUZZ_CHECK(s.cloud_layer_count <= 3, "at most three cloud layers");
  for (uint32_t i = 0; i < s.cloud_layer_count; ++i) {
    const AtmoCloudLayer& l = s.cloud_layers[i];
    FUZZ_CHECK(l.type < ATMO_CLOUD_VDB_FILE, "a procedural cloud type");
    FUZZ_CHECK(l.coverage_oktas >= 0 && l.coverage_oktas <= 8, "oktas in [0, 8]");
    FUZZ_CHECK(l.base_m >= 0 && l.base_m < 20000 && l.top_m > l.base_m && l.top_m <= 20000,
               "0 <= base < top <= 20 000 m");
  }
  const AtmoCloudsState cs = s.clouds_state();
  FUZZ_CHECK(cs.layer_count == s.cloud_layer_count && (cs.layer_count == 0) == (cs.layers == nullptr),
             "the clouds' struct points at the layers");
  if (s.fog.visibility_m != 0) {
    FUZZ_CHECK(s.fog.visibility_m >= 10 && s.fog.visibility_m <= 100000, "fog visibility in [10, 100 000] m");
    FUZZ_CHECK(s.fog.top_height_m >= -500 && s.fog.top_height_m <= 20000 && s.fog.top_height_m != 0,
               "fog top in [-500, 20 000] m and not 0 (no top)");
  } else {
    FUZZ_CHECK(s.fog.top_height_m == 0, "no fog: no top");
  }
}

void check_ig_message(const uint8_t* data, size_t size) {
  const c::IgMessage m = c::decode_ig_message(data, size);
  if (!m.ok()) {
    FUZZ_CHECK(m.skipped.empty() && m.sof == c::StartOfFrame{}, "a refused IG message carries nothing");
    FUZZ_CHECK(!m.error->message.empty(), "an error says why");
    FUZZ_CHECK(size == 0 || m.error->offset < size, "the error names a byte inside the datagram");
    return;
  }
  size_t covered = c::v3::kStartOfFrameSize;
  for (const c::SkippedPacket& k : m.skipped) covered += k.size;
  FUZZ_CHECK(covered == size, "the Start of Frame and the skipped packets cover the datagram");
  const std::vector<uint8_t> again = c::encode_start_of_frame(m.sof, m.byte_order);
  const c::IgMessage m2 = c::decode_ig_message(again);
  FUZZ_CHECK(m2.ok() && m2.sof == m.sof && m2.byte_order == m.byte_order, "decode(encode(sof)) == sof");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  check_ig_message(data, size);
  const c::DecodeResult d = c::decode(data, size);
  if (!d.ok()) {
    FUZZ_CHECK(d.events.empty() && d.skipped.empty(), "a refused datagram carries nothing");
    FUZZ_CHECK(!d.error->message.empty(), "an error says why");
    FUZZ_CHECK(size == 0 || d.error->offset < size, "the error names a byte inside the datagram");
    return 0;
  }
  FUZZ_CHECK(!d.events.empty() && std::holds_alternative<c::IgControl>(d.events[0]), "an IG Control first");
  FUZZ_CHECK(d.version.major == 3 || d.version.major == 4, "version 3 or 4");
  size_t covered = 0;
  for (const c::SkippedPacket& k : d.skipped) covered += k.size;
  FUZZ_CHECK(covered <= size, "skipped packets lie inside the datagram");

  // What was decoded can be sent again, and reads back the same.
  const std::vector<uint8_t> again = c::encode(d.version, d.byte_order, d.events);
  const c::DecodeResult d2 = c::decode(again);
  FUZZ_CHECK(d2.ok() && d2.byte_order == d.byte_order && d2.version.major == d.version.major,
             "a re-encoded datagram decodes");
  FUZZ_CHECK(same_events(d.events, d2.events), "decode(encode(events)) == events");

  c::EnvironmentState env;
  FUZZ_CHECK(env.apply(d), "a decoded datagram applies");
  FUZZ_CHECK(env.apply(d), "and applies again");  // the same message twice: a lost SOF, a resend
  c::MappingInputs in;
  check_mapped(c::to_plugin(env, in));
  in.host_utc_posix_s = 1.7e9;
  in.clouds_origin_geodetic[0] = 47.5;
  in.clouds_origin_geodetic[1] = 8.5;
  in.clouds_origin_geodetic[2] = 420.0;
  in.geoid_undulation_m = 48.0;
  check_mapped(c::to_plugin(env, in));
  return 0;
}
