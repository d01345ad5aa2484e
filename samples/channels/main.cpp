// atmo-channels — a multi-channel host: several display channels side by side
// (a scenario's "channels"), one per MPI rank (or several views of one
// context in one process), flying a scenario's "flight". Rank 0 computes each
// frame's state and broadcasts it; every rank draws its channels and, for its
// right-hand neighbour, a "seam view" (the neighbour's frustum restricted to
// the band they share); rank 0 gathers the bands and the plugin's state
// hashes and checks that every channel drew the same world.
// docs/MULTI_CHANNEL.md has the contract, the options and the checks.
//
//   mpirun -np 3 atmo-channels --scenario FILE [--frames F] [--size WxH] [--out DIR]
//   atmo-channels --views 3 [--view-order 2,0,1] --scenario FILE ...   (one process, three views)
#include <mpi.h>

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "atmo/atmo.hpp"
#include "atmo_host_scene/camera.h"
#include "atmo_host_scene/terrain.h"
#include "atmo_scenario/scenario.h"
#include "atmo_support/cli.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/image.h"
#include "atmo_support/offscreen_target.h"
#include "channel_layout.h"
#include "flight.h"
#include "scenario_setup.h"
#include "seams.h"

namespace {

namespace ch = atmo::channels;
namespace hs = atmo::host_scene;
namespace sc = atmo::scenario;
namespace su = atmo::support;

struct Options {
  std::string scenario_path;
  std::string out_dir = "out/channels";
  std::string plugin_path = ATMO_CHANNELS_DEFAULT_PLUGIN;
  std::int64_t frames = 0;   // 0: the flight's
  std::string size;          // "WxH": replaces channels.width/height
  int views = 0;             // channels in all; 0: the world size under mpirun, else channels.count
  std::string view_order;    // "2,0,1": the order a process creates and draws its channels
  int slow_rank = -1;
  int slow_ms = 0;
  int save_every = 0;        // write images every K frames (and the last); 0: the last only
  bool no_images = false;    // write no images (the CSV still)
  std::string cloud_setup = "stream";
  std::string cloud_draw_mode;  // "": the scenario's render.cloud_draw_mode
  int fault_rank = -1;       // test hook: this rank draws fault_frame a minute late
  std::int64_t fault_frame = -1;
  bool plugin_log = false;   // every plugin log line (else warnings and errors)
  std::uint32_t deferred_frames = 0;  // AtmoFrameState.deferred_frames; 0: the plugin's ATMO_DEFERRED_FRAMES
};

// What every rank knows about the run (the same on every rank: computed from the same argv and file).
struct Run {
  sc::Scenario scenario;
  ch::Layout layout;
  ch::FlightPlan plan;
  int band = 0;                    // columns of the shared band
  int rank = 0, ranks = 1;
  std::vector<int> order;          // the channels in drawing order (all N; each rank keeps its own)
  int first(int r) const { return static_cast<int>(static_cast<long>(r) * layout.count / ranks); }
  int end(int r) const { return first(r + 1); }
  int owner(int channel) const {
    for (int r = 0; r < ranks; ++r)
      if (channel >= first(r) && channel < end(r)) return r;
    return -1;
  }
  int max_owned() const {
    int m = 0;
    for (int r = 0; r < ranks; ++r) m = std::max(m, end(r) - first(r));
    return m;
  }
};

// One view of the plugin and the target it draws into: channel `channel`'s own view, or (seam) the view of
// channel `channel` drawn by the owner of channel - 1: its frustum and viewport into a target `band` wide.
struct Slot {
  int channel = 0;
  bool seam = false;
  std::unique_ptr<atmo::View> view;
  std::unique_ptr<su::OffscreenTarget> target;
};

// A view's state hash as gathered (fixed size: MPI_Gather of bytes).
struct HashRecord {
  std::int32_t channel = -1;  // the channel whose view state was hashed; -1: an empty record
  std::int32_t seam = 0;
  std::int32_t rank = -1;
  std::int32_t result = 0;    // get_state_hash's result; kNoHash: the plugin has none
  std::uint64_t host_frame_number = 0;
  std::uint64_t hash = 0;
  std::uint64_t parts[8] = {};
};
constexpr std::int32_t kNoHash = -1000;
static_assert(std::is_trivially_copyable_v<HashRecord>);

const char* const kPartNames[] = {"frame", "air", "clouds", "fog", "lights", "occluders", "view", "7"};

[[noreturn]] void abort_run(int rank, const std::string& what) {
  std::fprintf(stderr, "atmo-channels [rank %d]: %s\n", rank, what.c_str());
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, 2);
  std::abort();
}

// The plugin's log lines, prefixed with the rank (warnings and errors; everything with --plugin-log).
struct LogSink {
  int rank = 0;
  bool all = false;
};
void log_line(void* user, int32_t severity, const char* message) {
  const LogSink* sink = static_cast<const LogSink*>(user);
  if (!sink->all && severity < ATMO_LOG_WARNING) return;
  static const char* const names[] = {"debug", "info", "warning", "error", "host misbehaving"};
  std::fprintf(stderr, "[rank %d] atmo %s: %s\n", sink->rank, names[std::clamp(severity, 0, 4)], message);
}

bool parse_size(const std::string& text, int* w, int* h) {
  char x = 0;
  std::istringstream in(text);
  return (in >> *w >> x >> *h) && x == 'x' && in.peek() == EOF && *w >= 1 && *h >= 1 && *w <= 8192 && *h <= 8192;
}

