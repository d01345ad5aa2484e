// The checks of `atmo validate`. Each builds what it needs from nothing (it
// runs in a fresh process), talks to the plugin only through the C ABI, and
// says what it saw when it fails.
#include <glad/gl.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <memory>
#include <sstream>
#include <thread>
#include <vector>

#include "atmo/atmo.hpp"
#include "atmo/atmo_loader.h"
#include "atmo_support/example_view.h"
#include "atmo_support/gl_state.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/image_metrics.h"
#include "atmo_support/offscreen_target.h"
#include "validator.h"

namespace atmo::validate {

namespace {

using support::HeadlessGl;
using support::OffscreenTarget;

CheckResult pass(const std::string& note = "") { return {true, note}; }
CheckResult fail(const std::string& why) { return {false, why}; }

struct Plugin {
  AtmoLoadedPlugin loaded{};
  const AtmoPluginApi& api() const { return loaded.api; }
  ~Plugin() { atmo_unload_plugin(&loaded); }
};

// Loads with [1,1]; on failure returns the loader's message.
std::string load(const std::string& path, Plugin* p) {
  AtmoResult r = atmo_load_plugin(path.c_str(), 1, 1, "atmo validate", &p->loaded);
  return r == ATMO_SUCCESS ? std::string() : std::string(p->loaded.error);
}

std::string name(const Plugin& p, AtmoResult r) { return p.api().result_string(r); }

std::string expect(const Plugin& p, AtmoResult got, AtmoResult want, const std::string& what) {
  if (got == want) return {};
  return what + " returned " + name(p, got) + ", expected " + name(p, want);
}

using atmo::make;  // zeroed struct with its header filled (host SDK)

// A valid frame and view: Innsbruck at noon, looking north.
AtmoFrameState valid_frame() {
  auto f = make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  f.utc_posix_s = 1718964000.0;  // 2024-06-21T10:00:00Z
  return f;
}

AtmoViewState valid_view(int width, int height, unsigned depth_texture) {
  return support::example_view_state(width, height, depth_texture);
}

// Plugin messages are expected in these checks (they provoke errors); keep
// them out of the report. Count them so a check can assert they arrived.
std::atomic<long> g_quiet_messages{0};
void quiet_log(void*, int32_t, const char*) { ++g_quiet_messages; }

// Everything a drawing check needs: GL, plugin, context, view.
struct Session {
  Plugin plugin;
  std::unique_ptr<HeadlessGl> gl;
  AtmoHostServices services = make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  AtmoContext context = nullptr;
  AtmoView view = nullptr;
  std::string error;

