// atmo-cigi-host-emulator: a scripted CIGI host for atmo-cigi-ig. It sends
// four states through cigi.h's encoder — noon in clear air (50 km), noon at
// 2 km, noon under an overcast deck (3.3, little-endian), a clear night (4.0)
// — each for
// --frames-per-state host frames (the packets in the first, an IG Control
// alone in the rest, as a host sends every frame: the IG draws a change from
// its --deferred-frames D on, so D or more frames a state draw its last frame
// with it), with malformed,
// truncated, unknown and byte-swapped datagrams between them. It waits for
// the IG's Start of Frame after each frame (--sof-timeout, then exit 1): it
// must echo the host frame number and count its own frames one by one.
// --report writes one JSON line per datagram sent: what the IG should show
// (frames) or say (refused datagrams), and the Start of Frame received.
//
//   atmo-cigi-host-emulator --port N [--ig 127.0.0.1] [--frames-per-state 2] [--sof-timeout 30] [--report FILE]
//
// Exit codes: 0 every frame answered as the ICD says, 1 a missing or wrong
// Start of Frame, 2 a setup failure.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "atmo/cigi.h"
#include "atmo_support/cli.h"
#include "udp_socket.h"

namespace {

namespace cigi = atmo::cigi;
using atmo::cigi_ig::UdpSocket;

// The script's day: 2024-06-06, a new moon (no moonlight at night), at the sample scene's airfield (8.55 E:
// local noon near 11:26 UTC). Noon: 11:30 UTC, the Sun ~65 degrees up; night: 22:00 UTC, ~18 degrees down.
constexpr uint32_t kDate = 6062024;  // MMDDYYYY
constexpr uint8_t kNoonHour = 11, kNoonMinute = 30, kNightHour = 22, kNightMinute = 0;
constexpr float kClearVisibilityM = 50000, kLowVisibilityM = 2000;
// The overcast deck: Nimbostratus (the plugin's overcast), 100 %, base 1 500 m MSL, 800 m thick.
constexpr float kDeckBaseMslM = 1500, kDeckThicknessM = 800;
constexpr uint32_t kFirstHostFrame = 1000;  // far from the IG's own count, so an echo cannot be mistaken

cigi::IgControl ig_control(uint32_t host_frame, uint8_t minor_version = 3) {
  cigi::IgControl ig;
  ig.minor_version = minor_version;  // 3.3, or 4.0
  ig.ig_mode = 1;  // operate
  ig.host_frame_number = host_frame;
  return ig;
}

cigi::CelestialControl celestial(uint8_t hour, uint8_t minute) {
  cigi::CelestialControl c;
  c.hour = hour;
  c.minute = minute;
  c.date_mmddyyyy = kDate;
  c.date_time_valid = true;
  c.ephemeris_enable = false;  // frozen: each frame at exactly the time sent
  c.sun_enable = c.moon_enable = c.star_enable = true;
  c.star_intensity_pct = 100;
  return c;
}

cigi::AtmosphereControl atmosphere(float visibility_m) {
  cigi::AtmosphereControl a;
  a.visibility_m = visibility_m;
  return a;
}

cigi::WeatherControl overcast_deck(bool enable) {
  cigi::WeatherControl w;
  w.layer_id = cigi::kLayerCloud1;
  w.scope = cigi::kScopeGlobal;
  w.weather_enable = enable;
  w.cloud_type = cigi::kNimbostratus;
  w.coverage_pct = 100;
  w.base_elevation_m = kDeckBaseMslM;
  w.thickness_m = kDeckThicknessM;
  w.visibility_m = 200;  // inside the cloud (accepted, not drawn)
  return w;
}

// What the IG accepts and cannot draw (it says so once): a cloud layer of a user-defined type and a region.
cigi::WeatherControl user_defined_cloud_layer() {
  cigi::WeatherControl w;
  w.layer_id = cigi::kLayerCloud2;
  w.weather_enable = true;
  w.cloud_type = 11;  // user-defined: no plugin type
  w.coverage_pct = 50;
  w.base_elevation_m = 6000;
  w.thickness_m = 500;
  return w;
}

cigi::RegionControl region() {
  cigi::RegionControl r;
  r.region_id = 7;
  r.state = cigi::kRegionActive;
  r.latitude_deg = 47.46;
  r.longitude_deg = 8.55;
  r.size_x_m = r.size_y_m = 20000;
  return r;
}

// One datagram of the script: a host frame (answered) or a bad one (refused, not answered).
struct Step {
  std::string label;
  std::vector<uint8_t> bytes;
  bool frame = false;
  cigi::ByteOrder order = cigi::ByteOrder::Big;
  cigi::Version version{3, 3};
  uint32_t host_frame = 0;
  // A frame: its state (0, 1, ...: the script's order), whether it is the state's last frame (drawn with it
  // whatever the deferral), and what the IG should draw with.
  int state = -1;
  bool last_of_state = false;
  double utc_posix_s = 0, visibility_m = 0;
  int cloud_layers = 0;
  // A bad datagram: what the IG's log line should say.
  std::string expect;
};

double utc(uint8_t hour, uint8_t minute) {
  return *cigi::utc_from_civil(kDate % 10000, kDate / 1000000, kDate / 10000 % 100, hour, minute, 0.0);
}

std::vector<Step> script(int frames_per_state) {
  const cigi::Version v33{3, 3};
  std::vector<Step> steps;
  uint32_t host = kFirstHostFrame;
  int state = 0;
  const auto frame = [&](const std::string& label, cigi::ByteOrder order, std::vector<cigi::Event> events,
                         std::vector<std::pair<uint32_t, size_t>> raw, double t, double vis, int clouds,
                         cigi::Version version = {3, 3}) {
    for (int i = 0; i < frames_per_state; ++i) {
      cigi::Encoder e(version, order);
      e.add(ig_control(host, version.minor));
      if (i == 0) {
        for (const cigi::Event& ev : events) e.add(ev);
        for (const auto& [id, size] : raw) e.add_raw(id, size);
      }
      Step s;
      s.label = i == 0 ? label : label + " (IG Control only)";
      s.bytes = e.bytes();
      s.frame = true;
      s.order = order;
      s.version = version;
      s.host_frame = host++;
      s.state = state;
      s.last_of_state = i == frames_per_state - 1;
      s.utc_posix_s = t;
      s.visibility_m = vis;
      s.cloud_layers = clouds;
      steps.push_back(s);
    }
    ++state;
  };
  const auto bad = [&](std::string label, std::vector<uint8_t> bytes, std::string expect) {
    Step s;
    s.label = std::move(label);
    s.bytes = std::move(bytes);
    s.expect = std::move(expect);
    steps.push_back(s);
  };
  const double noon = utc(kNoonHour, kNoonMinute), night = utc(kNightHour, kNightMinute);

  frame("noon, clear air (50 km)", cigi::ByteOrder::Big,
        {celestial(kNoonHour, kNoonMinute), atmosphere(kClearVisibilityM)}, {}, noon, kClearVisibilityM, 0);

  bad("an empty datagram", {}, "empty datagram");
  {  // a Weather Control cut to 40 of its 56 bytes (the size field says 40)
    std::vector<uint8_t> b = cigi::encode(v33, cigi::ByteOrder::Big, {ig_control(host), overcast_deck(true)});
    b[24 + 1] = 40;
    b.resize(24 + 40);
    bad("a truncated Weather Control", b, "Weather Control (packet id 12) at byte 24: field 'packet size'");
  }
  {  // a datagram cut inside its second packet: the size field runs past the end
    std::vector<uint8_t> b = cigi::encode(v33, cigi::ByteOrder::Big, {ig_control(host), atmosphere(1)});
    b.resize(24 + 20);
    bad("a datagram cut short", b, "Atmosphere Control (packet id 10) at byte 24: field 'packet size': size 32 runs past");
  }

  // Unknown packets in a good message: skipped by their size, the frame drawn.
  frame("noon, 2 km; with an Entity Control and a user packet (skipped)", cigi::ByteOrder::Big,
        {atmosphere(kLowVisibilityM)}, {{2, 48}, {201, 16}}, noon, kLowVisibilityM, 0);

  {  // neither byte order's magic
    std::vector<uint8_t> b = cigi::encode(v33, cigi::ByteOrder::Big, {ig_control(host)});
    b[6] = 0x12;
    b[7] = 0x34;
    bad("a bad byte-swap magic", b, "IG Control (packet id 1) at byte 0: field 'byte-swap magic'");
  }
  {  // an unknown packet first: not a CIGI message
    cigi::Encoder e(v33, cigi::ByteOrder::Big);
    e.add_raw(200, 24);
    bad("an unknown packet first", e.bytes(), "field 'IG Control': the first packet must be an IG Control");
  }
  {  // a NaN visibility
    cigi::AtmosphereControl a = atmosphere(std::numeric_limits<float>::quiet_NaN());
    bad("a NaN visibility", cigi::encode(v33, cigi::ByteOrder::Big, {ig_control(host), a}),
        "Atmosphere Control (packet id 10) at byte 24: field 'visibility range': not a finite number");
  }

  // Byte-swapped: a little-endian host (the magic reads 0x00 0x80).
  // With a layer the plugin cannot draw and a region: accepted, said once.
  frame("noon, 50 km, an overcast deck (little-endian host)", cigi::ByteOrder::Little,
        {atmosphere(kClearVisibilityM), overcast_deck(true), user_defined_cloud_layer(), region()}, {}, noon,
        kClearVisibilityM, 1);

  {  // a CIGI 3.0/3.1 IG Control (16 bytes)
    std::vector<uint8_t> b = cigi::encode(v33, cigi::ByteOrder::Little, {ig_control(host)});
    b[1] = 16;
    b.resize(16);
    bad("a CIGI 3.1 IG Control", b, "a CIGI 3.0/3.1 IG Control");
  }

  // A CIGI 4.0 host (little-endian: the size field's zero byte comes second), answered with a 4.0 Start of Frame.
  frame("night, clear air (the deck's layer disabled; a CIGI 4.0 little-endian host)", cigi::ByteOrder::Little,
        {celestial(kNightHour, kNightMinute), overcast_deck(false)}, {}, night, kClearVisibilityM, 0,
        cigi::Version{4, 0});
  return steps;
}

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

const char* order_name(cigi::ByteOrder o) { return o == cigi::ByteOrder::Big ? "big" : "little"; }

}  // namespace