// "2,0,1": a permutation of 0..n-1; empty: 0..n-1.
std::optional<std::vector<int>> parse_order(const std::string& text, int n) {
  std::vector<int> order;
  if (text.empty()) {
    order.resize(n);
    std::iota(order.begin(), order.end(), 0);
    return order;
  }
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    try {
      size_t used = 0;
      const int v = std::stoi(item, &used);
      if (used != item.size()) return std::nullopt;
      order.push_back(v);
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < n; ++i)
    if (static_cast<int>(sorted.size()) != n || sorted[i] != i) return std::nullopt;
  return order;
}

// The run's layout: the scenario's channels (or, without them, its first camera's field of view and size,
// three channels, no overlap), the count and size as the command line says.
ch::Layout layout_of(const sc::Scenario& s, const Options& o, int ranks) {
  ch::Layout l;
  if (s.channels) {
    l.count = s.channels->count;
    l.horizontal_fov_deg = s.channels->horizontal_fov_deg;
    l.vertical_fov_deg = s.channels->vertical_fov_deg;
    l.overlap_deg = s.channels->overlap_deg;
    l.width = s.channels->width;
    l.height = s.channels->height;
    l.near_m = s.channels->near_m;
    l.far_m = s.channels->far_m;
  } else {
    const sc::Camera& c = s.cameras.front();
    l.vertical_fov_deg = c.vertical_fov_deg;
    l.horizontal_fov_deg =
        2.0 * glm::degrees(std::atan(std::tan(0.5 * glm::radians(c.vertical_fov_deg)) * c.width / c.height));
    l.width = c.width;
    l.height = c.height;
    l.near_m = c.near_m;
    l.far_m = c.far_m;
  }
  if (o.views > 0)
    l.count = o.views;
  else if (ranks > 1)
    l.count = ranks;
  if (!o.size.empty()) parse_size(o.size, &l.width, &l.height);
  return l;
}

std::string hex(std::uint64_t v) {
  char b[24];
  std::snprintf(b, sizeof b, "%016" PRIx64, v);
  return b;
}

std::string frame_name(std::uint64_t frame) {
  char b[32];
  std::snprintf(b, sizeof b, "frame%05" PRIu64, frame);
  return b;
}

// ---------------------------------------------------------------------------------------------------------
// One process's share: its GL context, the plugin, one context of it, and its channels' views.

class ChannelProcess {
 public:
  ChannelProcess(const Run& run, const Options& options) : run_(run), options_(options) {
    sink_.rank = run.rank;
    sink_.all = options.plugin_log;
    std::string error;
    gl_ = su::HeadlessGl::create(su::HeadlessGl::Profile::Core, &error);
    if (!gl_) throw std::runtime_error("no headless OpenGL context: " + error);
    services_ = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
    services_.gl_get_proc_address = &su::HeadlessGl::get_proc_address;
    services_.log = &log_line;
    services_.user = &sink_;
    plugin_ = std::make_unique<atmo::Plugin>(options.plugin_path, "atmo-channels");
    context_ = std::make_unique<atmo::Context>(*plugin_, &services_);
    context_->gl_init();
    const AtmoPluginApi& api = plugin_->api();
    has_hash_ = api.header.struct_size >= offsetof(AtmoPluginApi, get_state_hash) + sizeof(api.get_state_hash) &&
                api.get_state_hash != nullptr;

    // The views in this process's drawing order: each channel, then (but for the last channel) the seam view of
    // the next channel. Created in that order too.
    for (int c : run.order) {
      if (c < run.first(run.rank) || c >= run.end(run.rank)) continue;
      slots_.push_back(make_slot(c, false));
      if (c + 1 < run.layout.count && run.band > 0) slots_.push_back(make_slot(c + 1, true));
    }
  }

  ~ChannelProcess() {
    slots_.clear();
    if (context_) context_->gl_shutdown();
  }

  std::string describe() const {
    std::string views;
    for (const Slot& s : slots_)
      views += (views.empty() ? "" : ", ") + std::string(s.seam ? "seam of " : "channel ") + std::to_string(s.channel);
    return gl_->renderer() + "; views: " + views;
  }
  bool has_hash() const { return has_hash_; }

  // The world as the scenario starts it, on every rank in the same order: air, clouds, fog.
  void set_initial_world() {
    const sc::Scenario& s = run_.scenario;
    context_->set_atmosphere(atmo::render::atmosphere_state_of(s));
    if (!s.clouds.empty()) set_clouds(s.clouds);
    if (s.fog) context_->set_fog(atmo::render::fog_state_of(s));
  }

  // The Sun's elevation at frame `f` (degrees), from this process's first view.
  double sun_elevation_deg(const ch::FrameState& f) {
    set_frame(f);
    slots_.front().view->set(view_state(f, slots_.front().channel));
    return glm::degrees(slots_.front().view->lighting().sun_elevation_rad);
  }

  // The scenario's lights (set once the exposure, whose white sets the glows' threshold, is known).
  void set_lights(double exposure_scale) {
    const sc::Scenario& s = run_.scenario;
    if (!s.lights) return;
    const hs::Terrain terrain(atmo::render::terrain_of(s));  // its runway's lights, CPU only
    const std::vector<AtmoLightPoint> points = atmo::render::light_points_of(s, terrain);
    context_->set_lights(hs::lights_state_enu(atmo::render::origin_of(s), points,
                                              atmo::render::glow_threshold_cd_m2_of(exposure_scale)));
  }

