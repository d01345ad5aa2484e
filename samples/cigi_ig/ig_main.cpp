// atmo-cigi-ig: a CIGI image generator that draws the environment only. It
// listens on UDP for host messages (CIGI 3.3 or 4.0), keeps the environment
// they describe (host_sdk cigi.h: EnvironmentState), and for every host frame
// (a message accepted whole; its first packet is an IG Control) maps it onto
// the plugin (to_plugin), renders the sample host's scene headless (terrain,
// sky, aerial perspective, night sky, clouds: samples/sample_host's
// SampleRenderer) and answers the sender with a Start of Frame of the host's
// CIGI version and byte order that echoes the host's frame number. docs/CIGI.md, "atmo-cigi-ig".
//
//   atmo-cigi-ig [--bind 127.0.0.1] [--port 8004] [--port-file F] [--frames N] [--idle-timeout S]
//                [--out DIR] [--state-log FILE] [--plugin PATH] [--deferred-frames D]
//
// The plugin's frame is the host's frame number, so IGs of one host agree
// (docs/MULTI_CHANNEL.md). A message's set_* calls come before its frame's
// set_frame, so the plugin counts them as asked at the frame before: a change
// sent at host frame F is drawn from frame F - 1 + D (--deferred-frames D;
// the plugin's 8 by default; D = 1: from F itself).
//
// Exit codes: 0 after --frames N frames (or SIGINT/SIGTERM), 1 a plugin error,
// 2 a setup failure (arguments, socket, GL, files), 3 no datagram for
// --idle-timeout seconds.
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "atmo/cigi.h"
#include "atmo_support/cli.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/image.h"
#include "atmo_support/offscreen_target.h"
#include "sample_renderer.h"
#include "scene_settings.h"
#include "udp_socket.h"

#ifndef ATMO_CIGI_IG_DEFAULT_PLUGIN
#define ATMO_CIGI_IG_DEFAULT_PLUGIN "libatmo.so"
#endif

namespace {

namespace cigi = atmo::cigi;
namespace sample = atmo::sample;
namespace support = atmo::support;
using atmo::cigi_ig::UdpSocket;

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

constexpr double kPluginDefaultVisibilityM = 40000.0;  // AtmoAtmosphereState.visibility_m 0 means this (atmo.h)

struct Options {
  std::string bind = "127.0.0.1";
  uint16_t port = 8004;
  std::string port_file;
  int frames = 0;               // 0: until the idle timeout or a signal
  double idle_timeout_s = 300;  // 0: wait for ever
  std::string out_dir;
  std::string state_log;
  std::string plugin = ATMO_CIGI_IG_DEFAULT_PLUGIN;
  int width = 320, height = 180;
  double ev100 = 15.0;
  uint32_t deferred_frames = 0;  // AtmoFrameState.deferred_frames; 0: the plugin's ATMO_DEFERRED_FRAMES (8)
  bool verbose = false;
};

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char u[8];
      std::snprintf(u, sizeof u, "\\u%04x", c);
      out += u;
    } else {
      out += c;
    }
  }
  return out;
}

const char* order_name(cigi::ByteOrder o) { return o == cigi::ByteOrder::Big ? "big" : "little"; }

// The port, once the IG is ready: written whole (a reader never sees half a number).
bool write_port_file(const std::string& path, uint16_t port, std::string* error) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    f << port << "\n";
    if (!f) {
      *error = "cannot write " + tmp;
      return false;
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) *error = "cannot rename " + tmp + " to " + path + ": " + ec.message();
  return !ec;
}

