// atmo.hpp — header-only C++17 RAII wrapper over the Atmo C ABI (atmo.h) and
// the host SDK loader (atmo_loader.h). Errors become atmo::Error exceptions on
// the host's side of the ABI; nothing here crosses it.
//
//   atmo::Plugin plugin("libatmo.so");           // dlopen + negotiate
//   atmo::Context ctx(plugin, services);         // create_context
//   ctx.gl_init();                               // GL current
//   atmo::View view(ctx, 0);                     // create_view
//   ctx.set_frame(frame); view.set(view_state);
//   view.render(ATMO_PASS_SKY);
//   // destructors: view, then ctx (gl_shutdown if initialised, destroy), then plugin
#ifndef ATMO_ATMO_HPP
#define ATMO_ATMO_HPP

#include <stdexcept>
#include <string>
#include <vector>
#include <utility>

#include "atmo/atmo.h"
#include "atmo/atmo_loader.h"

namespace atmo {

class Error : public std::runtime_error {
 public:
  Error(AtmoResult code, const std::string& message) : std::runtime_error(message), code_(code) {}
  AtmoResult code() const { return code_; }

 private:
  AtmoResult code_;
};

// Zero-initialised struct with its header filled: atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE).
template <typename T>
T make(AtmoStructType type) {
  T value{};
  value.header.type = static_cast<uint32_t>(type);
  value.header.struct_size = static_cast<uint32_t>(sizeof(T));
  value.header.next = nullptr;
  return value;
}

// An AtmoLogSeverity's name, for a host's log lines (AtmoHostServices.log).
inline const char* log_severity_name(int32_t severity) {
  switch (severity) {
    case ATMO_LOG_DEBUG: return "debug";
    case ATMO_LOG_INFO: return "info";
    case ATMO_LOG_WARNING: return "warning";
    case ATMO_LOG_ERROR: return "error";
    case ATMO_LOG_HOST_MISBEHAVING: return "HOST MISBEHAVING";
  }
  return "?";
}

// An AtmoCloudsState over count layers of this header's AtmoCloudLayer (the
// stride, layer_size) in the ENU frame at the given geodetic origin (degrees,
// metres, WGS84); the quality knobs are 0, the plugin's defaults.
inline AtmoCloudsState clouds_state(double latitude_deg, double longitude_deg, double height_m,
                                    const AtmoCloudLayer* layers, uint32_t count) {
  auto state = make<AtmoCloudsState>(ATMO_TYPE_CLOUDS_STATE);
  state.origin_geodetic[0] = latitude_deg;
  state.origin_geodetic[1] = longitude_deg;
  state.origin_geodetic[2] = height_m;
  state.layers = layers;
  state.layer_count = count;
  state.layer_size = static_cast<uint32_t>(sizeof(AtmoCloudLayer));
  return state;
}

// An omnidirectional light at (x, y, z) in the lights' world frame (metres)
// of `intensity_cd` candela, white unless `rgb` says otherwise (relative
// weights; the plugin reads intensity_cd * color).
inline AtmoLightPoint omni_light(double x, double y, double z, double intensity_cd,
                                 const double rgb[3] = nullptr) {
  AtmoLightPoint p{};
  p.position_m[0] = x;
  p.position_m[1] = y;
  p.position_m[2] = z;
  p.intensity_cd = intensity_cd;
  for (int k = 0; k < 3; ++k) p.color[k] = rgb ? rgb[k] : 1.0;
  return p;
}

// `count` lights evenly along the segment from `start` to `end` (both
// included; one light: at `start`), each a copy of `light` at its place: a
// runway's edge, a road's street lights, an approach's bars. Positions in the
// lights' world frame, metres.
inline std::vector<AtmoLightPoint> light_string(const double start[3], const double end[3], uint32_t count,
                                                const AtmoLightPoint& light) {
  std::vector<AtmoLightPoint> out(count, light);
  for (uint32_t i = 0; i < count; ++i) {
    const double t = count > 1 ? double(i) / double(count - 1) : 0.0;
    for (int k = 0; k < 3; ++k) out[i].position_m[k] = start[k] + t * (end[k] - start[k]);
  }
  return out;
}

// An AtmoLightsState for group `group` over `lights` (this header's stride)
// in the ENU frame at the given geodetic origin (degrees, metres, WGS84).
inline AtmoLightsState lights_state(uint32_t group, const std::vector<AtmoLightPoint>& lights, double latitude_deg,
                                    double longitude_deg, double height_m) {
  auto state = make<AtmoLightsState>(ATMO_TYPE_LIGHTS_STATE);
  state.world_frame = ATMO_WORLD_ENU;
  state.world_origin_geodetic[0] = latitude_deg;
  state.world_origin_geodetic[1] = longitude_deg;
  state.world_origin_geodetic[2] = height_m;
  state.light_size = static_cast<uint32_t>(sizeof(AtmoLightPoint));
  state.lights = lights.data();
  state.light_count = static_cast<uint32_t>(lights.size());
  state.group = group;
  return state;
}

class Plugin {
 public:
  explicit Plugin(const std::string& path, const char* host_name = "atmo C++ host",
                  uint32_t min_version = ATMO_INTERFACE_VERSION_1,
                  uint32_t max_version = ATMO_INTERFACE_VERSION_CURRENT) {
    AtmoResult r = atmo_load_plugin(path.c_str(), min_version, max_version, host_name, &loaded_);
    if (r < 0) throw Error(r, loaded_.error);
  }
  ~Plugin() { atmo_unload_plugin(&loaded_); }
  Plugin(const Plugin&) = delete;
  Plugin& operator=(const Plugin&) = delete;