  // Frame f: its events, set_frame, then every view in order: set_view, the state hash, the passes.
  void draw(const ch::FrameState& f, std::vector<HashRecord>* hashes) {
    for (int i = 0; i < f.event_count; ++i) apply_event(f.events[i]);
    set_frame(f);
    hashes->clear();
    images_.clear();
    for (Slot& slot : slots_) {
      const AtmoViewState state = view_state(f, slot.channel);
      slot.target->clear(0.0f, 0.0f, 0.0f, 1.0f, 1.0f);
      slot.view->set(state);
      HashRecord record;
      record.channel = slot.channel;
      record.seam = slot.seam ? 1 : 0;
      record.rank = run_.rank;
      record.result = kNoHash;
      if (has_hash_) {
        AtmoStateHash h = atmo::make<AtmoStateHash>(ATMO_TYPE_STATE_HASH);
        record.result = plugin_->api().get_state_hash(slot.view->handle(), &h);
        if (record.result < 0) throw std::runtime_error("get_state_hash: " + context_->last_error());
        record.host_frame_number = h.host_frame_number;
        record.hash = h.hash;
        std::copy(std::begin(h.parts), std::end(h.parts), record.parts);
      }
      hashes->push_back(record);
      render_passes(slot);
      images_.push_back(slot.target->read_color());
    }
  }

  // After draw(): channel c's own image, and the seam view's image of channel c (band columns).
  const su::Image& channel_image(int c) const { return image_of(c, false); }
  const su::Image& seam_image(int c) const { return image_of(c, true); }

 private:
  Slot make_slot(int channel, bool seam) {
    Slot s;
    s.channel = channel;
    s.seam = seam;
    s.view = std::make_unique<atmo::View>(*context_, static_cast<uint32_t>(seam ? 1000 + channel : channel));
    std::string error;
    s.target = su::OffscreenTarget::create(seam ? run_.band : run_.layout.width, run_.layout.height, &error);
    if (!s.target) throw std::runtime_error("offscreen target: " + error);
    return s;
  }

  const su::Image& image_of(int c, bool seam) const {
    for (size_t i = 0; i < slots_.size(); ++i)
      if (slots_[i].channel == c && slots_[i].seam == seam) return images_.at(i);
    throw std::logic_error("no view of channel " + std::to_string(c));
  }

  void set_frame(const ch::FrameState& f) {
    AtmoFrameState frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.host_frame_number = f.frame;
    frame.utc_posix_s = f.utc_posix_s;
    frame.dut1_s = f.dut1_s;
    frame.deferred_frames = options_.deferred_frames;
    context_->set_frame(frame);
  }

  void set_clouds(const std::vector<sc::CloudLayer>& layers) {
    std::vector<std::string> paths;
    const std::vector<AtmoCloudLayer> atmo_layers = atmo::render::cloud_layers_of(run_.scenario, layers, &paths);
    AtmoCloudsState state = atmo::render::clouds_state_of(run_.scenario, atmo_layers);
    state.setup = options_.cloud_setup == "wait" ? ATMO_CLOUD_SETUP_WAIT : ATMO_CLOUD_SETUP_STREAM;
    if (context_->set_clouds(state) != ATMO_SUCCESS) throw std::runtime_error("set_clouds: " + context_->last_error());
  }

  void apply_event(int index) {
    const sc::FlightEvent& e = run_.scenario.flight->events.at(static_cast<size_t>(index));
    if (e.atmosphere) context_->set_atmosphere(atmo::render::atmosphere_state_of(*e.atmosphere));
    if (e.clouds) set_clouds(*e.clouds);
  }

  // Channel c's view state at frame f: the eye's pose turned by the channel's yaw, its frustum, the whole
  // channel as viewport (a seam view's target is narrower: GL clips what falls outside it), no depth.
  AtmoViewState view_state(const ch::FrameState& f, int c) const {
    const sc::Scenario& s = run_.scenario;
    hs::ViewSetup setup;
    setup.world_origin = atmo::render::origin_of(s);
    setup.near_m = run_.layout.near_m;
    setup.far_m = run_.layout.far_m;
    setup.output_encoding = ATMO_OUTPUT_LINEAR_HDR;
    setup.exposure_scale = 1.0;  // absolute cd/m^2; the 8-bit encoding is the host's (seams.h)
    // As atmo render (view_setup_of): the layer march's still quality, every pixel every frame.
    if (s.render.cloud_draw_mode == sc::CloudDrawMode::Layer || s.render.cloud_draw_mode == sc::CloudDrawMode::Auto)
      setup.cloud_quality = ATMO_CLOUD_QUALITY_HIGH;
    setup.pose.position_enu_m = glm::dvec3(f.eye_enu_m[0], f.eye_enu_m[1], f.eye_enu_m[2]);
    setup.pose.heading_deg = f.heading_deg;
    setup.pose.pitch_deg = f.pitch_deg;
    setup.vfov_rad = glm::radians(run_.layout.vertical_fov_deg);
    setup.depth_convention = hs::DepthConvention::Standard;
    setup.viewport = {0, 0, run_.layout.width, run_.layout.height};
    AtmoViewState state = hs::make_view_state(setup);
    const glm::dmat4 view = ch::view_from_enu(
        ch::enu_from_channel_camera(f.heading_deg, f.pitch_deg, ch::channel_yaw_deg(run_.layout, c)), setup.pose.position_enu_m);
    const glm::dmat4 projection = ch::channel_projection(run_.layout);
    std::memcpy(state.view_from_world, glm::value_ptr(view), sizeof state.view_from_world);
    std::memcpy(state.clip_from_view, glm::value_ptr(projection), sizeof state.clip_from_view);
    state.depth_texture = 0;
    return state;
  }