// The scene's weather from the mapped CIGI state; true when the clouds changed (set_clouds relights: only then).
bool apply_plugin_state(const cigi::PluginState& s, sample::SceneSettings* settings) {
  settings->utc_posix_s = s.frame.utc_posix_s;
  settings->visibility_m = s.atmosphere.visibility_m > 0 ? s.atmosphere.visibility_m : kPluginDefaultVisibilityM;
  settings->fog_visibility_m = s.fog.visibility_m;
  if (s.fog.visibility_m > 0) settings->fog_top_m = s.fog.top_height_m - settings->origin.height_m;
  settings->night_sky = s.night_sky;
  std::vector<sample::CloudLayerSettings> layers;
  for (uint32_t i = 0; i < s.cloud_layer_count; ++i) {
    const AtmoCloudLayer& in = s.cloud_layers[i];
    sample::CloudLayerSettings l;
    l.type = static_cast<AtmoCloudLayerType>(in.type);
    l.coverage_oktas = in.coverage_oktas;
    l.base_m = in.base_m;  // above the clouds' origin, which is the airfield datum (MappingInputs)
    l.top_m = in.top_m;
    if (in.area_size_m > 0) l.area_size_km = in.area_size_m / 1000.0;  // else CloudLayerSettings' 20 km, the plugin's
    l.seed = in.seed;
    layers.push_back(l);
  }
  const auto same = [](const sample::CloudLayerSettings& a, const sample::CloudLayerSettings& b) {
    return a.type == b.type && a.coverage_oktas == b.coverage_oktas && a.base_m == b.base_m && a.top_m == b.top_m &&
           a.area_size_km == b.area_size_km && a.seed == b.seed;
  };
  const std::vector<sample::CloudLayerSettings>& old = settings->clouds.layers;
  bool changed = old.size() != layers.size();
  for (size_t i = 0; !changed && i < layers.size(); ++i) changed = !same(old[i], layers[i]);
  settings->clouds.layers = std::move(layers);
  return changed;
}

// The packets' fields the plugin has no input for (docs/CIGI.md's table), said the first time each packet comes.
const char* not_drawn(const cigi::Event& e) {
  return std::visit(
      [](const auto& p) -> const char* {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, cigi::IgControl>) {
          return "IG Control: database, smoothing, last IG frame and entity substitution accepted, not drawn (the "
                 "IG mode is echoed in the Start of Frame; a requested database answers -128)";
        } else if constexpr (std::is_same_v<T, cigi::CelestialControl>) {
          return "Celestial Sphere Control: Sun and Moon enables and star intensity accepted, not drawn (the plugin "
                 "draws the Sun, Moon and stars where they are; star field enable off skips the night sky pass)";
        } else if constexpr (std::is_same_v<T, cigi::AtmosphereControl>) {
          return "Atmosphere Control: model enable, humidity, temperature, winds and pressure accepted, not drawn "
                 "(visibility drawn)";
        } else if constexpr (std::is_same_v<T, cigi::RegionControl>) {
          return "Environmental Region Control: accepted, not drawn (the plugin has no regional weather)";
        } else {
          static_assert(std::is_same_v<T, cigi::WeatherControl>, "a packet without its line");
          return "Weather Control: humidity, temperature, scud, transition bands, winds, lightning, severity, "
                 "pressure, aerosol and the visibility inside clouds accepted, not drawn; regional and entity "
                 "layers and layers 10-255 not drawn; rain to dust (4-9) give only a visibility";
        }
      },
      e);
}

std::string clouds_text(const sample::SceneSettings& s) {
  if (s.clouds.layers.empty()) return "no clouds";
  std::ostringstream t;
  for (size_t i = 0; i < s.clouds.layers.size(); ++i) {
    const sample::CloudLayerSettings& l = s.clouds.layers[i];
    t << (i ? ", " : "") << sample::cloud_type_name(l.type) << ' ' << l.coverage_oktas << " oktas " << l.base_m << "-"
      << l.top_m << " m";
  }
  return t.str();
}