  const AtmoPluginApi& api() const { return loaded_.api; }
  std::string result_string(AtmoResult r) const { return loaded_.api.result_string(r); }

 private:
  AtmoLoadedPlugin loaded_{};
};

class Context {
 public:
  Context(const Plugin& plugin, const AtmoHostServices* services = nullptr,
          const char* asset_root = nullptr, uint64_t seed = 0)
      : api_(&plugin.api()) {
    auto info = make<AtmoContextCreateInfo>(ATMO_TYPE_CONTEXT_CREATE_INFO);
    info.services = services;
    info.asset_root = asset_root;
    info.application_name = "atmo C++ host";
    info.seed = seed;
    AtmoResult r = api_->create_context(&info, &context_);
    if (r < 0) throw Error(r, std::string("create_context: ") + api_->result_string(r));
  }
  ~Context() {
    if (!context_) return;
    if (gl_alive_) api_->gl_shutdown(context_);
    api_->destroy_context(context_);
  }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // [gl-current]
  void gl_init() {
    check(api_->gl_init(context_), "gl_init");
    gl_alive_ = true;
  }
  // [gl-current]
  void gl_shutdown() {
    check(api_->gl_shutdown(context_), "gl_shutdown");
    gl_alive_ = false;
  }
  void gl_context_lost() {
    check(api_->gl_context_lost(context_), "gl_context_lost");
    gl_alive_ = false;
  }
  void set_atmosphere(const AtmoAtmosphereState& s) { check(api_->set_atmosphere(context_, &s), "set_atmosphere"); }
  void set_frame(const AtmoFrameState& s) { check(api_->set_frame(context_, &s), "set_frame"); }
  std::string last_error() const { return api_->last_error(context_); }
  // Throws on an invalid state; a layer that failed to load (ATMO_ERROR_IO)
  // is returned, not thrown: the clouds are unchanged (last_error says which file).
  AtmoResult set_clouds(const AtmoCloudsState& s) {
    if (!api_->set_clouds) throw std::runtime_error("set_clouds: the plugin has no clouds (an older plugin)");
    AtmoResult r = api_->set_clouds(context_, &s);
    return r == ATMO_ERROR_IO ? r : check(r, "set_clouds");
  }