  bool open(const std::string& path, HeadlessGl::Profile profile = HeadlessGl::Profile::Core, bool init_gl = true) {
    error = load(path, &plugin);
    if (!error.empty()) return false;
    gl = HeadlessGl::create(profile, &error);
    if (!gl) {
      error = "no headless GL context: " + error;
      return false;
    }
    services.gl_get_proc_address = &HeadlessGl::get_proc_address;
    services.log = &quiet_log;
    auto info = make<AtmoContextCreateInfo>(ATMO_TYPE_CONTEXT_CREATE_INFO);
    info.services = &services;
    AtmoResult r = plugin.api().create_context(&info, &context);
    if (r != ATMO_SUCCESS) return fail_with("create_context", r);
    if (init_gl && (r = plugin.api().gl_init(context)) != ATMO_SUCCESS) return fail_with("gl_init", r);
    auto vinfo = make<AtmoViewCreateInfo>(ATMO_TYPE_VIEW_CREATE_INFO);
    if ((r = plugin.api().create_view(context, &vinfo, &view)) != ATMO_SUCCESS) return fail_with("create_view", r);
    return true;
  }
  bool fail_with(const char* what, AtmoResult r) {
    error = std::string(what) + " failed: " + name(plugin, r) + ": " + plugin.api().last_error(context);
    return false;
  }
  AtmoResult render(AtmoPassKind pass) {
    auto info = make<AtmoPassInfo>(ATMO_TYPE_PASS_INFO);
    info.pass = pass;
    return plugin.api().render_pass(view, &info);
  }
  ~Session() {
    if (!plugin.loaded.library) return;
    if (view) plugin.api().destroy_view(view);
    if (context) {
      plugin.api().gl_shutdown(context);
      plugin.api().destroy_context(context);
    }
  }
};

// Renders the sky into a small target and returns it.
bool render_sky_image(Session& s, int size, support::Image* out, std::string* why) {
  auto target = OffscreenTarget::create(size, size, why);
  if (!target) return false;
  target->bind();
  target->clear(0, 0, 0, 1);
  auto frame = valid_frame();
  auto view = valid_view(size, size, 0);
  AtmoResult r;
  if ((r = s.plugin.api().set_frame(s.context, &frame)) != ATMO_SUCCESS ||
      (r = s.plugin.api().set_view(s.view, &view)) != ATMO_SUCCESS || (r = s.render(ATMO_PASS_SKY)) != ATMO_SUCCESS) {
    *why = "rendering the sky failed: " + name(s.plugin, r) + ": " + s.plugin.api().last_error(s.context);
    return false;
  }
  *out = target->read_color();
  return true;
}

// ---------------------------------------------------------------- negotiation

AtmoNegotiateInfo negotiate_info(uint32_t lo, uint32_t hi) {
  auto info = make<AtmoNegotiateInfo>(ATMO_TYPE_NEGOTIATE_INFO);
  info.min_interface_version = lo;
  info.max_interface_version = hi;
  info.host_name = "atmo validate";
  return info;
}

CheckResult check_exports(const std::string& path) {
  Plugin p;
  std::string e = load(path, &p);
  if (!e.empty()) return fail(e);
  return pass("atmo_negotiate found, plugin '" + std::string(p.api().plugin_name) + "'");
}

CheckResult negotiate_case(const std::string& path, uint32_t lo, uint32_t hi, AtmoResult want, uint32_t want_version) {
  Plugin p;
  std::string e = load(path, &p);
  if (!e.empty()) return fail(e);
  auto info = negotiate_info(lo, hi);
  auto api = make<AtmoPluginApi>(ATMO_TYPE_PLUGIN_API);
  AtmoResult r = p.loaded.negotiate(&info, &api);
  if (r != want) {
    return fail("range [" + std::to_string(lo) + ", " + std::to_string(hi) + "] returned " + std::to_string(r) +
                ", expected " + std::to_string(want));
  }
  if (want == ATMO_SUCCESS) {
    if (api.interface_version != want_version)
      return fail("chose interface version " + std::to_string(api.interface_version) + ", expected " +
                  std::to_string(want_version));
    if (!api.create_context || !api.render_pass || !api.result_string) return fail("function table has NULL entries");
  } else if (api.create_context != nullptr) {
    return fail("a refused negotiation still filled the function table");
  }
  return pass();
}

CheckResult check_negotiate_struct_edges(const std::string& path) {
  Plugin p;
  std::string e = load(path, &p);
  if (!e.empty()) return fail(e);
  auto info = negotiate_info(1, 1);
  auto api = make<AtmoPluginApi>(ATMO_TYPE_PLUGIN_API);
  if (p.loaded.negotiate(nullptr, &api) != ATMO_ERROR_INVALID_ARGUMENT) return fail("NULL host info was accepted");
  if (p.loaded.negotiate(&info, nullptr) != ATMO_ERROR_INVALID_ARGUMENT) return fail("NULL api was accepted");
  auto small = info;
  small.header.struct_size = 12;
  if (p.loaded.negotiate(&small, &api) != ATMO_ERROR_STRUCT_TOO_SMALL) return fail("undersized AtmoNegotiateInfo accepted");
  auto wrong = info;
  wrong.header.type = ATMO_TYPE_FRAME_STATE;
  if (p.loaded.negotiate(&wrong, &api) != ATMO_ERROR_WRONG_STRUCT_TYPE) return fail("wrong type tag accepted");
  auto small_api = make<AtmoPluginApi>(ATMO_TYPE_PLUGIN_API);
  small_api.header.struct_size = 40;
  if (p.loaded.negotiate(&info, &small_api) != ATMO_ERROR_STRUCT_TOO_SMALL) return fail("undersized api table accepted");
  // A newer host with a bigger table: the plugin fills its part, says how much, leaves the rest alone.
  struct Bigger {
    AtmoPluginApi api;
    uint64_t future[4];
  } big;
  std::memset(&big, 0xAB, sizeof(big));
  big.api.header.type = ATMO_TYPE_PLUGIN_API;
  big.api.header.struct_size = sizeof(big);
  big.api.header.next = nullptr;
  if (p.loaded.negotiate(&info, &big.api) != ATMO_SUCCESS) return fail("a larger api table was refused");
  if (big.api.header.struct_size != sizeof(AtmoPluginApi))
    return fail("larger table: struct_size came back " + std::to_string(big.api.header.struct_size) + ", expected " +
                std::to_string(sizeof(AtmoPluginApi)));
  for (uint64_t f : big.future)
    if (f != 0xABABABABABABABABull) return fail("larger table: the plugin wrote past its own table");
  // Oversized negotiate info with an unknown extension chained.
  struct Unknown {
    AtmoStructHeader header;
    double payload;
  } unknown = {{0x7fff0001u, sizeof(Unknown), nullptr}, 1.0};
  struct BigInfo {
    AtmoNegotiateInfo info;
    uint64_t extra;
  } big_info{info, 42};
  big_info.info.header.struct_size = sizeof(big_info);
  big_info.info.header.next = &unknown;
  auto api2 = make<AtmoPluginApi>(ATMO_TYPE_PLUGIN_API);
  if (p.loaded.negotiate(&big_info.info, &api2) != ATMO_SUCCESS)
    return fail("oversized AtmoNegotiateInfo with an unknown `next` entry was refused");
  return pass();
}

CheckResult check_result_strings(const std::string& path) {
  Plugin p;
  std::string e = load(path, &p);
  if (!e.empty()) return fail(e);
  for (AtmoResult r = -20; r <= 5; ++r) {
    const char* s = p.api().result_string(r);
    if (!s || !*s) return fail("result_string(" + std::to_string(r) + ") is empty");
  }
  if (std::string(p.api().result_string(ATMO_ERROR_STRUCT_TOO_SMALL)) == p.api().result_string(ATMO_SUCCESS))
    return fail("distinct codes share a name");
  return pass();
}

// ---------------------------------------------------------------- structs and arguments

CheckResult check_create_context_arguments(const std::string& path) {
  Plugin p;
  std::string e = load(path, &p);
  if (!e.empty()) return fail(e);
  const auto& api = p.api();
  AtmoContext ctx = reinterpret_cast<AtmoContext>(0x1);
  auto info = make<AtmoContextCreateInfo>(ATMO_TYPE_CONTEXT_CREATE_INFO);
  std::string why;
  if (!(why = expect(p, api.create_context(nullptr, &ctx), ATMO_ERROR_INVALID_ARGUMENT, "create_context(NULL info)")).empty())
    return fail(why);
  if (ctx != nullptr) return fail("create_context(NULL info) left *out_context non-NULL");
  if (!(why = expect(p, api.create_context(&info, nullptr), ATMO_ERROR_INVALID_ARGUMENT, "create_context(NULL out)")).empty())
    return fail(why);
  auto small = info;
  small.header.struct_size = 20;
  if (!(why = expect(p, api.create_context(&small, &ctx), ATMO_ERROR_STRUCT_TOO_SMALL, "undersized AtmoContextCreateInfo")).empty())
    return fail(why);
  if (std::string(api.last_error(nullptr)).find("struct_size") == std::string::npos)
    return fail("the error message does not name the field: '" + std::string(api.last_error(nullptr)) + "'");
  auto services = make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  services.header.struct_size = 16;
  info.services = &services;
  if (!(why = expect(p, api.create_context(&info, &ctx), ATMO_ERROR_STRUCT_TOO_SMALL, "undersized AtmoHostServices")).empty())
    return fail(why);
  info.services = nullptr;  // all fallbacks
  if (!(why = expect(p, api.create_context(&info, &ctx), ATMO_SUCCESS, "create_context(NULL services)")).empty())
    return fail(why);
  api.destroy_context(ctx);
  return pass();
}

CheckResult check_state_structs(const std::string& path) {
  Session s;
  if (!s.open(path)) return fail(s.error);
  const auto& api = s.plugin.api();
  std::string why;
  auto frame = valid_frame();
  auto view = valid_view(32, 32, 0);
  auto atm = make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
  struct {
    const char* what;
    AtmoResult got, want;
  } cases[] = {
      {"set_frame(NULL)", api.set_frame(s.context, nullptr), ATMO_ERROR_INVALID_ARGUMENT},
      {"set_view(NULL)", api.set_view(s.view, nullptr), ATMO_ERROR_INVALID_ARGUMENT},
      {"set_atmosphere(NULL)", api.set_atmosphere(s.context, nullptr), ATMO_ERROR_INVALID_ARGUMENT},
      {"render_pass(NULL)", api.render_pass(s.view, nullptr), ATMO_ERROR_INVALID_ARGUMENT},
      {"get_lighting(NULL)", api.get_lighting(s.view, nullptr), ATMO_ERROR_INVALID_ARGUMENT},
  };
  for (auto& c : cases)
    if (!(why = expect(s.plugin, c.got, c.want, c.what)).empty()) return fail(why);

  // Undersized: every state struct at 8 bytes less than version 1.
  auto f2 = frame;
  f2.header.struct_size = 32;  // 8 bytes short of the version-1 layout (40); deferred_frames after it is optional
  if (!(why = expect(s.plugin, api.set_frame(s.context, &f2), ATMO_ERROR_STRUCT_TOO_SMALL, "undersized AtmoFrameState")).empty())
    return fail(why);
  auto v2 = view;
  v2.header.struct_size = 400;  // 8 bytes short of the version-1 layout (408); the fields after it are optional
  if (!(why = expect(s.plugin, api.set_view(s.view, &v2), ATMO_ERROR_STRUCT_TOO_SMALL, "undersized AtmoViewState")).empty())
    return fail(why);
  auto a2 = atm;
  a2.header.struct_size = 24;
  if (!(why = expect(s.plugin, api.set_atmosphere(s.context, &a2), ATMO_ERROR_STRUCT_TOO_SMALL, "undersized AtmoAtmosphereState")).empty())
    return fail(why);
  auto pass_info = make<AtmoPassInfo>(ATMO_TYPE_PASS_INFO);
  pass_info.header.struct_size = 16;
  if (!(why = expect(s.plugin, api.render_pass(s.view, &pass_info), ATMO_ERROR_STRUCT_TOO_SMALL, "undersized AtmoPassInfo")).empty())
    return fail(why);
  auto light = make<AtmoLighting>(ATMO_TYPE_LIGHTING);
  light.header.struct_size = 20;
  if (!(why = expect(s.plugin, api.get_lighting(s.view, &light), ATMO_ERROR_STRUCT_TOO_SMALL, "undersized AtmoLighting")).empty())
    return fail(why);

  // Wrong tags.
  auto f3 = frame;
  f3.header.type = ATMO_TYPE_VIEW_STATE;
  if (!(why = expect(s.plugin, api.set_frame(s.context, &f3), ATMO_ERROR_WRONG_STRUCT_TYPE, "AtmoFrameState with a view tag")).empty())
    return fail(why);

  // Oversized (a newer host) with unknown chained extensions: accepted.
  struct Unknown {
    AtmoStructHeader header;
    double payload[3];
  } ext2 = {{0x7fff0002u, sizeof(Unknown), nullptr}, {1, 2, 3}}, ext1 = {{0x7fff0003u, sizeof(Unknown), &ext2}, {4, 5, 6}};
  struct NewerFrame {
    AtmoFrameState frame;
    double future_field[6];
  } newer{frame, {7, 7, 7, 7, 7, 7}};
  newer.frame.header.struct_size = sizeof(newer);
  newer.frame.header.next = &ext1;
  if (!(why = expect(s.plugin, api.set_frame(s.context, &newer.frame), ATMO_SUCCESS, "oversized AtmoFrameState + unknown next")).empty())
    return fail(why);
  struct NewerView {
    AtmoViewState view;
    double future_field[2];
  } newer_view{view, {1, 2}};
  newer_view.view.header.struct_size = sizeof(newer_view);
  newer_view.view.header.next = &ext1;
  if (!(why = expect(s.plugin, api.set_view(s.view, &newer_view.view), ATMO_SUCCESS, "oversized AtmoViewState")).empty())
    return fail(why);
  // An older host whose AtmoLighting is exactly version 1 gets it filled.
  auto l1 = make<AtmoLighting>(ATMO_TYPE_LIGHTING);
  if (!(why = expect(s.plugin, api.get_lighting(s.view, &l1), ATMO_SUCCESS, "get_lighting")).empty()) return fail(why);
  double n = std::sqrt(l1.sun_direction_enu[0] * l1.sun_direction_enu[0] + l1.sun_direction_enu[1] * l1.sun_direction_enu[1] +
                       l1.sun_direction_enu[2] * l1.sun_direction_enu[2]);
  if (std::abs(n - 1.0) > 1e-6) return fail("get_lighting: sun direction is not a unit vector");
  // A host compiled with the first, 104-byte AtmoLighting: its part is filled, nothing beyond it is written.
  struct OldHostLighting {
    unsigned char first_layout[104];
    uint64_t canary[8];
  } old;
  std::memset(&old, 0xCD, sizeof(old));
  AtmoStructHeader old_header = {ATMO_TYPE_LIGHTING, 104, nullptr};
  std::memcpy(old.first_layout, &old_header, sizeof(old_header));
  if (!(why = expect(s.plugin, api.get_lighting(s.view, reinterpret_cast<AtmoLighting*>(&old)), ATMO_SUCCESS,
                     "get_lighting with the 104-byte layout")).empty())
    return fail(why);
  for (uint64_t c : old.canary)
    if (c != 0xCDCDCDCDCDCDCDCDull) return fail("get_lighting wrote past a 104-byte AtmoLighting");
  double old_sun_z;
  std::memcpy(&old_sun_z, old.first_layout + offsetof(AtmoLighting, sun_direction_enu) + 2 * sizeof(double),
              sizeof(double));
  if (std::abs(old_sun_z - l1.sun_direction_enu[2]) > 1e-12) return fail("the 104-byte AtmoLighting was not filled");
  return pass();
}

CheckResult check_non_finite_and_range(const std::string& path) {
  Session s;
  if (!s.open(path)) return fail(s.error);
  const auto& api = s.plugin.api();
  support::Image before;
  std::string why;
  if (!render_sky_image(s, 24, &before, &why)) return fail(why);

  const double nan = std::nan(""), inf = INFINITY;
  struct Case {
    const char* what;
    std::function<AtmoResult()> call;
    AtmoResult want;
  };
  std::vector<Case> cases = {
      {"frame utc NaN", [&] { auto f = valid_frame(); f.utc_posix_s = nan; return api.set_frame(s.context, &f); }, ATMO_ERROR_NON_FINITE_VALUE},
      {"frame utc +Inf", [&] { auto f = valid_frame(); f.utc_posix_s = inf; return api.set_frame(s.context, &f); }, ATMO_ERROR_NON_FINITE_VALUE},
      {"frame dut1 2 s", [&] { auto f = valid_frame(); f.dut1_s = 2.0; return api.set_frame(s.context, &f); }, ATMO_ERROR_OUT_OF_RANGE},
      {"eye latitude NaN", [&] { auto v = valid_view(24, 24, 0); v.eye_geodetic[0] = nan; return api.set_view(s.view, &v); }, ATMO_ERROR_NON_FINITE_VALUE},
      {"eye latitude 95°", [&] { auto v = valid_view(24, 24, 0); v.eye_geodetic[0] = 95; return api.set_view(s.view, &v); }, ATMO_ERROR_OUT_OF_RANGE},
      {"eye ECEF -Inf", [&] { auto v = valid_view(24, 24, 0); v.eye_kind = ATMO_POSITION_ECEF; v.eye_ecef_m[2] = -inf; return api.set_view(s.view, &v); }, ATMO_ERROR_NON_FINITE_VALUE},
      {"eye ECEF at the Earth's centre", [&] { auto v = valid_view(24, 24, 0); v.eye_kind = ATMO_POSITION_ECEF; return api.set_view(s.view, &v); }, ATMO_ERROR_OUT_OF_RANGE},
      {"view matrix NaN", [&] { auto v = valid_view(24, 24, 0); v.view_from_world[5] = nan; return api.set_view(s.view, &v); }, ATMO_ERROR_NON_FINITE_VALUE},
      {"view matrix singular", [&] { auto v = valid_view(24, 24, 0); std::memset(v.view_from_world, 0, sizeof(v.view_from_world)); return api.set_view(s.view, &v); }, ATMO_ERROR_OUT_OF_RANGE},
      {"view matrix element 1e300", [&] { auto v = valid_view(24, 24, 0); v.view_from_world[0] = 1e300; return api.set_view(s.view, &v); }, ATMO_ERROR_OUT_OF_RANGE},
      {"view matrix scaled by 2 (not a rotation)", [&] { auto v = valid_view(24, 24, 0); for (int i = 0; i < 11; ++i) v.view_from_world[i] *= i % 4 == 3 ? 1.0 : 2.0; return api.set_view(s.view, &v); }, ATMO_ERROR_OUT_OF_RANGE},
      {"view matrix mirrored", [&] { auto v = valid_view(24, 24, 0); for (int i = 0; i < 3; ++i) v.view_from_world[i * 4] = -v.view_from_world[i * 4]; return api.set_view(s.view, &v); }, ATMO_ERROR_OUT_OF_RANGE},
      {"projection Inf", [&] { auto v = valid_view(24, 24, 0); v.clip_from_view[0] = inf; return api.set_view(s.view, &v); }, ATMO_ERROR_NON_FINITE_VALUE},
      {"projection singular", [&] { auto v = valid_view(24, 24, 0); std::memset(v.clip_from_view, 0, sizeof(v.clip_from_view)); return api.set_view(s.view, &v); }, ATMO_ERROR_OUT_OF_RANGE},
      {"projection element 1e300", [&] { auto v = valid_view(24, 24, 0); v.clip_from_view[0] = 1e300; return api.set_view(s.view, &v); }, ATMO_ERROR_OUT_OF_RANGE},
      {"projection near-singular (x scale 1e-12)", [&] { auto v = valid_view(24, 24, 0); v.clip_from_view[0] = 1e-12; return api.set_view(s.view, &v); }, ATMO_ERROR_OUT_OF_RANGE},
      {"viewport 0x0", [&] { auto v = valid_view(24, 24, 0); v.viewport[2] = 0; return api.set_view(s.view, &v); }, ATMO_ERROR_OUT_OF_RANGE},
      {"depth convention 7", [&] { auto v = valid_view(24, 24, 0); v.depth_convention = 7; return api.set_view(s.view, &v); }, ATMO_ERROR_INVALID_ARGUMENT},
      {"log depth far NaN", [&] { auto v = valid_view(24, 24, 0); v.depth_convention = ATMO_DEPTH_LOGARITHMIC; v.far_plane_m = nan; return api.set_view(s.view, &v); }, ATMO_ERROR_NON_FINITE_VALUE},
      {"exposure -1", [&] { auto v = valid_view(24, 24, 0); v.exposure_scale = -1; return api.set_view(s.view, &v); }, ATMO_ERROR_OUT_OF_RANGE},
      {"visibility NaN", [&] { auto a = make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE); a.visibility_m = nan; return api.set_atmosphere(s.context, &a); }, ATMO_ERROR_NON_FINITE_VALUE},
      {"visibility 1 m", [&] { auto a = make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE); a.visibility_m = 1; return api.set_atmosphere(s.context, &a); }, ATMO_ERROR_OUT_OF_RANGE},
      {"pass 99", [&] { auto pi = make<AtmoPassInfo>(ATMO_TYPE_PASS_INFO); pi.pass = 99; return api.render_pass(s.view, &pi); }, ATMO_ERROR_INVALID_ARGUMENT},
  };
  for (auto& c : cases) {
    AtmoResult r = c.call();
    if (r != c.want) return fail(std::string(c.what) + ": returned " + name(s.plugin, r) + ", expected " + name(s.plugin, c.want));
    if (std::string(api.last_error(s.context)).empty()) return fail(std::string(c.what) + ": no error message");
  }
  // Every rejection left the state alone: the same render as before.
  auto target = OffscreenTarget::create(24, 24, &why);
  target->bind();
  target->clear(0, 0, 0, 1);
  AtmoResult r = s.render(ATMO_PASS_SKY);
  if (r != ATMO_SUCCESS) return fail("render after rejected input: " + name(s.plugin, r));
  support::Image after = target->read_color();
  auto diff = support::compare_images(before, after, 1.0);
  if (diff.max_abs != 0.0 || diff.nonfinite_b != 0)
    return fail("rejected input changed the image (max difference " + std::to_string(diff.max_abs) + ")");
  return pass(std::to_string(cases.size()) + " bad inputs refused, state unchanged");
}