int main(int argc, char** argv) {
  std::string ig_address = "127.0.0.1", report_path;
  uint16_t port = 0;
  double sof_timeout_s = 30;
  int frames_per_state = 2;
  CLI::App app{"A scripted CIGI 3.3/4.0 host for atmo-cigi-ig: four states (noon to night, 50 km to 2 km, an overcast "
               "deck) and bad datagrams between them; each frame waits for the IG's Start of Frame."};
  app.add_option("--ig", ig_address, "The IG's IPv4 address")->capture_default_str();
  app.add_option("--port", port, "The IG's UDP port")->required()->check(CLI::Range(1, 65535));
  app.add_option("--frames-per-state", frames_per_state,
                 "Host frames each state is held for (the packets in the first); as many as the IG's "
                 "--deferred-frames or more: each state's last frame is drawn with it")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--sof-timeout", sof_timeout_s, "Seconds to wait for each Start of Frame")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  app.add_option("--report", report_path, "Write one JSON line per datagram sent (and the answer to a frame)");
  if (const auto exit_code = atmo::support::parse_command_line(app, argc, argv)) return *exit_code;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);

  std::string error;
  sockaddr_in ig{};
  if (!atmo::cigi_ig::parse_ipv4(ig_address, port, &ig, &error)) {
    std::fprintf(stderr, "atmo-cigi-host-emulator: --ig: %s\n", error.c_str());
    return 2;
  }
  UdpSocket socket;
  if (!socket.open("0.0.0.0", 0, &error)) {
    std::fprintf(stderr, "atmo-cigi-host-emulator: %s\n", error.c_str());
    return 2;
  }
  std::ofstream report;
  if (!report_path.empty()) {
    report.open(report_path, std::ios::trunc);
    if (!report) {
      std::fprintf(stderr, "atmo-cigi-host-emulator: cannot write %s\n", report_path.c_str());
      return 2;
    }
  }
  std::printf("atmo-cigi-host-emulator: CIGI 3.3 host on port %u, sending to %s\n", socket.local_port(),
              atmo::cigi_ig::to_string(ig).c_str());

  bool have_ig_frame = false;
  uint32_t last_ig_frame = 0;
  std::vector<uint8_t> answer;
  for (const Step& step : script(frames_per_state)) {
    if (!socket.send_to(ig, step.bytes, &error)) {
      std::fprintf(stderr, "atmo-cigi-host-emulator: %s\n", error.c_str());
      return 2;
    }
    std::ostringstream line;
    line.precision(12);
    line << "{\"label\":\"" << json_escape(step.label) << "\",\"bytes\":" << step.bytes.size();
    if (!step.frame) {
      std::printf("sent %s (%zu bytes): no answer expected\n", step.label.c_str(), step.bytes.size());
      line << ",\"frame\":false,\"expect\":\"" << json_escape(step.expect) << "\"}";
      if (report.is_open()) report << line.str() << '\n' << std::flush;
      continue;
    }
    // The IG's answer to this frame; anything else first is an error (an answer to a refused datagram would
    // echo an older host frame).
    const auto sent = std::chrono::steady_clock::now();
    sockaddr_in from{};
    UdpSocket::Wait w;
    do {
      const double left = sof_timeout_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
      w = left > 0 ? socket.receive(left, &answer, &from, &error) : UdpSocket::Wait::Timeout;
    } while (w == UdpSocket::Wait::Interrupted);
    if (w == UdpSocket::Wait::Error) {
      std::fprintf(stderr, "atmo-cigi-host-emulator: %s\n", error.c_str());
      return 2;
    }
    if (w == UdpSocket::Wait::Timeout) {
      std::fprintf(stderr, "atmo-cigi-host-emulator: no Start of Frame within %g s after host frame %u (%s)\n",
                   sof_timeout_s, step.host_frame, step.label.c_str());
      return 1;
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - sent).count();
    const cigi::IgMessage m = cigi::decode_ig_message(answer);
    if (!m.ok()) {
      std::fprintf(stderr, "atmo-cigi-host-emulator: the answer to host frame %u from %s: %s\n", step.host_frame,
                   atmo::cigi_ig::to_string(from).c_str(), m.error->message.c_str());
      return 1;
    }
    const cigi::StartOfFrame& sof = m.sof;
    std::printf("sent host frame %u, %s (%zu bytes, CIGI %d.%d %s-endian); Start of Frame %u (last host frame %u, "
                "CIGI %d.%d %s-endian, mode %u) after %.0f ms\n",
                step.host_frame, step.label.c_str(), step.bytes.size(), step.version.major, step.version.minor,
                order_name(step.order), sof.ig_frame_number, sof.last_host_frame_number, m.version.major,
                m.version.minor, order_name(m.byte_order), sof.ig_mode, ms);
    line << ",\"frame\":true,\"host_frame\":" << step.host_frame << ",\"state\":" << step.state
         << ",\"last_of_state\":" << (step.last_of_state ? "true" : "false") << ",\"byte_order\":\"" << order_name(step.order)
         << "\",\"version\":\"" << int(step.version.major) << '.' << int(step.version.minor)
         << "\",\"utc_posix_s\":" << step.utc_posix_s << ",\"visibility_m\":" << step.visibility_m
         << ",\"cloud_layers\":" << step.cloud_layers << ",\"sof\":{\"ig_frame\":" << sof.ig_frame_number
         << ",\"last_host_frame\":" << sof.last_host_frame_number << ",\"byte_order\":\"" << order_name(m.byte_order)
         << "\",\"version\":\"" << int(m.version.major) << '.' << int(m.version.minor)
         << "\",\"ms\":" << std::lround(ms) << "}}";
    if (report.is_open()) report << line.str() << '\n' << std::flush;
    if (sof.last_host_frame_number != step.host_frame) {
      std::fprintf(stderr, "atmo-cigi-host-emulator: the Start of Frame after host frame %u says last host frame %u\n",
                   step.host_frame, sof.last_host_frame_number);
      return 1;
    }
    if (have_ig_frame && sof.ig_frame_number != last_ig_frame + 1) {
      std::fprintf(stderr, "atmo-cigi-host-emulator: IG frame %u follows IG frame %u (one more each message)\n",
                   sof.ig_frame_number, last_ig_frame);
      return 1;
    }
    have_ig_frame = true;
    last_ig_frame = sof.ig_frame_number;
  }
  std::printf("atmo-cigi-host-emulator: every frame answered\n");
  return 0;
}
