// The context's lookup tables after the first frame are rebuilt on a worker
// thread: frames never wait for them. The plugin is linked statically here
// (atmo_plugin_static) so the test can hold the worker on a latch through its
// test hook and look at what the context draws with (tables_version, tables_key);
// it is driven through the same C ABI function table a host gets.
//
// Proved: (a) while the worker is held, render_pass and get_lighting return
// with the old tables and the old air (the image and the light are bit-equal
// to the frame before the change); the next call after the build ends swaps
// the new ones in, and they are the tables a fresh context makes. (b) three
// quick changes while a build runs build twice and end with the newest air.
// (c) destroy_context during a build cancels it and joins. (d) progress lines
// reach the host's log, at info level, always on the host's thread.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "abi/objects.h"
#include "abi/scene_inputs.h"
#include "atmo/atmo.hpp"
#include "atmo_support/headless_gl.h"
#include "atmo_support/offscreen_target.h"

namespace {

using atmo::support::HeadlessGl;
using atmo::support::Image;
using atmo::support::OffscreenTarget;

constexpr int kWidth = 48;
constexpr int kHeight = 32;

// The host's log: every line with its severity and the thread it came on.
struct LogCapture {
  struct Line {
    int32_t severity;
    std::string text;
    std::thread::id thread;
  };
  std::mutex mutex;
  std::vector<Line> lines;

  static void log(void* user, int32_t severity, const char* message) {
    auto* self = static_cast<LogCapture*>(user);
    std::lock_guard<std::mutex> lock(self->mutex);
    self->lines.push_back({severity, message, std::this_thread::get_id()});
  }
  int count(const std::string& text, int32_t severity = -1) {
    std::lock_guard<std::mutex> lock(mutex);
    int n = 0;
    for (const Line& l : lines)
      if (l.text.find(text) != std::string::npos && (severity < 0 || l.severity == severity)) ++n;
    return n;
  }
  bool all_on(std::thread::id thread) {
    std::lock_guard<std::mutex> lock(mutex);
    for (const Line& l : lines)
      if (l.thread != thread) return false;
    return true;
  }
  std::string dump() {
    std::lock_guard<std::mutex> lock(mutex);
    std::string all;
    for (const Line& l : lines) all += "  [" + std::to_string(l.severity) + "] " + l.text + "\n";
    return all;
  }
};

// Holds the worker at the start of its builds until released (or cancelled).
struct Gate {
  std::mutex mutex;
  std::condition_variable changed;
  bool open = false;
  int entered = 0, cancelled = 0;

  void hold(const std::atomic<bool>& cancel) {
    std::unique_lock<std::mutex> lock(mutex);
    ++entered;
    changed.notify_all();
    while (!open && !cancel.load()) changed.wait_for(lock, std::chrono::milliseconds(1));
    if (!open) ++cancelled;
  }
  void wait_entered(int n) {
    std::unique_lock<std::mutex> lock(mutex);
    changed.wait(lock, [&] { return entered >= n; });
  }
  void release() {
    std::lock_guard<std::mutex> lock(mutex);
    open = true;
    changed.notify_all();
  }
  std::function<void(const std::atomic<bool>&)> hook() {
    return [this](const std::atomic<bool>& cancel) { hold(cancel); };
  }
};

void copy(const glm::dmat4& m, double out[16]) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[c * 4 + r] = m[c][r];
}