// ---------------------------------------------------------------- lifecycle

CheckResult check_call_order(const std::string& path) {
  Session s;
  if (!s.open(path, HeadlessGl::Profile::Core, /*init_gl=*/false)) return fail(s.error);
  const auto& api = s.plugin.api();
  std::string why;
  if (!(why = expect(s.plugin, s.render(ATMO_PASS_SKY), ATMO_ERROR_CALL_OUT_OF_ORDER, "render_pass before gl_init")).empty())
    return fail(why);
  if (api.gl_init(s.context) != ATMO_SUCCESS) return fail("gl_init failed");
  if (!(why = expect(s.plugin, s.render(ATMO_PASS_SKY), ATMO_ERROR_CALL_OUT_OF_ORDER, "render_pass before set_frame")).empty())
    return fail(why);
  auto light = make<AtmoLighting>(ATMO_TYPE_LIGHTING);
  if (!(why = expect(s.plugin, api.get_lighting(s.view, &light), ATMO_ERROR_CALL_OUT_OF_ORDER, "get_lighting before set_frame")).empty())
    return fail(why);
  auto frame = valid_frame();
  api.set_frame(s.context, &frame);
  if (!(why = expect(s.plugin, s.render(ATMO_PASS_SKY), ATMO_ERROR_CALL_OUT_OF_ORDER, "render_pass before set_view")).empty())
    return fail(why);
  auto view = valid_view(16, 16, 0);
  api.set_view(s.view, &view);
  auto target = OffscreenTarget::create(16, 16, &why);
  target->bind();
  if (!(why = expect(s.plugin, s.render(ATMO_PASS_SKY), ATMO_SUCCESS, "render_pass in order")).empty()) return fail(why);
  if (!(why = expect(s.plugin, api.gl_shutdown(s.context), ATMO_SUCCESS, "gl_shutdown")).empty()) return fail(why);
  if (!(why = expect(s.plugin, s.render(ATMO_PASS_SKY), ATMO_ERROR_CALL_OUT_OF_ORDER, "render_pass after gl_shutdown")).empty())
    return fail(why);
  return pass();
}