std::string state_json(uint32_t ig_frame, const cigi::DecodeResult& d, const cigi::PluginState& ps,
                       const sample::SceneSettings& s, const std::string& hash_json, const std::string& png) {
  std::ostringstream j;
  j.precision(12);
  j << "{\"ig_frame\":" << ig_frame << ",\"host_frame\":" << ps.frame.host_frame_number << ",\"cigi\":\""
    << int(d.version.major) << '.' << int(d.version.minor) << "\",\"byte_order\":\"" << order_name(d.byte_order)
    << "\",\"utc\":\"" << sample::format_utc(s.utc_posix_s) << "\",\"utc_posix_s\":" << s.utc_posix_s
    << ",\"time_from_cigi\":" << (ps.time_from_cigi ? "true" : "false") << ",\"visibility_m\":" << s.visibility_m
    << ",\"cloud_layers\":[";
  for (size_t i = 0; i < s.clouds.layers.size(); ++i) {
    const sample::CloudLayerSettings& l = s.clouds.layers[i];
    j << (i ? "," : "") << "{\"type\":\"" << sample::cloud_type_name(l.type) << "\",\"coverage_oktas\":"
      << l.coverage_oktas << ",\"base_m\":" << l.base_m << ",\"top_m\":" << l.top_m << ",\"seed\":" << l.seed << "}";
  }
  j << "],\"fog\":{\"visibility_m\":" << ps.fog.visibility_m << ",\"top_height_m\":" << ps.fog.top_height_m
    << "},\"night_sky\":" << (s.night_sky ? "true" : "false") << ",\"state_hash\":" << hash_json
    << ",\"png\":\"" << json_escape(png) << "\"}";
  return j.str();
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"Atmo's CIGI sample IG: renders the environment of a CIGI 3.3 / 4.0 host's messages (UDP) and "
               "answers each host frame with a Start of Frame of the host's CIGI version."};
  app.add_option("--bind", o.bind, "IPv4 address to listen on")->capture_default_str();
  app.add_option("--port", o.port, "UDP port to listen on; 0: an ephemeral one (printed)")->capture_default_str();
  app.add_option("--port-file", o.port_file, "Write the port here once the IG is ready (for tests)");
  app.add_option("--frames", o.frames, "Exit after N rendered frames; 0: no limit")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--idle-timeout", o.idle_timeout_s, "Exit (status 3) after S seconds without a datagram; 0: never")
      ->check(CLI::Range(0.0, 1.0e6))
      ->capture_default_str();
  app.add_option("--out", o.out_dir, "Write each frame as DIR/frame_NNN.png (NNN: the IG frame number)");
  app.add_option("--state-log", o.state_log, "Write one JSON line per frame: the state the frame was drawn with");
  app.add_option("--plugin", o.plugin, "Path of libatmo.so")->capture_default_str();
  app.add_option("--width", o.width, "Width in pixels")->check(CLI::Range(16, 8192))->capture_default_str();
  app.add_option("--height", o.height, "Height in pixels")->check(CLI::Range(16, 8192))->capture_default_str();
  app.add_option("--ev", o.ev100, "Exposure, EV100 (fixed: night is dark)")->capture_default_str();
  app.add_option("--deferred-frames", o.deferred_frames,
                 "A change the host sends at host frame F is drawn from frame F - 1 + D (new air tables, the "
                 "clouds' lighting: AtmoFrameState.deferred_frames); 1: from F; 0: the plugin's 8")
      ->check(CLI::Range(0u, 100000u))
      ->capture_default_str();
  app.add_flag("--verbose", o.verbose, "Print the plugin's debug and info messages");
  if (const auto exit_code = support::parse_command_line(app, argc, argv)) return *exit_code;

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // a line per frame as it happens, also into a pipe or a file

  std::string error;
  UdpSocket socket;
  if (!socket.open(o.bind, o.port, &error)) {
    std::fprintf(stderr, "atmo-cigi-ig: %s\n", error.c_str());
    return 2;
  }
  const std::unique_ptr<support::HeadlessGl> gl = support::HeadlessGl::create(support::HeadlessGl::Profile::Core, &error);
  if (!gl) {
    std::fprintf(stderr, "atmo-cigi-ig: no headless GL context: %s\n", error.c_str());
    return 2;
  }
  sample::SceneSettings settings;
  settings.pose = sample::approach_path(0.0);  // 6 km out on the glide path: sky above, terrain to the horizon
  settings.ev100 = o.ev100;
  settings.deferred_frames = o.deferred_frames;
  settings.clouds.setup = ATMO_CLOUD_SETUP_WAIT;  // each frame drawn with the clouds of its own message
  sample::fall_back_depth_convention(&settings);
  std::unique_ptr<sample::SampleRenderer> renderer;
  try {
    renderer = std::make_unique<sample::SampleRenderer>(o.plugin, &support::HeadlessGl::get_proc_address, o.verbose);
  } catch (const atmo::Error& e) {
    std::fprintf(stderr, "atmo-cigi-ig: %s\n", e.what());
    return 1;
  }
  if (!renderer->gl_init(settings.seed, &error)) {
    std::fprintf(stderr, "atmo-cigi-ig: gl_init: %s\n", error.c_str());
    renderer->gl_shutdown();
    return 1;
  }
  int status = 0;
  std::unique_ptr<support::OffscreenTarget> target = support::OffscreenTarget::create(o.width, o.height, &error);
  if (!target) {
    std::fprintf(stderr, "atmo-cigi-ig: offscreen target: %s\n", error.c_str());
    status = 2;
  }
  if (status == 0 && !o.out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.out_dir, ec);
    if (ec) {
      std::fprintf(stderr, "atmo-cigi-ig: cannot create %s: %s\n", o.out_dir.c_str(), ec.message().c_str());
      status = 2;
    }
  }
  std::ofstream state_log;
  if (status == 0 && !o.state_log.empty()) {
    state_log.open(o.state_log, std::ios::trunc);
    if (!state_log) {
      std::fprintf(stderr, "atmo-cigi-ig: cannot write %s\n", o.state_log.c_str());
      status = 2;
    }
  }
  const uint16_t port = socket.local_port();
  if (status == 0) {
    std::printf("atmo-cigi-ig: GL %s, %s; plugin %s; %dx%d\n", gl->version().c_str(), gl->renderer().c_str(),
                renderer->api().plugin_name, o.width, o.height);
    std::printf("atmo-cigi-ig: listening on %s:%u (CIGI 3.3 or 4.0 host messages; each answered in its version)\n",
                o.bind.c_str(), port);
    if (!o.port_file.empty() && !write_port_file(o.port_file, port, &error)) {
      std::fprintf(stderr, "atmo-cigi-ig: --port-file: %s\n", error.c_str());
      status = 2;
    }
  }

  cigi::EnvironmentState env;
  cigi::MappingInputs inputs;
  inputs.host_utc_posix_s = settings.utc_posix_s;  // until a Celestial Sphere Control sets the time
  inputs.clouds_origin_geodetic[0] = settings.origin.latitude_deg;
  inputs.clouds_origin_geodetic[1] = settings.origin.longitude_deg;
  inputs.clouds_origin_geodetic[2] = settings.origin.height_m;
  std::set<std::string> notes_said;  // to_plugin's notes, each said once
  std::set<size_t> packets_seen;     // kinds of packet received (Event's index), to say once what is not drawn
  uint32_t ig_frame = 0;
  int rendered = 0, refused = 0;
  const auto start = std::chrono::steady_clock::now();
  auto last_datagram = start;
  std::vector<uint8_t> bytes;

  while (status == 0 && !g_stop && (o.frames == 0 || rendered < o.frames)) {
    double wait_s = 1.0e6;
    if (o.idle_timeout_s > 0) {
      wait_s = o.idle_timeout_s -
               std::chrono::duration<double>(std::chrono::steady_clock::now() - last_datagram).count();
      if (wait_s <= 0) {
        std::fprintf(stderr, "atmo-cigi-ig: no datagram for %g s (--idle-timeout): exiting after %d frame(s)\n",
                     o.idle_timeout_s, rendered);
        status = 3;
        break;
      }
    }
    sockaddr_in from{};
    const UdpSocket::Wait w = socket.receive(wait_s, &bytes, &from, &error);
    if (w == UdpSocket::Wait::Timeout || w == UdpSocket::Wait::Interrupted) continue;
    if (w == UdpSocket::Wait::Error) {
      std::fprintf(stderr, "atmo-cigi-ig: %s\n", error.c_str());
      status = 2;
      break;
    }
    last_datagram = std::chrono::steady_clock::now();
    const std::string sender = atmo::cigi_ig::to_string(from);

    const cigi::DecodeResult d = cigi::decode(bytes);
    if (!d.ok()) {
      // Refused whole (the environment unchanged), no frame, no answer: the host's next message goes on.
      ++refused;
      std::printf("atmo-cigi-ig: refused a %zu-byte datagram from %s: %s\n", bytes.size(), sender.c_str(),
                  d.error->message.c_str());
      continue;
    }
    for (const std::string& line : d.log) std::printf("atmo-cigi-ig: %s\n", line.c_str());
    for (const cigi::Event& e : d.events)
      if (packets_seen.insert(e.index()).second) std::printf("atmo-cigi-ig: %s\n", not_drawn(e));
    env.apply(d);
    for (const std::string& line : env.log) std::printf("atmo-cigi-ig: %s\n", line.c_str());
    env.log.clear();

    // Every accepted message is a host frame: its first packet is an IG Control.
    const cigi::IgControl& ig = *env.ig_control;
    const cigi::PluginState ps = cigi::to_plugin(env, inputs);
    for (const std::string& note : ps.notes)
      if (notes_said.insert(note).second) std::printf("atmo-cigi-ig: mapping: %s (said once)\n", note.c_str());
    if (apply_plugin_state(ps, &settings)) {
      std::string message;
      if (!renderer->set_clouds(settings, &message)) {
        std::fprintf(stderr, "atmo-cigi-ig: host frame %u: %s\n", ig.host_frame_number, message.c_str());
        status = 1;
        break;
      }
    }
    const auto frame_start = std::chrono::steady_clock::now();
    const sample::FrameReport report =
        renderer->render_frame(settings, ps.frame.host_frame_number, target->fbo(), o.width, o.height, false);
    if (!report.errors.empty()) {
      for (const std::string& m : report.errors)
        std::fprintf(stderr, "atmo-cigi-ig: host frame %u: %s\n", ig.host_frame_number, m.c_str());
      status = 1;
      break;
    }
    std::string png;
    if (!o.out_dir.empty()) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%03u.png", ig_frame);
      png = name;
      if (!support::write_png((std::filesystem::path(o.out_dir) / name).string(), target->read_color(), &error)) {
        std::fprintf(stderr, "atmo-cigi-ig: %s\n", error.c_str());
        status = 2;
        break;
      }
    }
    std::string hash = "\"none\"";  // JSON: the hash and its parts (which input changed), or "none"
    try {
      AtmoStateHash h{};
      if (renderer->state_hash(&h)) {
        static const char* const parts[ATMO_STATE_HASH_PART_COUNT] = {"frame",  "air",       "clouds", "fog",
                                                                      "lights", "occluders", "view"};
        const auto hex = [](uint64_t v) {
          char text[24];
          std::snprintf(text, sizeof text, "\"%016llx\"", static_cast<unsigned long long>(v));
          return std::string(text);
        };
        hash = "{\"hash\":" + hex(h.hash);
        for (int i = 0; i < ATMO_STATE_HASH_PART_COUNT; ++i) hash += std::string(",\"") + parts[i] + "\":" + hex(h.parts[i]);
        hash += "}";
      }
    } catch (const atmo::Error& e) {
      std::fprintf(stderr, "atmo-cigi-ig: %s\n", e.what());
      status = 1;
      break;
    }
    const double render_ms =  // to the pixels read back (write_png) or the state hash
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frame_start).count();
    if (state_log.is_open()) {
      state_log << state_json(ig_frame, d, ps, settings, hash, png) << '\n';
      state_log.flush();
    }

    // The answer: a Start of Frame in the host's CIGI version and byte order (a host that cannot swap reads it as
    // is; a CIGI 3 host that can reads the magic).
    cigi::StartOfFrame sof;
    sof.minor_version = d.version.major == 3 ? 3 : 0;
    sof.ig_frame_number = ig_frame;
    sof.last_host_frame_number = ig.host_frame_number;
    sof.ig_mode = ig.ig_mode <= 2 ? ig.ig_mode : 1;  // offline maintenance (3) is the IG's own to enter
    sof.database_id = ig.database_id > 0 ? -128 : 0;  // one built-in terrain: a requested database cannot load
    sof.timestamp_valid = true;
    sof.timestamp_ticks = static_cast<uint32_t>(
        std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - start).count() / 10);
    if (!socket.send_to(from, cigi::encode_start_of_frame(sof, d.byte_order, d.version.major), &error)) {
      std::fprintf(stderr, "atmo-cigi-ig: %s\n", error.c_str());
      status = 2;
      break;
    }
    const std::string answer = "Start of Frame " + std::to_string(ig_frame) + " (CIGI " +
                               std::to_string(d.version.major) + ", " + order_name(d.byte_order) + "-endian) to " +
                               sender;
    std::printf("atmo-cigi-ig: frame %u: host frame %u (CIGI %d.%d %s-endian from %s): %s%s, visibility %.0f m, "
                "%s, %s%s; drawn in %.0f ms; %s\n",
                ig_frame, ig.host_frame_number, d.version.major, d.version.minor, order_name(d.byte_order),
                sender.c_str(), sample::format_utc(settings.utc_posix_s).c_str(),
                ps.time_from_cigi ? "" : " (the IG's: no valid CIGI date/time yet)", settings.visibility_m,
                clouds_text(settings).c_str(),
                settings.fog_visibility_m > 0 ? ("fog " + std::to_string(int(settings.fog_visibility_m)) + " m").c_str()
                                              : "no fog",
                settings.night_sky ? "" : ", star field off", render_ms, answer.c_str());
    ++ig_frame;
    ++rendered;
  }
  if (status == 0) {
    std::printf("atmo-cigi-ig: %d frame(s) drawn, %d datagram(s) refused%s\n", rendered, refused,
                g_stop ? " (stopped by a signal)" : "");
  }
  target.reset();
  renderer->gl_shutdown();
  renderer.reset();
  return status;
}