AtmoViewState view_state(double latitude_deg = 47.26) {
  auto vs = atmo::make<AtmoViewState>(ATMO_TYPE_VIEW_STATE);
  vs.eye_kind = ATMO_POSITION_GEODETIC;
  vs.eye_geodetic[0] = latitude_deg;
  vs.eye_geodetic[1] = 11.35;
  vs.eye_geodetic[2] = 300.0;
  vs.world_frame = ATMO_WORLD_ENU;
  vs.world_origin_geodetic[0] = latitude_deg;
  vs.world_origin_geodetic[1] = 11.35;
  const double h = glm::radians(250.0), p = glm::radians(5.0);
  glm::dvec3 forward(std::sin(h) * std::cos(p), std::cos(h) * std::cos(p), std::sin(p));
  copy(glm::lookAt(glm::dvec3(0.0), forward, glm::dvec3(0, 0, 1)), vs.view_from_world);
  copy(glm::perspective(glm::radians(60.0), double(kWidth) / kHeight, 1.0, 1e5), vs.clip_from_view);
  vs.viewport[2] = kWidth;
  vs.viewport[3] = kHeight;
  vs.exposure_scale = 1.0;
  return vs;
}

// The plugin through its function table (no dlopen: linked into this test), one
// context and one view, optionally with GL.
struct Host {
  AtmoPluginApi api{};
  LogCapture log;
  AtmoHostServices services = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  HeadlessGl* gl = nullptr;
  AtmoContext ctx = nullptr;
  AtmoView view = nullptr;

  explicit Host(HeadlessGl* gl_context = nullptr, double visibility_m = 40000.0) : gl(gl_context) {
    auto info = atmo::make<AtmoNegotiateInfo>(ATMO_TYPE_NEGOTIATE_INFO);
    info.min_interface_version = info.max_interface_version = ATMO_INTERFACE_VERSION_1;
    api.header = ATMO_HEADER(ATMO_TYPE_PLUGIN_API, AtmoPluginApi);
    EXPECT_EQ(atmo_negotiate(&info, &api), ATMO_SUCCESS);
    services.user = &log;
    services.log = &LogCapture::log;
    if (gl) services.gl_get_proc_address = &HeadlessGl::get_proc_address;
    auto create = atmo::make<AtmoContextCreateInfo>(ATMO_TYPE_CONTEXT_CREATE_INFO);
    create.services = &services;
    EXPECT_EQ(api.create_context(&create, &ctx), ATMO_SUCCESS);
    if (gl) {
      EXPECT_EQ(api.gl_init(ctx), ATMO_SUCCESS) << api.last_error(ctx);
    }
    auto view_info = atmo::make<AtmoViewCreateInfo>(ATMO_TYPE_VIEW_CREATE_INFO);
    EXPECT_EQ(api.create_view(ctx, &view_info, &view), ATMO_SUCCESS);
    set_air(visibility_m);
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = 1718989800.0;  // 2024-06-21T17:10Z: low sun, where haze shows most
    EXPECT_EQ(api.set_frame(ctx, &frame), ATMO_SUCCESS);
    auto vs = view_state();
    EXPECT_EQ(api.set_view(view, &vs), ATMO_SUCCESS);
  }
  ~Host() { destroy(); }

  void destroy() {
    if (!ctx) return;
    api.destroy_view(view);
    if (gl) api.gl_shutdown(ctx);
    api.destroy_context(ctx);
    ctx = nullptr;
  }
  void set_air(double visibility_m) {
    auto air = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
    air.visibility_m = visibility_m;
    ASSERT_EQ(api.set_atmosphere(ctx, &air), ATMO_SUCCESS) << api.last_error(ctx);
  }
  AtmoLighting lighting() {
    auto l = atmo::make<AtmoLighting>(ATMO_TYPE_LIGHTING);
    EXPECT_EQ(api.get_lighting(view, &l), ATMO_SUCCESS) << api.last_error(ctx);
    return l;
  }
  Image render(OffscreenTarget& target) {
    target.clear(0, 0, 0, 0);
    auto pass = atmo::make<AtmoPassInfo>(ATMO_TYPE_PASS_INFO);
    pass.pass = ATMO_PASS_SKY;
    EXPECT_EQ(api.render_pass(view, &pass), ATMO_SUCCESS) << api.last_error(ctx);
    return target.read_color();
  }
  // The next host frame (the same time): deferred work is due by host_frame_number.
  void next_frame() {
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = 1718989800.0;
    frame.host_frame_number = ++frame_number;
    EXPECT_EQ(api.set_frame(ctx, &frame), ATMO_SUCCESS);
  }
  uint64_t frame_number = 0;
  AtmoContext_T& inside() { return *ctx; }
  atmo::abi::TableWorker& worker() { return ctx->table_worker; }
};