  void render_passes(Slot& slot) {
    const bool stars = !run_.scenario.night_sky || run_.scenario.night_sky->stars;
    for (AtmoPassKind pass : {ATMO_PASS_SKY, ATMO_PASS_AERIAL_PERSPECTIVE, ATMO_PASS_NIGHT_SKY, ATMO_PASS_CLOUDS,
                          ATMO_PASS_LIGHT_GLOWS, ATMO_PASS_LIGHT_POINTS}) {
      if (pass == ATMO_PASS_NIGHT_SKY && !stars) continue;
      slot.view->render(pass);
    }
    glFinish();
  }

  const Run& run_;
  const Options& options_;
  LogSink sink_;
  std::unique_ptr<su::HeadlessGl> gl_;
  AtmoHostServices services_{};
  std::unique_ptr<atmo::Plugin> plugin_;
  std::unique_ptr<atmo::Context> context_;
  bool has_hash_ = false;
  std::vector<Slot> slots_;
  std::vector<su::Image> images_;  // per slot, after draw()
};

// ---------------------------------------------------------------------------------------------------------
// Gathering to rank 0.

std::vector<float> pack(const std::vector<const su::Image*>& images) {
  std::vector<float> out;
  for (const su::Image* i : images) out.insert(out.end(), i->rgba.begin(), i->rgba.end());
  return out;
}

// MPI_Gatherv of floats: rank 0 gets every rank's `mine`, counts[r] floats from rank r, in rank order.
std::vector<float> gather_floats(const std::vector<float>& mine, const std::vector<int>& counts, int rank) {
  std::vector<int> displs(counts.size(), 0);
  for (size_t r = 1; r < counts.size(); ++r) displs[r] = displs[r - 1] + counts[r - 1];
  std::vector<float> all(rank == 0 ? static_cast<size_t>(displs.back() + counts.back()) : 0);
  MPI_Gatherv(mine.data(), static_cast<int>(mine.size()), MPI_FLOAT, all.data(), counts.data(), displs.data(),
              MPI_FLOAT, 0, MPI_COMM_WORLD);
  return all;
}

// ---------------------------------------------------------------------------------------------------------
// Rank 0's checks and outputs.

struct FrameCheck {
  bool seams_checked = false;
  bool seams_ok = true;
  ch::BandDiff worst;
  int worst_pair = -1;             // channels worst_pair and worst_pair + 1
  std::string hash_status = "n/a";  // "agree", "DIFFER ..." or "n/a"
  bool hash_ok = true;
  std::uint64_t hash = 0;
};

class Checker {
 public:
  Checker(const Run& run, const Options& options) : run_(run), options_(options) {
    std::filesystem::create_directories(options.out_dir);
    csv_.open(std::filesystem::path(options.out_dir) / "channels.csv");
    if (!csv_) throw std::runtime_error("cannot write " + options.out_dir + "/channels.csv");
    csv_ << "frame,t_s,utc,events,seam_pairs,seam_max_levels,seam_max_rel,seam_values_differing,seams_ok,hash,"
            "hash_status,frame_ms\n";
  }

  // The seams: channel i + 1's band as its owner drew it (its left `band` columns) against the seam view the
  // owner of channel i drew of it. `bands` is the gathered payload (see band_payload).
  FrameCheck check(const ch::FrameState& f, const std::vector<float>& bands, const std::vector<HashRecord>& hashes) {
    FrameCheck out;
    const int n = run_.layout.count, b = run_.band, h = run_.layout.height;
    if (b > 0 && n > 1) {
      out.seams_checked = true;
      const size_t band_floats = static_cast<size_t>(b) * h * 4;
      // Offsets of each channel's left band and of the seam view of each channel in the payload.
      std::vector<size_t> left(n, SIZE_MAX), seam(n, SIZE_MAX);
      size_t at = 0;
      for (int r = 0; r < run_.ranks; ++r) {
        for (int c = run_.first(r); c < run_.end(r); ++c) {
          if (c > 0) left[c] = at, at += band_floats;
          if (c + 1 < n) seam[c + 1] = at, at += band_floats;
        }
      }
      if (at != bands.size()) throw std::logic_error("seam payload of the wrong size");
      for (int c = 1; c < n; ++c) {
        su::Image own = su::make_image(b, h), other = su::make_image(b, h);
        std::copy_n(bands.begin() + static_cast<std::ptrdiff_t>(left[c]), band_floats, own.rgba.begin());
        std::copy_n(bands.begin() + static_cast<std::ptrdiff_t>(seam[c]), band_floats, other.rgba.begin());
        const ch::BandDiff d = ch::compare_bands(other, own, static_cast<float>(f.exposure_scale));
        if (!d.ok()) out.seams_ok = false;
        if (out.worst_pair < 0 || d.max_relative > out.worst.max_relative || d.max_levels > out.worst.max_levels ||
            d.values_nonfinite > out.worst.values_nonfinite) {
          out.worst = d;
          out.worst_pair = c - 1;
        }
      }
    }
    check_hashes(f, hashes, &out);
    return out;
  }