CheckResult check_double_init_destroy(const std::string& path) {
  Session s;
  if (!s.open(path)) return fail(s.error);
  const auto& api = s.plugin.api();
  std::string why;
  if (!(why = expect(s.plugin, api.gl_init(s.context), ATMO_SUCCESS, "second gl_init")).empty()) return fail(why);
  if (!(why = expect(s.plugin, api.gl_shutdown(s.context), ATMO_SUCCESS, "gl_shutdown")).empty()) return fail(why);
  if (!(why = expect(s.plugin, api.gl_shutdown(s.context), ATMO_SUCCESS, "second gl_shutdown")).empty()) return fail(why);
  if (!(why = expect(s.plugin, api.gl_context_lost(s.context), ATMO_SUCCESS, "gl_context_lost after shutdown")).empty()) return fail(why);
  api.destroy_view(s.view);
  api.destroy_view(s.view);  // stale: must be refused quietly
  s.view = nullptr;
  api.destroy_view(nullptr);
  api.destroy_context(nullptr);
  AtmoContext stale = s.context;
  api.destroy_context(s.context);
  s.context = nullptr;
  api.destroy_context(stale);  // double destroy
  auto frame = valid_frame();
  if (!(why = expect(s.plugin, api.set_frame(stale, &frame), ATMO_ERROR_INVALID_HANDLE, "set_frame on a destroyed context")).empty())
    return fail(why);
  AtmoContext bogus = reinterpret_cast<AtmoContext>(&frame);
  if (!(why = expect(s.plugin, api.gl_init(bogus), ATMO_ERROR_INVALID_HANDLE, "gl_init on a foreign pointer")).empty())
    return fail(why);
  // Views die with their context.
  auto info = make<AtmoContextCreateInfo>(ATMO_TYPE_CONTEXT_CREATE_INFO);
  AtmoContext c2 = nullptr;
  AtmoView v2 = nullptr;
  auto vinfo = make<AtmoViewCreateInfo>(ATMO_TYPE_VIEW_CREATE_INFO);
  if (api.create_context(&info, &c2) != ATMO_SUCCESS || api.create_view(c2, &vinfo, &v2) != ATMO_SUCCESS)
    return fail("could not create a second context and view");
  api.destroy_context(c2);
  auto view = valid_view(8, 8, 0);
  if (!(why = expect(s.plugin, api.set_view(v2, &view), ATMO_ERROR_INVALID_HANDLE, "set_view on a view of a destroyed context")).empty())
    return fail(why);
  return pass();
}