bool same_light(const AtmoLighting& a, const AtmoLighting& b) {
  for (int i = 0; i < 3; ++i) {
    if (a.sun_illuminance_lux[i] != b.sun_illuminance_lux[i]) return false;
    if (a.sky_illuminance_horizontal_lux[i] != b.sky_illuminance_horizontal_lux[i]) return false;
    if (a.sky_average_radiance[i] != b.sky_average_radiance[i]) return false;
  }
  return true;
}

bool same_image(const Image& a, const Image& b) { return a.rgba == b.rgba; }

// A headless GL context and an offscreen target.
struct GlTarget {
  std::string error;
  std::unique_ptr<HeadlessGl> gl = HeadlessGl::create(HeadlessGl::Profile::Core, &error);
  std::unique_ptr<OffscreenTarget> target = gl ? OffscreenTarget::create(kWidth, kHeight, &error) : nullptr;
  bool ok() const { return gl && target; }
};

}  // namespace

TEST(TableWorker, FirstUseBuildsOnTheCallingThreadWithProgressInTheLog) {
  Host host;
  EXPECT_EQ(host.inside().tables_version, 0u);
  host.lighting();
  EXPECT_EQ(host.inside().tables_version, 1u);
  EXPECT_EQ(host.inside().tables_key.visibility_m, 40000.0);
  EXPECT_EQ(host.worker().builds_started(), 0u);  // no worker for the first tables
  EXPECT_EQ(atmo::abi::describe(host.inside().tables_key).rfind("visibility 40000 m, aerosol scale height 1200 m, "
                                                             "ground albedo 0.1, sphere radius 63",
                                                             0),
            0u);
  EXPECT_EQ(host.log.count("atmo: building atmosphere tables (" + atmo::abi::describe(host.inside().tables_key) +
                               ") on the calling thread, before the first frame",
                           ATMO_LOG_INFO),
            1)
      << host.log.dump();
  EXPECT_EQ(host.log.count("atmo: transmittance 256x64 ... done in", ATMO_LOG_INFO), 1) << host.log.dump();
  EXPECT_EQ(host.log.count("atmo: multiple scattering 64x32 ... done in", ATMO_LOG_INFO), 1) << host.log.dump();
  for (const char* quarter : {"25 %", "50 %", "75 %"}) {
    EXPECT_EQ(host.log.count(std::string("atmo: transmittance 256x64: ") + quarter, ATMO_LOG_DEBUG), 1);
    EXPECT_EQ(host.log.count(std::string("atmo: multiple scattering 64x32: ") + quarter, ATMO_LOG_DEBUG), 1);
  }
  EXPECT_TRUE(host.log.all_on(std::this_thread::get_id()));
  std::printf("%s", host.log.dump().c_str());
}