  void record(const ch::FrameState& f, const FrameCheck& c, double frame_ms) {
    ++frames_;
    if (c.seams_checked) {
      ++seam_frames_;
      if (!c.seams_ok) ++seam_failures_;
      worst_levels_ = std::max(worst_levels_, c.worst.max_levels);
      worst_rel_ = std::max(worst_rel_, c.worst.max_relative);
    }
    if (c.hash_status != "n/a") {
      ++hash_frames_;
      if (!c.hash_ok) ++hash_failures_;
    }
    if (f.frame > 0) frame_ms_.push_back(frame_ms);
    std::string events;
    for (int i = 0; i < f.event_count; ++i) events += (i ? " " : "") + event_text(f.events[i]);
    char line[512];
    std::snprintf(line, sizeof line, "frame %4" PRIu64 "  t %9.3f s  %s", f.frame, f.t_s,
                  sc::format_iso8601_utc(f.utc_posix_s).c_str());
    std::string text = line;
    if (!events.empty()) text += "  events: " + events;
    if (c.seams_checked) {
      std::snprintf(line, sizeof line, "  seams: %s max %d levels, rel %.3g (%ld values differ; worst %d|%d)",
                    c.seams_ok ? "ok" : "FAIL", c.worst.max_levels, c.worst.max_relative, c.worst.values_differing,
                    c.worst_pair, c.worst_pair + 1);
      text += line;
    } else {
      text += "  seams: none shared";
    }
    text += "  hash: " + c.hash_status;
    std::snprintf(line, sizeof line, "  %.1f ms", frame_ms);
    text += line;
    std::printf("%s\n", text.c_str());
    std::fflush(stdout);
    csv_ << f.frame << ',' << f.t_s << ',' << sc::format_iso8601_utc(f.utc_posix_s) << ",\"" << events << "\","
         << (c.seams_checked ? run_.layout.count - 1 : 0) << ',' << c.worst.max_levels << ',' << c.worst.max_relative
         << ',' << c.worst.values_differing << ',' << (c.seams_checked ? (c.seams_ok ? "1" : "0") : "") << ','
         << (c.hash_status == "n/a" ? "" : hex(c.hash)) << ",\"" << c.hash_status << "\"," << frame_ms << '\n';
    csv_.flush();
  }

  // The channels' images of frame f (gathered, in channel order): EXR (linear) and PNG (display) per channel,
  // and the stitched panorama as PNG.
  void write_images(const ch::FrameState& f, const std::vector<float>& all) {
    const int n = run_.layout.count, w = run_.layout.width, h = run_.layout.height;
    const size_t floats = static_cast<size_t>(w) * h * 4;
    if (all.size() != floats * n) throw std::logic_error("gathered images of the wrong size");
    std::vector<su::Image> channels;
    std::string error;
    const std::filesystem::path dir(options_.out_dir);
    for (int c = 0; c < n; ++c) {
      su::Image img = su::make_image(w, h);
      std::copy_n(all.begin() + static_cast<std::ptrdiff_t>(floats * c), floats, img.rgba.begin());
      const std::string stem = (dir / ("channel" + std::to_string(c) + "_" + frame_name(f.frame))).string();
      if (!su::write_exr(stem + ".exr", img, &error)) throw std::runtime_error(error);
      if (!su::write_png(stem + ".png", su::tone_map_to_display(img, static_cast<float>(f.exposure_scale)), &error))
        throw std::runtime_error(error);
      channels.push_back(std::move(img));
    }
    const su::Image panorama = ch::stitch(channels, run_.band);
    const std::string path = (dir / ("panorama_" + frame_name(f.frame) + ".png")).string();
    if (!su::write_png(path, su::tone_map_to_display(panorama, static_cast<float>(f.exposure_scale)), &error))
      throw std::runtime_error(error);
    std::fprintf(stderr, "atmo-channels: wrote %s (%dx%d) and %d channel images\n", path.c_str(), panorama.width,
                 panorama.height, n);
  }

  // The summary; true when every check that ran passed.
  bool summary(bool hash_available) const {
    std::vector<double> ms = frame_ms_;
    std::sort(ms.begin(), ms.end());
    const double median = ms.empty() ? 0.0 : ms[ms.size() / 2];
    const double mean = ms.empty() ? 0.0 : std::accumulate(ms.begin(), ms.end(), 0.0) / ms.size();
    std::printf("summary: %d channels (%dx%d, %.2f deg wide, %.2f deg shared: %d columns) on %d process%s, %d frames\n",
                run_.layout.count, run_.layout.width, run_.layout.height, run_.layout.horizontal_fov_deg,
                run_.layout.overlap_deg, run_.band, run_.ranks, run_.ranks == 1 ? "" : "es", frames_);
    if (seam_frames_ > 0)
      std::printf("  seams: %s: %d of %d frames within %d level (8-bit display: the plugin's encoding as "
                  "atmo_support applies it to the linear output) and %.0e relative (linear, floor %.0e cd/m^2); "
                  "worst %d levels, %.3g relative\n",
                  seam_failures_ == 0 ? "PASS" : "FAIL", seam_frames_ - seam_failures_, seam_frames_, ch::kMaxLevels,
                  ch::kMaxRelative, ch::kRelativeFloorCdM2, worst_levels_, worst_rel_);
    else
      std::printf("  seams: not checked (no band is shared: one channel, or no overlap)\n");
    if (!hash_available)
      std::printf("  state hash: not available from this plugin (get_state_hash is NULL): not checked\n");
    else
      std::printf("  state hash: %s: all views agree in %d of %d frames\n", hash_failures_ == 0 ? "PASS" : "FAIL",
                  hash_frames_ - hash_failures_, hash_frames_);
    if (ms.empty())
      std::printf("  wall time per frame: not measured (one frame: the first, with the set-up, is left out)\n");
    else
      std::printf("  wall time per frame (rank 0, frames 1..%d, barrier to barrier): median %.1f ms, mean %.1f ms\n",
                  frames_ - 1, median, mean);
    return seam_failures_ == 0 && hash_failures_ == 0;
  }