  void set_fog(const AtmoFogState& s) {
    if (!api_->set_fog) throw std::runtime_error("set_fog: the plugin has no fog (an older plugin)");
    check(api_->set_fog(context_, &s), "set_fog");
  }
  // No fog (an older plugin without fog has none to clear).
  void clear_fog() {
    if (api_->set_fog) check(api_->set_fog(context_, nullptr), "set_fog");
  }
  void set_lights(const AtmoLightsState& s) {
    if (!api_->set_lights) throw std::runtime_error("set_lights: the plugin has no lights (an older plugin)");
    check(api_->set_lights(context_, &s), "set_lights");
  }
  void set_light_group_pose(const AtmoLightGroupPose& p) {
    if (!api_->set_light_group_pose)
      throw std::runtime_error("set_light_group_pose: the plugin has no light groups (an older plugin)");
    check(api_->set_light_group_pose(context_, &p), "set_light_group_pose");
  }
  // The host's objects as occluders of the sky (docs/SKY_OCCLUSION.md); nullptr clears them.
  void set_occluders(const AtmoOccludersState* s) {
    if (!api_->set_occluders) throw std::runtime_error("set_occluders: the plugin has no sky occlusion (an older plugin)");
    check(api_->set_occluders(context_, s), "set_occluders");
  }
  void set_occluder_poses(const AtmoOccluderPoses& p) {
    if (!api_->set_occluder_poses)
      throw std::runtime_error("set_occluder_poses: the plugin has no sky occlusion (an older plugin)");
    check(api_->set_occluder_poses(context_, &p), "set_occluder_poses");
  }
  void update_lights(const AtmoLightsUpdate& u) {
    if (!api_->update_lights) throw std::runtime_error("update_lights: the plugin has no light groups (an older plugin)");
    check(api_->update_lights(context_, &u), "update_lights");
  }

  AtmoContext handle() const { return context_; }
  const AtmoPluginApi& api() const { return *api_; }

  // Throws with the plugin's detailed message on an error; returns statuses.
  AtmoResult check(AtmoResult r, const char* what) const {
    if (r < 0) {
      throw Error(r, std::string(what) + ": " + api_->result_string(r) + ": " + api_->last_error(context_));
    }
    return r;
  }

 private:
  const AtmoPluginApi* api_;
  AtmoContext context_ = nullptr;
  bool gl_alive_ = false;
};

class View {
 public:
  View(Context& context, uint32_t channel_id = 0) : context_(&context) {
    auto info = make<AtmoViewCreateInfo>(ATMO_TYPE_VIEW_CREATE_INFO);
    info.channel_id = channel_id;
    context_->check(context_->api().create_view(context_->handle(), &info, &view_), "create_view");
  }
  ~View() {
    if (view_) context_->api().destroy_view(view_);
  }
  View(const View&) = delete;
  View& operator=(const View&) = delete;

  void set(const AtmoViewState& s) { context_->check(context_->api().set_view(view_, &s), "set_view"); }
  // [gl-current] Returns ATMO_SUCCESS or ATMO_STATUS_NOTHING_TO_DRAW.
  AtmoResult render(AtmoPassKind pass, uint32_t flags = 0) {  // flags: AtmoPassFlags the pass takes
    auto info = make<AtmoPassInfo>(ATMO_TYPE_PASS_INFO);
    info.pass = static_cast<uint32_t>(pass);
    info.flags = flags;
    return context_->check(context_->api().render_pass(view_, &info), "render_pass");
  }
  AtmoLighting lighting() const {
    auto out = make<AtmoLighting>(ATMO_TYPE_LIGHTING);
    context_->check(context_->api().get_lighting(view_, &out), "get_lighting");
    return out;
  }
  // [gl-current] light_count 0 without fog or lights (or from an older plugin).
  AtmoFogLighting fog_lighting() const {
    auto out = make<AtmoFogLighting>(ATMO_TYPE_FOG_LIGHTING);
    if (context_->api().get_fog_lighting)
      context_->check(context_->api().get_fog_lighting(view_, &out), "get_fog_lighting");
    return out;
  }
  // [gl-current] object_count 0 without occluders (or from an older plugin).
  AtmoSkyOcclusion sky_occlusion() const {
    auto out = make<AtmoSkyOcclusion>(ATMO_TYPE_SKY_OCCLUSION);
    if (context_->api().get_sky_occlusion)
      context_->check(context_->api().get_sky_occlusion(view_, &out), "get_sky_occlusion");
    return out;
  }
  // [no-gl] The state this view's next pass draws from, hashed (docs/MULTI_CHANNEL.md); false from a plugin
  // without get_state_hash (out untouched).
  bool state_hash(AtmoStateHash* out) const {
    if (!context_->api().get_state_hash) return false;
    *out = make<AtmoStateHash>(ATMO_TYPE_STATE_HASH);
    context_->check(context_->api().get_state_hash(view_, out), "get_state_hash");
    return true;
  }
  AtmoView handle() const { return view_; }

 private:
  Context* context_;
  AtmoView view_ = nullptr;
};

}  // namespace atmo

#endif  // ATMO_ATMO_HPP