// (a) and (d)
// New tables take effect ATMO_DEFERRED_FRAMES host frames after they were asked for: not before, even when
// the worker is done early (a fast channel must not switch before a slow one), and not later.
TEST(TableWorker, FramesKeepTheOldTablesUntilTheirFrameThenSwap) {
  GlTarget g;
  ASSERT_TRUE(g.ok()) << g.error;
  std::unique_ptr<HeadlessGl>& gl = g.gl;
  std::unique_ptr<OffscreenTarget>& target = g.target;
  Host host(gl.get());
  const Image clear_image = host.render(*target);
  const AtmoLighting clear_light = host.lighting();
  ASSERT_EQ(host.inside().tables_version, 1u);
  ASSERT_EQ(host.inside().uploaded_tables_version, 1u);

  Gate gate;
  host.worker().test_before_build = gate.hook();
  host.set_air(5000.0);  // set_atmosphere starts the build at once
  gate.wait_entered(1);

  // The worker is held: every call returns, drawing and lighting with the old air.
  for (int frame = 0; frame < 3; ++frame) {
    host.next_frame();
    const Image image = host.render(*target);
    EXPECT_TRUE(same_image(image, clear_image)) << "frame " << frame;
    EXPECT_TRUE(same_light(host.lighting(), clear_light)) << "frame " << frame;
    EXPECT_EQ(host.inside().tables_version, 1u);
    EXPECT_EQ(host.inside().uploaded_tables_version, 1u);
    EXPECT_EQ(host.inside().tables_key.visibility_m, 40000.0);
    EXPECT_TRUE(host.worker().busy());
    EXPECT_EQ(host.worker().progress(), 0.0);
  }

  gate.release();
  host.worker().wait_idle();  // the tables are built; nothing is swapped before their frame
  EXPECT_EQ(host.inside().tables_version, 1u);
  while (host.frame_number + 1 < ATMO_DEFERRED_FRAMES) {
    host.next_frame();
    EXPECT_TRUE(same_image(host.render(*target), clear_image)) << "frame " << host.frame_number;
    EXPECT_EQ(host.inside().tables_version, 1u);
  }
  host.next_frame();  // asked for at frame 0: in use from frame ATMO_DEFERRED_FRAMES
  EXPECT_EQ(host.frame_number, uint64_t(ATMO_DEFERRED_FRAMES));
  const Image hazy_image = host.render(*target);
  EXPECT_EQ(host.inside().tables_version, 2u);
  EXPECT_EQ(host.inside().uploaded_tables_version, 2u);
  EXPECT_EQ(host.inside().tables_key.visibility_m, 5000.0);
  EXPECT_FALSE(same_image(hazy_image, clear_image));
  EXPECT_FALSE(same_light(host.lighting(), clear_light));
  EXPECT_EQ(host.worker().builds_started(), 1u);

  // What it swapped in is what a context made with that air from the start draws.
  Host fresh(gl.get(), 5000.0);
  EXPECT_TRUE(same_image(fresh.render(*target), hazy_image));
  EXPECT_TRUE(same_light(fresh.lighting(), host.lighting()));
  EXPECT_EQ(fresh.inside().transmittance.texels, host.inside().transmittance.texels);
  EXPECT_EQ(fresh.inside().multiple_scattering.texels, host.inside().multiple_scattering.texels);

  // (d) The worker's lines reached the host's log, on the host's thread only.
  EXPECT_EQ(host.log.count("atmo: building atmosphere tables (visibility 5000 m", ATMO_LOG_INFO), 1) << host.log.dump();
  EXPECT_EQ(host.log.count("on a worker thread; frames keep the current air until they are ready"), 1);
  EXPECT_EQ(host.log.count("atmo: transmittance 256x64 ... done in", ATMO_LOG_INFO), 2);
  EXPECT_EQ(host.log.count("atmo: multiple scattering 64x32 ... done in", ATMO_LOG_INFO), 2);
  EXPECT_EQ(host.log.count("atmo: multiple scattering 64x32: 75 %", ATMO_LOG_DEBUG), 2);
  EXPECT_EQ(host.log.count("atmo: atmosphere tables (" + atmo::abi::describe(host.inside().tables_key) +
                               ") in use from host frame " + std::to_string(ATMO_DEFERRED_FRAMES) +
                               " (asked for at frame 0), built in ",
                           ATMO_LOG_INFO),
            1)
      << host.log.dump();
  EXPECT_TRUE(host.log.all_on(std::this_thread::get_id()));
  std::printf("%s", host.log.dump().c_str());
}