 private:
  std::string event_text(int i) const {
    const sc::FlightEvent& e = run_.scenario.flight->events.at(static_cast<size_t>(i));
    std::string t;
    char b[96];
    if (e.atmosphere) {
      std::snprintf(b, sizeof b, "atmosphere#%d(visibility %.0f m)", i, e.atmosphere->visibility_m);
      t += b;
    }
    if (e.clouds) {
      std::snprintf(b, sizeof b, "%sclouds#%d(%zu layers)", t.empty() ? "" : "+", i, e.clouds->size());
      t += b;
    }
    return t;
  }

  void check_hashes(const ch::FrameState& f, const std::vector<HashRecord>& records, FrameCheck* out) const {
    std::vector<HashRecord> views;
    for (const HashRecord& r : records)
      if (r.channel >= 0) views.push_back(r);
    if (views.empty() || std::any_of(views.begin(), views.end(), [](const HashRecord& r) { return r.result == kNoHash; }))
      return;  // n/a
    std::sort(views.begin(), views.end(), [](const HashRecord& a, const HashRecord& b) {
      return a.channel != b.channel ? a.channel < b.channel : a.seam < b.seam;
    });
    const HashRecord& ref = views.front();
    out->hash = ref.hash;
    std::string differ;
    for (const HashRecord& r : views) {
      const std::string who = std::string(r.seam ? "seam view of channel " : "channel ") + std::to_string(r.channel) +
                              " (rank " + std::to_string(r.rank) + ")";
      if (r.host_frame_number != f.frame)
        differ += "; " + who + " hashed host frame " + std::to_string(r.host_frame_number);
      if (r.hash != ref.hash) {
        std::string parts;
        for (int p = 0; p < ATMO_STATE_HASH_VIEW; ++p)
          if (r.parts[p] != ref.parts[p]) parts += (parts.empty() ? "" : ",") + std::string(kPartNames[p]);
        differ += "; " + who + " " + hex(r.hash) + " vs channel 0's " + hex(ref.hash) + " (parts differing: " +
                  (parts.empty() ? "none of frame..occluders?" : parts) + ")";
      }
      if (r.seam) {  // the same view state as the channel's own view: the same VIEW part
        for (const HashRecord& o : views)
          if (!o.seam && o.channel == r.channel && o.parts[ATMO_STATE_HASH_VIEW] != r.parts[ATMO_STATE_HASH_VIEW])
            differ += "; " + who + " view part differs from the channel's own view";
      }
    }
    out->hash_ok = differ.empty();
    out->hash_status = differ.empty() ? "agree (" + hex(ref.hash) + ", " + std::to_string(views.size()) + " views)"
                                      : "DIFFER" + differ;
  }

  const Run& run_;
  const Options& options_;
  std::ofstream csv_;
  int frames_ = 0, seam_frames_ = 0, seam_failures_ = 0, hash_frames_ = 0, hash_failures_ = 0;
  int worst_levels_ = 0;
  double worst_rel_ = 0.0;
  std::vector<double> frame_ms_;
};

// ---------------------------------------------------------------------------------------------------------