CheckResult check_context_loss(const std::string& path) {
  Session s;
  if (!s.open(path)) return fail(s.error);
  support::Image first, second;
  std::string why;
  if (!render_sky_image(s, 24, &first, &why)) return fail(why);
  const auto& api = s.plugin.api();
  if (!(why = expect(s.plugin, api.gl_context_lost(s.context), ATMO_SUCCESS, "gl_context_lost")).empty()) return fail(why);
  s.gl.reset();  // the GL context is really gone
  s.gl = HeadlessGl::create(HeadlessGl::Profile::Core, &why);
  if (!s.gl) return fail("could not create a second GL context: " + why);
  if (!(why = expect(s.plugin, s.render(ATMO_PASS_SKY), ATMO_ERROR_CALL_OUT_OF_ORDER, "render_pass after context loss")).empty())
    return fail(why);
  if (!(why = expect(s.plugin, api.gl_init(s.context), ATMO_SUCCESS, "gl_init on the new context")).empty()) return fail(why);
  if (!render_sky_image(s, 24, &second, &why)) return fail(why);
  auto diff = support::compare_images(first, second, 1.0);
  if (diff.max_abs > 1e-6) return fail("image after re-init differs (max " + std::to_string(diff.max_abs) + ")");
  return pass("identical image after loss and re-init");
}

CheckResult check_multiple_views(const std::string& path) {
  Session s;
  if (!s.open(path)) return fail(s.error);
  const auto& api = s.plugin.api();
  AtmoView second = nullptr;
  auto vinfo = make<AtmoViewCreateInfo>(ATMO_TYPE_VIEW_CREATE_INFO);
  vinfo.channel_id = 1;
  if (api.create_view(s.context, &vinfo, &second) != ATMO_SUCCESS) return fail("second create_view failed");
  std::string why;
  auto target = OffscreenTarget::create(32, 16, &why);
  target->bind();
  target->clear(0, 0, 0, 1);
  auto frame = valid_frame();
  api.set_frame(s.context, &frame);
  auto left = valid_view(16, 16, 0);
  auto right = valid_view(16, 16, 0);
  right.viewport[0] = 16;
  // The right channel looks up (pitched 60°): a different, darker-blue region.
  double up[16] = {1, 0, 0, 0, 0, 0.5, -0.8660254, 0, 0, 0.8660254, 0.5, 0, 0, 0, 0, 1};
  std::memcpy(right.view_from_world, up, sizeof(up));
  auto pi = make<AtmoPassInfo>(ATMO_TYPE_PASS_INFO);
  if (api.set_view(s.view, &left) || api.set_view(second, &right) || api.render_pass(s.view, &pi) ||
      api.render_pass(second, &pi))
    return fail("rendering two views failed: " + std::string(api.last_error(s.context)));
  support::Image img = target->read_color();
  const float* a = img.pixel(8, 8);
  const float* b = img.pixel(24, 8);
  if (!(a[0] > 0 && b[0] > 0)) return fail("a channel was not drawn");
  if (std::abs(a[1] - b[1]) < 1e-6f) return fail("the two channels show the same thing");
  api.destroy_view(second);
  return pass();
}

// ---------------------------------------------------------------- host services

std::atomic<long> g_allocations{0}, g_frees{0}, g_log_messages{0}, g_gl_lookups{0};
void* counting_allocate(void*, size_t size, size_t alignment) {
  ++g_allocations;
  return std::aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment);
}
void counting_free(void*, void* p) {
  ++g_frees;
  std::free(p);
}
void counting_log(void*, int32_t, const char*) { ++g_log_messages; }
void* counting_gl(void*, const char* name) {
  ++g_gl_lookups;
  return HeadlessGl::get_proc_address(nullptr, name);
}

CheckResult check_host_services(const std::string& path) {
  Plugin p;
  std::string e = load(path, &p);
  if (!e.empty()) return fail(e);
  auto gl = HeadlessGl::create(HeadlessGl::Profile::Core, &e);
  if (!gl) return fail("no GL: " + e);
  const auto& api = p.api();
  auto services = make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  services.allocate = &counting_allocate;
  services.deallocate = &counting_free;
  services.log = &counting_log;
  services.gl_get_proc_address = &counting_gl;
  auto info = make<AtmoContextCreateInfo>(ATMO_TYPE_CONTEXT_CREATE_INFO);
  info.services = &services;
  AtmoContext ctx = nullptr;
  AtmoView view = nullptr;
  auto vinfo = make<AtmoViewCreateInfo>(ATMO_TYPE_VIEW_CREATE_INFO);
  if (api.create_context(&info, &ctx) || api.gl_init(ctx) || api.create_view(ctx, &vinfo, &view))
    return fail("setup failed: " + std::string(api.last_error(ctx)));
  if (g_gl_lookups == 0) return fail("the host's gl_get_proc_address was not used");
  if (g_allocations < 2) return fail("the host allocator was not used for the context and view");
  auto bad = valid_frame();
  bad.utc_posix_s = std::nan("");
  api.set_frame(ctx, &bad);
  if (g_log_messages == 0) return fail("an error was not reported through the host's log sink");
  api.gl_shutdown(ctx);
  api.destroy_context(ctx);  // destroys the view too
  if (g_allocations != g_frees)
    return fail("allocations " + std::to_string(g_allocations) + " != frees " + std::to_string(g_frees));
  // Half a pair is refused.
  services.deallocate = nullptr;
  if (api.create_context(&info, &ctx) != ATMO_ERROR_INVALID_ARGUMENT) return fail("allocate without deallocate accepted");
  return pass(std::to_string(g_allocations.load()) + " allocations, all freed; " + std::to_string(g_gl_lookups.load()) +
              " GL lookups through the host");
}