// At their frame the new tables are waited for: a slow machine (here a worker held until 200 ms after the frame
// began) still switches on the same frame as the others.
TEST(TableWorker, TheDueFrameWaitsForASlowWorker) {
  GlTarget g;
  ASSERT_TRUE(g.ok()) << g.error;
  std::unique_ptr<HeadlessGl>& gl = g.gl;
  std::unique_ptr<OffscreenTarget>& target = g.target;
  Host host(gl.get());
  const Image clear_image = host.render(*target);
  Gate gate;
  host.worker().test_before_build = gate.hook();
  host.set_air(5000.0);
  gate.wait_entered(1);
  while (host.frame_number + 1 < ATMO_DEFERRED_FRAMES) {
    host.next_frame();
    EXPECT_TRUE(same_image(host.render(*target), clear_image));
  }
  std::thread slow([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    gate.release();
  });
  host.next_frame();
  const Image due = host.render(*target);
  slow.join();
  EXPECT_EQ(host.inside().tables_key.visibility_m, 5000.0);
  EXPECT_EQ(host.inside().tables_version, 2u);
  Host fresh(gl.get(), 5000.0);
  EXPECT_TRUE(same_image(fresh.render(*target), due)) << "the due frame draws the new air";
}

// Two channels, one of whose machine builds tables slowly (its worker sleeps 600 ms first): every frame draws
// the same pixels and hashes the same state on both, before, at and after the switch.
TEST(TableWorker, ASlowChannelSwitchesOnTheSameFrameAsAFastOne) {
  GlTarget g;
  ASSERT_TRUE(g.ok()) << g.error;
  std::unique_ptr<HeadlessGl>& gl = g.gl;
  std::unique_ptr<OffscreenTarget>& target = g.target;
  Host fast(gl.get()), slow(gl.get());
  fast.render(*target);
  slow.render(*target);
  slow.worker().test_before_build = [](const std::atomic<bool>&) {
    std::this_thread::sleep_for(std::chrono::milliseconds(600));
  };
  fast.set_air(5000.0);
  slow.set_air(5000.0);
  auto hash = [](Host& h) {
    auto out = atmo::make<AtmoStateHash>(ATMO_TYPE_STATE_HASH);
    EXPECT_EQ(h.api.get_state_hash(h.view, &out), ATMO_SUCCESS);
    return out.hash;
  };
  for (uint64_t f = 1; f <= ATMO_DEFERRED_FRAMES + 1; ++f) {
    fast.next_frame();
    slow.next_frame();
    EXPECT_EQ(hash(fast), hash(slow)) << "frame " << f;
    EXPECT_TRUE(same_image(fast.render(*target), slow.render(*target))) << "frame " << f;
    EXPECT_EQ(fast.inside().tables_version, slow.inside().tables_version) << "frame " << f;
  }
  EXPECT_EQ(slow.inside().tables_key.visibility_m, 5000.0);
}

// (b)
TEST(TableWorker, ChangesWhileABuildRunsBuildOnlyTheRunningAndTheNewest) {
  Host host;
  host.lighting();
  Gate gate;
  host.worker().test_before_build = gate.hook();
  host.set_air(5000.0);
  gate.wait_entered(1);
  for (double visibility : {10000.0, 15000.0, 20000.0}) {
    host.set_air(visibility);
    host.lighting();
    EXPECT_EQ(host.inside().tables_version, 1u);
  }
  EXPECT_EQ(host.worker().builds_started(), 1u);
  gate.release();
  atmo::abi::wait_for_tables(&host.inside());
  EXPECT_EQ(host.worker().builds_started(), 2u);  // 5 km (running) and 20 km (the newest); 10 and 15 km never
  EXPECT_EQ(host.inside().tables_key.visibility_m, 20000.0);
  EXPECT_EQ(host.inside().tables_version, 2u);
  EXPECT_FALSE(host.worker().busy());
  EXPECT_EQ(host.log.count("atmo: building atmosphere tables (visibility 10000 m"), 0);
  EXPECT_EQ(host.log.count("atmo: building atmosphere tables (visibility 15000 m"), 0);

  Host fresh(nullptr, 20000.0);
  EXPECT_TRUE(same_light(fresh.lighting(), host.lighting()));
  EXPECT_TRUE(host.log.all_on(std::this_thread::get_id()));
}