int run_channels(const Options& options, int rank, int ranks) {
  // Every rank reads the scenario and works out the same run; only rank 0 speaks.
  Run run;
  run.rank = rank;
  run.ranks = ranks;
  std::string error;
  {
    sc::LoadResult loaded = sc::load_scenario_file(options.scenario_path);
    if (!loaded.scenario) {
      error = loaded.error;
    } else {
      run.scenario = std::move(*loaded.scenario);
      if (!options.cloud_draw_mode.empty()) {
        static const char* const modes[] = {"auto", "direct", "layer", "impostors"};  // sc::CloudDrawMode's order
        for (int m = 0; m < 4; ++m)
          if (options.cloud_draw_mode == modes[m]) run.scenario.render.cloud_draw_mode = static_cast<sc::CloudDrawMode>(m);
      }
      run.layout = layout_of(run.scenario, options, ranks);
      run.plan = ch::flight_plan_of(run.scenario);
      if (options.frames > 0) run.plan.frames = options.frames;
      int w = 0, h = 0;
      if (!options.size.empty() && !parse_size(options.size, &w, &h))
        error = "--size: '" + options.size + "' is not WxH (1 to 8192 each)";
      else if (options.views > 0 && ranks > 1 && options.views < ranks)
        error = "--views " + std::to_string(options.views) + " is fewer channels than the " + std::to_string(ranks) +
                " processes";
      else if (std::string e = ch::layout_error(run.layout); !e.empty())
        error = "channels: " + e;
      else if (std::string e = ch::flight_error(run.scenario); !e.empty())
        error = "flight: " + e;
      else if (options.slow_rank >= ranks)
        error = "--slow-rank " + std::to_string(options.slow_rank) + ": there are " + std::to_string(ranks) + " ranks";
      else if (auto order = parse_order(options.view_order, run.layout.count))
        run.order = *order;
      else
        error = "--view-order '" + options.view_order + "' is not a permutation of 0.." +
                std::to_string(run.layout.count - 1);
      run.band = ch::band_columns(run.layout);
    }
  }
  if (!error.empty()) {
    if (rank == 0) std::fprintf(stderr, "atmo-channels: %s\n", error.c_str());
    return 2;
  }
  const sc::Scenario& s = run.scenario;
  if (rank == 0) {
    std::fprintf(stderr,
                 "atmo-channels: %s: %d channels of %dx%d (%.2f x %.2f deg, %.2f deg shared = %d columns) on %d "
                 "process%s, %" PRId64 " frames at %g Hz\n",
                 options.scenario_path.c_str(), run.layout.count, run.layout.width, run.layout.height,
                 run.layout.horizontal_fov_deg, run.layout.vertical_fov_deg, run.layout.overlap_deg, run.band, ranks,
                 ranks == 1 ? "" : "es", run.plan.frames, run.plan.frame_rate_hz);
    if (s.channels && s.channels->count != run.layout.count)
      std::fprintf(stderr, "atmo-channels: note: %d channels (%s), not the scenario's count %d\n", run.layout.count,
                   options.views > 0 ? "--views" : "the world size", s.channels->count);
    if (!s.objects.empty()) std::fprintf(stderr, "atmo-channels: note: the scenario's objects are not drawn here\n");
    if (s.terrain) std::fprintf(stderr, "atmo-channels: note: no terrain is drawn here (the plugin's Earth is the ground)\n");
  }

  std::unique_ptr<ChannelProcess> process;
  try {
    process = std::make_unique<ChannelProcess>(run, options);
    std::fprintf(stderr, "atmo-channels [rank %d]: %s\n", rank, process->describe().c_str());
    process->set_initial_world();
  } catch (const std::exception& e) {
    abort_run(rank, e.what());
  }

  // The 8-bit encoding's exposure, fixed for the flight: the scenario's, else from the Sun at frame 0 as rank 0
  // sees it (every rank asks its first view, the same calls everywhere; rank 0's answer is broadcast).
  double exposure_scale = 1.0;
  try {
    const ch::FrameState first = ch::frame_state(s, run.plan, 0);
    const double sun_deg = process->sun_elevation_deg(first);
    const double ev100 = s.render.exposure_ev100.value_or(sc::auto_exposure_ev100(sun_deg));
    exposure_scale = hs::exposure_scale_from_ev100(ev100);
    if (rank == 0)
      std::fprintf(stderr, "atmo-channels: Sun %.2f deg up at frame 0; EV100 %.2f for the 8-bit output\n", sun_deg, ev100);
  } catch (const std::exception& e) {
    abort_run(rank, e.what());
  }
  MPI_Bcast(&exposure_scale, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  try {
    process->set_lights(exposure_scale);
  } catch (const std::exception& e) {
    abort_run(rank, e.what());
  }

  // Whether every rank's plugin has get_state_hash.
  int has_hash = process->has_hash() ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &has_hash, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (rank == 0 && !has_hash) std::printf("state hash: not available from this plugin\n");

  std::unique_ptr<Checker> checker;
  if (rank == 0) {
    try {
      checker = std::make_unique<Checker>(run, options);
    } catch (const std::exception& e) {
      abort_run(rank, e.what());
    }
  }

  const int n = run.layout.count;
  const int band_floats = run.band * run.layout.height * 4;
  const int image_floats = run.layout.width * run.layout.height * 4;
  std::vector<int> band_counts(ranks), image_counts(ranks);
  for (int r = 0; r < ranks; ++r) {
    int bands = 0;
    for (int c = run.first(r); c < run.end(r); ++c) bands += (c > 0 ? 1 : 0) + (c + 1 < n ? 1 : 0);
    band_counts[r] = run.band > 0 ? bands * band_floats : 0;
    image_counts[r] = (run.end(r) - run.first(r)) * image_floats;
  }
  const int records_per_rank = 2 * run.max_owned();

  std::vector<HashRecord> hashes;
  for (std::int64_t k = 0; k < run.plan.frames; ++k) {
    const double start = MPI_Wtime();
    ch::FrameState f;
    if (rank == 0) {
      f = ch::frame_state(s, run.plan, k);
      f.exposure_scale = exposure_scale;
      const bool last = k + 1 == run.plan.frames;
      f.save = !options.no_images && (last || (options.save_every > 0 && k % options.save_every == 0)) ? 1 : 0;
    }
    MPI_Bcast(&f, sizeof f, MPI_BYTE, 0, MPI_COMM_WORLD);

    try {
      if (rank == options.slow_rank && options.slow_ms > 0)
        std::this_thread::sleep_for(std::chrono::milliseconds(options.slow_ms));
      ch::FrameState mine = f;
      if (rank == options.fault_rank && static_cast<std::int64_t>(f.frame) == options.fault_frame) {
        mine.utc_posix_s += 60.0;  // the test hook: a rank that draws the wrong time
        std::fprintf(stderr, "atmo-channels [rank %d]: --fault-frame: drawing frame %" PRIu64 " a minute late\n", rank,
                     f.frame);
      }
      process->draw(mine, &hashes);
    } catch (const std::exception& e) {
      abort_run(rank, "frame " + std::to_string(f.frame) + ": " + e.what());
    }

    // The seam bands: for each channel of this rank, in channel order, its own left band and the seam view of
    // the next channel.
    std::vector<float> bands;
    if (run.band > 0) {
      std::vector<su::Image> crops;
      for (int c = run.first(rank); c < run.end(rank); ++c) {
        if (c > 0) crops.push_back(ch::crop_columns(process->channel_image(c), 0, run.band));
        if (c + 1 < n) crops.push_back(process->seam_image(c + 1));
      }
      std::vector<const su::Image*> pointers;
      for (const su::Image& i : crops) pointers.push_back(&i);
      bands = pack(pointers);
    }
    const std::vector<float> all_bands = gather_floats(bands, band_counts, rank);

    hashes.resize(static_cast<size_t>(records_per_rank));  // empty records (channel -1) pad it
    std::vector<HashRecord> all_hashes(rank == 0 ? static_cast<size_t>(records_per_rank) * ranks : 0);
    MPI_Gather(hashes.data(), static_cast<int>(records_per_rank * sizeof(HashRecord)), MPI_BYTE, all_hashes.data(),
               static_cast<int>(records_per_rank * sizeof(HashRecord)), MPI_BYTE, 0, MPI_COMM_WORLD);

    std::vector<float> all_images;
    if (f.save) {
      std::vector<const su::Image*> mine;
      for (int c = run.first(rank); c < run.end(rank); ++c) mine.push_back(&process->channel_image(c));
      all_images = gather_floats(pack(mine), image_counts, rank);
    }

    MPI_Barrier(MPI_COMM_WORLD);  // stands in for the display's swap lock
    const double frame_ms = (MPI_Wtime() - start) * 1e3;

    if (rank == 0) {
      try {
        const FrameCheck c = checker->check(f, all_bands, all_hashes);
        checker->record(f, c, frame_ms);
        if (f.save) checker->write_images(f, all_images);
        std::fprintf(stderr, "atmo-channels: frame %" PRIu64 "/%" PRId64 " done\n", f.frame + 1, run.plan.frames);
      } catch (const std::exception& e) {
        abort_run(rank, e.what());
      }
    }
  }

  int result = 0;
  if (rank == 0) {
    result = checker->summary(has_hash != 0) ? 0 : 1;
    std::printf("atmo-channels: %s\n", result == 0 ? "PASS" : "FAIL");
  }
  MPI_Bcast(&result, 1, MPI_INT, 0, MPI_COMM_WORLD);
  try {
    process.reset();
  } catch (const std::exception& e) {
    abort_run(rank, e.what());
  }
  return result;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);

  Options o;
  CLI::App app{
      "atmo-channels: several display channels, one per MPI rank (or several views in one process), flying a "
      "scenario's flight; checks that the channels agree at their seams and in the plugin's state hash. "
      "docs/MULTI_CHANNEL.md"};
  app.add_option("--scenario", o.scenario_path, "scenario JSON (its \"channels\" and \"flight\")")->required();
  app.add_option("--frames", o.frames, "frames to draw (default: the flight's)")->check(CLI::Range(1, 1000000));
  app.add_option("--size", o.size, "each channel's size WxH (default: the scenario's channels)");
  app.add_option("--out", o.out_dir, "folder for the CSV, channel images and panoramas")->capture_default_str();
  app.add_option("--views", o.views,
                 "channels in all (default: one per process under mpirun, else the scenario's count); "
                 "a process draws its share as views of one context")
      ->check(CLI::Range(1, 64));
  app.add_option("--view-order", o.view_order, "the order each process creates and draws its views, e.g. 2,0,1");
  app.add_option("--slow-rank", o.slow_rank, "this rank sleeps --slow-ms before drawing each frame")->check(CLI::NonNegativeNumber);
  app.add_option("--slow-ms", o.slow_ms, "milliseconds the slow rank sleeps")->check(CLI::Range(0, 60000));
  app.add_option("--deferred-frames", o.deferred_frames,
                 "frames between asking for work off the host's thread and its effect (AtmoFrameState.deferred_frames; "
                 "0: the plugin's default)")
      ->check(CLI::Range(0, 100000));
  app.add_option("--save-every", o.save_every, "write the images every K frames (and the last; 0: the last only)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--no-images", o.no_images, "write no images (the CSV only)");
  app.add_option("--cloud-setup", o.cloud_setup, "AtmoCloudSetup of the clouds: stream (real time) or wait")
      ->check(CLI::IsMember({"stream", "wait"}))
      ->capture_default_str();
  app.add_option("--cloud-draw-mode", o.cloud_draw_mode,
                 "AtmoCloudDrawMode: auto, direct, layer or impostors (default: the scenario's render.cloud_draw_mode)")
      ->check(CLI::IsMember({"auto", "direct", "layer", "impostors"}));
  app.add_option("--plugin", o.plugin_path, "libatmo.so to load")->capture_default_str();
  app.add_flag("--plugin-log", o.plugin_log, "print every plugin log line (default: warnings and errors)");
  app.add_option("--fault-rank", o.fault_rank, "test hook: this rank draws --fault-frame a minute late")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--fault-frame", o.fault_frame, "test hook: the frame --fault-rank gets wrong")
      ->check(CLI::NonNegativeNumber);

  int code = 0;
  try {
    app.parse(argc, argv);
    code = -1;
  } catch (const CLI::ParseError& e) {
    // Every rank parsed the same argv; one message.
    if (rank == 0) code = app.exit(e) == 0 ? 0 : 2;
    else code = e.get_exit_code() == 0 ? 0 : 2;
  }
  if (code < 0) code = run_channels(o, rank, ranks);
  MPI_Finalize();
  return code;
}