// ---------------------------------------------------------------- GL state contract

std::string state_leaks(const support::GlStateSnapshot& before, const support::GlStateSnapshot& after) {
  auto diff = support::diff_gl_state(before, after);
  std::string out;
  for (size_t i = 0; i < diff.size() && i < 6; ++i) out += (i ? "; " : "") + diff[i];
  if (diff.size() > 6) out += "; ... (" + std::to_string(diff.size()) + " values)";
  return out;
}

// 2024-06-21 22:00 UTC, midnight at Innsbruck: the Sun 19 degrees down, so the night pass draws too.
AtmoFrameState night_frame() {
  auto f = valid_frame();
  f.utc_posix_s += 12 * 3600.0;
  return f;
}

// Fog, a lamp in view and a cumulus layer: with these (and a night frame and a
// depth texture) every pass has something to draw, so each one's first call
// (lazy creation of its GL objects) is checked, not only the sky's.
std::string give_every_pass_work(const AtmoPluginApi& api, AtmoContext context) {
  auto fog = make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
  fog.visibility_m = 3000.0;
  // A lamp 400 m north of the origin, on the ground (the eye is 600 m up), glowing in the fog, and a beacon
  // 5 km north at the eye's height, drawn as a point against the sky.
  static AtmoLightPoint lamps[2] = {};  // copied by set_lights
  lamps[0].position_m[1] = 400.0;
  lamps[1].position_m[1] = 5000.0;
  lamps[1].position_m[2] = 600.0;
  for (AtmoLightPoint& lamp : lamps) {
    lamp.intensity_cd = 1e5;
    lamp.color[0] = lamp.color[1] = lamp.color[2] = 1.0;
  }
  auto lights = make<AtmoLightsState>(ATMO_TYPE_LIGHTS_STATE);
  lights.world_frame = ATMO_WORLD_ENU;
  lights.light_size = sizeof(AtmoLightPoint);
  lights.world_origin_geodetic[0] = 47.26;
  lights.world_origin_geodetic[1] = 11.35;
  lights.lights = lamps;
  lights.light_count = 2;
  auto layer = make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
  layer.type = ATMO_CLOUD_CUMULUS;
  layer.coverage_oktas = 4;  // a few small clouds ahead, 200-800 m above the eye: cheap to draw on llvmpipe
  layer.base_m = 800.0;
  layer.top_m = 1400.0;
  layer.area_size_m = 2500.0;
  layer.seed = 4;
  auto clouds = make<AtmoCloudsState>(ATMO_TYPE_CLOUDS_STATE);
  clouds.origin_geodetic[0] = 47.26;
  clouds.origin_geodetic[1] = 11.35;
  clouds.layers = &layer;
  clouds.layer_count = 1;
  AtmoResult r;
  if ((r = api.set_fog(context, &fog)) != ATMO_SUCCESS) return std::string("set_fog failed: ") + api.last_error(context);
  if ((r = api.set_lights(context, &lights)) != ATMO_SUCCESS)
    return std::string("set_lights failed: ") + api.last_error(context);
  if ((r = api.set_clouds(context, &clouds)) != ATMO_SUCCESS)
    return std::string("set_clouds failed: ") + api.last_error(context);
  // An object of two spheres 300 m north at the eye's height: get_sky_occlusion has something to upload
  // (a plugin from before sky occlusion has no set_occluders: its table ends above).
  if (!api.set_occluders) return {};
  static const AtmoOccluderSphere spheres[2] = {{{-4.0, 300.0, 600.0}, 5.0}, {{4.0, 300.0, 600.0}, 5.0}};
  AtmoOccluderObject object{};
  object.spheres = spheres;
  object.sphere_count = 2;
  object.albedo[0] = object.albedo[1] = object.albedo[2] = 0.3;
  for (int k = 0; k < 4; ++k) object.world_from_object[5 * k] = 1.0;
  auto occluders = make<AtmoOccludersState>(ATMO_TYPE_OCCLUDERS_STATE);
  occluders.world_frame = ATMO_WORLD_ENU;
  occluders.world_origin_geodetic[0] = 47.26;
  occluders.world_origin_geodetic[1] = 11.35;
  occluders.objects = &object;
  occluders.object_count = 1;
  if ((r = api.set_occluders(context, &occluders)) != ATMO_SUCCESS)
    return std::string("set_occluders failed: ") + api.last_error(context);
  return {};
}

const char* const kPassNames[] = {"sky", "aerial perspective", "clouds", "night sky", "light glows", "light points",
                                   "sky occlusion"};
static_assert(sizeof(kPassNames) / sizeof(kPassNames[0]) == ATMO_PASS_COUNT, "a name for every pass");

// Pending GL error flags, drained (each flag once).
std::vector<GLenum> take_gl_errors() {
  std::vector<GLenum> errors;
  for (GLenum e = glGetError(); e != GL_NO_ERROR && errors.size() < 8; e = glGetError()) errors.push_back(e);
  return errors;
}