TEST(TableWorker, GoingBackToTheAirInUseCancelsTheBuild) {
  Host host;
  host.lighting();
  Gate gate;
  host.worker().test_before_build = gate.hook();
  host.set_air(5000.0);
  gate.wait_entered(1);
  host.set_air(40000.0);  // back: the running build is cancelled (the gate sees the flag)
  atmo::abi::wait_for_tables(&host.inside());
  EXPECT_EQ(gate.cancelled, 1);
  EXPECT_EQ(host.inside().tables_version, 1u);
  EXPECT_EQ(host.inside().tables_key.visibility_m, 40000.0);
  atmo::abi::TableKey hazy = host.inside().tables_key;
  hazy.visibility_m = 5000.0;
  EXPECT_EQ(host.log.count("atmo: atmosphere table build (" + atmo::abi::describe(hazy) + ") cancelled"), 1)
      << host.log.dump();
}

// A moved eye (a new model sphere) is a new key too; wait_for_tables with the view asks for it.
TEST(TableWorker, ANewSphereIsBuiltOnTheWorkerAndWaitForTablesWithTheViewGetsIt) {
  Host host;
  host.lighting();
  const double radius = host.inside().tables_key.radius_m;
  auto equator = view_state(0.0);
  ASSERT_EQ(host.api.set_view(host.view, &equator), ATMO_SUCCESS);
  host.lighting();
  EXPECT_EQ(host.inside().tables_key.radius_m, radius);  // still the old sphere, while the worker builds
  atmo::abi::wait_for_tables(&host.inside(), host.view);
  EXPECT_EQ(host.inside().tables_version, 2u);
  EXPECT_NE(host.inside().tables_key.radius_m, radius);
  std::printf("[ tables ] sphere radius at 47.26 N: %.0f km, at the equator: %.0f km\n", radius / 1000.0,
              host.inside().tables_key.radius_m / 1000.0);
}

// (c) The worker is held inside a build; destroy_context must cancel and join it
// (with no cancellation this test would hang), and nothing leaks (ASan/LSan).
TEST(TableWorker, DestroyingTheContextDuringABuildCancelsAndJoins) {
  Host host;
  host.lighting();
  Gate gate;
  host.worker().test_before_build = gate.hook();
  host.set_air(5000.0);
  gate.wait_entered(1);
  LogCapture& log = host.log;
  const auto start = std::chrono::steady_clock::now();
  host.destroy();
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(gate.cancelled, 1);
  EXPECT_EQ(log.count("atmo: atmosphere table build (visibility 5000 m", ATMO_LOG_INFO), 1) << log.dump();
  EXPECT_EQ(log.count("cancelled (context destroyed)"), 1) << log.dump();
  std::printf("[ tables ] destroy_context with a held build returned in %.1f ms\n", ms);
}

// The same with the worker inside the table loops (no hook): the stop flag is
// checked per row, so destroy_context does not wait for the build to end.
TEST(TableWorker, DestroyingTheContextWhileTheTablesAreComputedReturns) {
  Host host;
  const auto t0 = std::chrono::steady_clock::now();
  host.lighting();
  const double build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  host.set_air(5000.0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (host.worker().progress() == 0.0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  const double fraction = host.worker().progress();
  const auto start = std::chrono::steady_clock::now();
  host.destroy();
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::printf("[ tables ] destroy_context with the worker %.0f %% through a build returned in %.1f ms "
              "(a whole build takes %.0f ms here)\n",
              100.0 * fraction, ms, build_ms);
  EXPECT_GT(fraction, 0.0);
}