CheckResult gl_state_check(const std::string& path, HeadlessGl::Profile profile, bool unusual) {
  Session s;
  if (!s.open(path, profile, /*init_gl=*/false)) return fail(s.error);
  const auto& api = s.plugin.api();
  const int size = 64;  // UnusualGlState's framebuffer is 64x64
  unsigned depth = support::make_split_depth_texture(size, size, 0.9999f);
  auto frame = night_frame();
  auto view = valid_view(size, size, depth);
  view.exposure_scale = 1e3;  // a night exposure: the stars show, so the night pass draws
  api.set_frame(s.context, &frame);
  api.set_view(s.view, &view);
  std::string why = give_every_pass_work(api, s.context);
  if (!why.empty()) return fail(why);
  // The default state still needs a complete framebuffer (surfaceless EGL has none).
  std::string target_error;
  std::unique_ptr<OffscreenTarget> target;
  if (!unusual) {
    target = OffscreenTarget::create(size, size, &target_error);
    if (!target) return fail(target_error);
    target->bind();
  }
  std::unique_ptr<support::UnusualGlState> odd;
  if (unusual) odd = std::make_unique<support::UnusualGlState>();

  size_t values = 0;
  int calls = 0;
  // Each call runs with a host's GL error pending (GL_INVALID_ENUM, GL_INVALID_VALUE, GL_INVALID_OPERATION in
  // turn; Mesa keeps one flag at a time): it must still be pending after the call (the plugin must not consume
  // the host's errors), and no state value may change.
  GLuint deleted_vao = 0;  // a name no longer in use: binding it is GL_INVALID_OPERATION and changes nothing
  glGenVertexArrays(1, &deleted_vao);
  glDeleteVertexArrays(1, &deleted_vao);
  const std::pair<GLenum, std::function<void()>> host_errors[] = {
      {GL_INVALID_ENUM, [] { glEnable(GL_NONE); }},
      {GL_INVALID_VALUE, [] { glViewport(0, 0, -1, -1); }},
      {GL_INVALID_OPERATION, [&] { glBindVertexArray(deleted_vao); }}};
  auto probe = [&](const std::string& what, const std::function<AtmoResult()>& call, bool must_draw = false) {
    support::GlStateSnapshot before = support::capture_gl_state();
    values = before.values.size();
    const auto& host_error = host_errors[calls % 3];
    host_error.second();
    AtmoResult r = call();
    std::vector<GLenum> errors = take_gl_errors();
    support::GlStateSnapshot after = support::capture_gl_state();
    ++calls;
    if (r < 0) return what + " failed: " + name(s.plugin, r) + ": " + api.last_error(s.context);
    if (must_draw && r != ATMO_SUCCESS) return what + " returned " + name(s.plugin, r) + ": it must draw here";
    std::string leaks = state_leaks(before, after);
    if (!leaks.empty()) return what + " changed GL state: " + leaks;
    if (errors.size() != 1 || errors[0] != host_error.first) {
      std::string got;
      for (GLenum e : errors) got += (got.empty() ? "" : ", ") + std::to_string(e);
      return what + " did not keep the host's pending GL error " + std::to_string(host_error.first) +
             ": pending after the call: " + (got.empty() ? "none" : got);
    }
    return std::string();
  };
  // Every problem is collected (a plugin that drops the host's errors may leak state too).
  std::vector<std::string> problems;
  auto run = [&](const std::string& what, const std::function<AtmoResult()>& call, bool must_draw = false) {
    std::string why = probe(what, call, must_draw);
    if (!why.empty()) problems.push_back(why);
  };
  run("gl_init", [&] { return api.gl_init(s.context); });
  // Every pass draws, twice: the first call creates its GL objects, the second reuses them.
  for (const char* call : {"first", "second"}) {
    for (int pass_index = 0; pass_index < ATMO_PASS_COUNT; ++pass_index) {
      const std::string what = std::string(call) + " render_pass(" + kPassNames[pass_index] + ")";
      run(what, [&] { return s.render(static_cast<AtmoPassKind>(pass_index)); }, true);
    }
  }
  // A second frame after the atmosphere changed (re-uploads the table).
  auto atm = make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
  atm.visibility_m = 3000;
  api.set_atmosphere(s.context, &atm);
  run("render_pass(sky) with a new table", [&] { return s.render(ATMO_PASS_SKY); });
  auto lighting = make<AtmoLighting>(ATMO_TYPE_LIGHTING);
  run("get_lighting", [&] { return api.get_lighting(s.view, &lighting); });
  auto fog_lighting = make<AtmoFogLighting>(ATMO_TYPE_FOG_LIGHTING);
  run("get_fog_lighting", [&] { return api.get_fog_lighting(s.view, &fog_lighting); });
  auto shadows = make<AtmoCloudShadows>(ATMO_TYPE_CLOUD_SHADOWS);
  run("get_cloud_shadows", [&] { return api.get_cloud_shadows(s.view, &shadows); });
  auto occlusion = make<AtmoSkyOcclusion>(ATMO_TYPE_SKY_OCCLUSION);
  if (api.get_sky_occlusion)
    run("get_sky_occlusion", [&] { return api.get_sky_occlusion(s.view, &occlusion); }, true);
  run("gl_shutdown", [&] { return api.gl_shutdown(s.context); });
  if (!problems.empty()) {
    // State changes first: they are what breaks a host's later draws.
    std::stable_partition(problems.begin(), problems.end(),
                          [](const std::string& p) { return p.find(" changed GL state: ") != std::string::npos; });
    std::string all;
    for (size_t i = 0; i < problems.size() && i < 4; ++i) all += (i ? " | " : "") + problems[i];
    if (problems.size() > 4) all += " | ... (" + std::to_string(problems.size()) + " calls)";
    return fail(all);
  }
  if (values < 40) return fail("only " + std::to_string(values) + " GL state values compared; need >= 40");
  odd.reset();
  glDeleteTextures(1, &depth);
  return pass(std::to_string(calls) + " calls (every pass drawing, first and second call), " + std::to_string(values) +
              " GL state values unchanged and the host's pending GL error kept by each; GL " + s.gl->version());
}

// Fixed-function state of a compatibility context that a host may leave on and
// that changes what a program's fragments write: every pass must draw the
// same image with it (bit for bit) as with the default state.
struct OddHostState {
  const char* what;
  std::function<void()> set, reset;
};

std::vector<OddHostState> odd_fixed_function_states() {
  using AlphaFunc = void (*)(GLenum, GLfloat);
  constexpr GLenum kAlphaTest = 0x0BC0, kClampFragmentColor = 0x891B;
  static const AlphaFunc alpha_func = reinterpret_cast<AlphaFunc>(HeadlessGl::get_proc_address(nullptr, "glAlphaFunc"));
  return {
      {"GL_ALPHA_TEST on, glAlphaFunc(GL_NEVER)", [] { glEnable(kAlphaTest); alpha_func(GL_NEVER, 0.0f); },
       [] { glDisable(kAlphaTest); alpha_func(GL_ALWAYS, 0.0f); }},
      {"glClampColor(GL_CLAMP_FRAGMENT_COLOR, GL_TRUE)", [] { glClampColor(kClampFragmentColor, GL_TRUE); },
       [] { glClampColor(kClampFragmentColor, 0x891D /* GL_FIXED_ONLY */); }},
      {"GL_COLOR_LOGIC_OP on (GL_COPY)", [] { glEnable(GL_COLOR_LOGIC_OP); glLogicOp(GL_COPY); },
       [] { glDisable(GL_COLOR_LOGIC_OP); }},
  };
}

CheckResult check_fixed_function_state(const std::string& path) {
  Session s;
  if (!s.open(path, HeadlessGl::Profile::Compatibility)) return fail(s.error);
  if (s.gl->is_core()) return fail("no compatibility-profile context: " + s.gl->version());
  const auto& api = s.plugin.api();
  const int size = 32;
  std::string why;
  auto target = OffscreenTarget::create(size, size, &why);
  if (!target) return fail(why);
  unsigned depth = support::make_split_depth_texture(size, size, 0.9999f);
  if (!(why = give_every_pass_work(api, s.context)).empty()) return fail(why);
  // Noon and midnight (Moon and stars), exposed so that the sky, the Moon and the lamp's glow exceed 1.
  struct Scene {
    AtmoFrameState frame;
    double exposure;
  };
  const Scene scenes[] = {{valid_frame(), 1e-2}, {night_frame(), 1e3}};
  std::vector<support::Image> reference;
  // One scene's five passes, each over the host's geometry colour.
  auto draw_all = [&](const Scene& scene, std::vector<support::Image>* out) -> std::string {
    out->clear();
    auto view = valid_view(size, size, depth);
    view.exposure_scale = scene.exposure;
    api.set_frame(s.context, &scene.frame);
    api.set_view(s.view, &view);
    for (int p = 0; p < ATMO_PASS_COUNT; ++p) {
      target->clear(0.25f, 0.5f, 0.75f, 1.0f);  // the host's geometry
      AtmoResult r = s.render(static_cast<AtmoPassKind>(p));
      if (r < 0) return std::string("render_pass(") + kPassNames[p] + ") failed: " + api.last_error(s.context);
      out->push_back(target->read_color());
    }
    return {};
  };
  auto compare = [&](const std::vector<support::Image>& got, const char* when, const std::string& state) {
    for (size_t i = 0; i < got.size(); ++i) {
      size_t differing = 0;
      double worst = 0.0;
      for (size_t k = 0; k < got[i].rgba.size(); ++k) {
        const double d = std::abs(double(got[i].rgba[k]) - double(reference[i].rgba[k]));
        if (got[i].rgba[k] != reference[i].rgba[k]) ++differing;
        if (d > worst || std::isnan(d)) worst = d;
      }
      if (differing) {
        return std::string("render_pass(") + kPassNames[i] + ") at " + when + " with " + state + ": " +
               std::to_string(differing) + " of " + std::to_string(got[i].rgba.size()) +
               " channel values differ from the default state's image, largest |difference| " + std::to_string(worst);
      }
    }
    return std::string();
  };
  int states = 0;
  for (const Scene& scene : scenes) {
    const char* when = &scene == &scenes[0] ? "noon" : "midnight";
    // The default state's images, once the clouds' relighting for this light has settled (its worker thread
    // remakes them some frames after the light changed).
    std::vector<support::Image> again;
    if (!(why = draw_all(scene, &reference)).empty()) return fail(why);
    for (int tries = 0;; ++tries) {
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      if (!(why = draw_all(scene, &again)).empty()) return fail(why);
      if (compare(again, when, "the default state").empty()) break;
      if (tries == 20) return fail(compare(again, when, "the default state again (not repeatable after 6 s)"));
      reference = again;
    }
    for (const OddHostState& odd : odd_fixed_function_states()) {
      target->bind();
      odd.set();
      std::vector<support::Image> got;
      why = draw_all(scene, &got);
      odd.reset();
      if (why.empty()) why = compare(got, when, odd.what);
      if (!why.empty()) return fail(why);
      ++states;
    }
  }
  glDeleteTextures(1, &depth);
  return pass(std::to_string(states) + " host states and scenes x 5 passes, bit-identical to the default state's images");
}

// The oldest GL the ABI promises. Mesa honours MESA_GL_VERSION_OVERRIDE when
// the driver starts, which in this fresh process is now; other drivers ignore
// it, and the check then says which version it got.
CheckResult check_gl33(const std::string& path) {
  setenv("MESA_GL_VERSION_OVERRIDE", "3.3", 1);
  return gl_state_check(path, HeadlessGl::Profile::Core, true);
}

CheckResult check_nothing_to_draw_costs_nothing(const std::string& path) {
  Session s;
  if (!s.open(path)) return fail(s.error);
  const auto& api = s.plugin.api();
  std::string why;
  auto target = OffscreenTarget::create(16, 16, &why);
  target->bind();
  target->clear(0.25f, 0.5f, 0.75f, 1);
  auto frame = valid_frame();
  auto view = valid_view(16, 16, 0);  // no depth texture: no aerial perspective
  api.set_frame(s.context, &frame);
  api.set_view(s.view, &view);
  AtmoResult r = s.render(ATMO_PASS_AERIAL_PERSPECTIVE);
  if (r != ATMO_STATUS_NOTHING_TO_DRAW) return fail("aerial perspective without depth returned " + name(s.plugin, r));
  for (AtmoPassKind p : {ATMO_PASS_CLOUDS, ATMO_PASS_NIGHT_SKY, ATMO_PASS_LIGHT_GLOWS}) {
    r = s.render(p);
    if (r <= 0) return fail("an empty pass returned " + name(s.plugin, r) + ", expected a status > 0");
  }
  support::Image img = target->read_color();
  for (size_t i = 0; i < img.pixel_count(); ++i)
    if (img.rgba[i * 4] != 0.25f || img.rgba[i * 4 + 2] != 0.75f) return fail("an empty pass wrote pixels");
  return pass();
}

}  // namespace

std::vector<Check> all_checks() {
  using P = const std::string&;
  return {
      {"load: dlopen and the atmo_negotiate symbol", check_exports},
      {"negotiate: exact range [1,1]", [](P p) { return negotiate_case(p, 1, 1, ATMO_SUCCESS, 1); }},
      {"negotiate: wider host range [1,99] picks 1", [](P p) { return negotiate_case(p, 1, 99, ATMO_SUCCESS, 1); }},
      {"negotiate: no overlap [2,5] is refused", [](P p) { return negotiate_case(p, 2, 5, ATMO_ERROR_INCOMPATIBLE_VERSION, 0); }},
      {"negotiate: empty range [3,1] is refused", [](P p) { return negotiate_case(p, 3, 1, ATMO_ERROR_INVALID_ARGUMENT, 0); }},
      {"negotiate: range starting at 0 is refused", [](P p) { return negotiate_case(p, 0, 0, ATMO_ERROR_INVALID_ARGUMENT, 0); }},
      {"negotiate: NULL, undersized, oversized, wrong-type, unknown-next structs", check_negotiate_struct_edges},
      {"result_string names every code", check_result_strings},
      {"create_context: NULL arguments, undersized structs, NULL services", check_create_context_arguments},
      {"state structs: NULL, undersized, wrong type, oversized, unknown next", check_state_structs},
      {"NaN/Inf and out-of-range input is refused and changes nothing", check_non_finite_and_range},
      {"calls out of order are refused", check_call_order},
      {"double init/shutdown/destroy and stale handles", check_double_init_destroy},
      {"context loss and re-init", check_context_loss},
      {"two views of one context", check_multiple_views},
      {"host services: allocator, log sink, GL loader", check_host_services},
      {"empty passes draw nothing", check_nothing_to_draw_costs_nothing},
      {"GL state unchanged by every call (default host state, core)",
       [](P p) { return gl_state_check(p, HeadlessGl::Profile::Core, false); }},
      {"GL state unchanged by every call (unusual host state, core)",
       [](P p) { return gl_state_check(p, HeadlessGl::Profile::Core, true); }},
      {"GL state unchanged by every call (default host state, compatibility profile: VAO 0, array buffer 0)",
       [](P p) { return gl_state_check(p, HeadlessGl::Profile::Compatibility, false); }},
      {"GL state unchanged by every call (unusual host state, compatibility profile)",
       [](P p) { return gl_state_check(p, HeadlessGl::Profile::Compatibility, true); }},
      {"OpenGL 3.3 core context: draws, and GL state unchanged", check_gl33},
      {"every pass draws the same image under alpha test, colour clamping, logic op (compatibility profile)",
       check_fixed_function_state},
  };
}

}  // namespace atmo::validate
