// entry.cpp — the C ABI: atmo_negotiate and the function table. Each function
// checks its handles and structs, runs behind an exception barrier, and on
// error leaves state unchanged and records a message naming what and where.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <new>
#include <string>

#include "abi/night_sky_inputs.h"
#include "abi/objects.h"
#include "abi/pass_inputs.h"
#include "abi/scene_inputs.h"
#include "abi/struct_io.h"
#include "abi/validation.h"
#include "atmo/atmo.h"

using atmo::abi::HostServices;
using atmo::abi::read_struct;
using atmo::abi::ReadError;

namespace {

constexpr uint32_t kPluginVersion = (0u << 16) | (1u << 8) | 0u;
constexpr uint32_t kMinInterface = ATMO_INTERFACE_VERSION_1;
constexpr uint32_t kMaxInterface = ATMO_INTERFACE_VERSION_1;

// Errors with no live context to hold them (create_context, bad handles).
// A plain buffer, not a std::string: a thread_local with a destructor
// registers it with glibc (__cxa_thread_atexit), which then keeps libatmo.so
// mapped after dlclose for as long as that thread lives.
constexpr size_t kOrphanErrorBytes = 1024;
thread_local char g_orphan_error[kOrphanErrorBytes];

AtmoResult fail(AtmoContext_T* ctx, AtmoResult code, const char* function, const std::string& message) {
  std::string text = std::string(function) + ": " + message;
  if (ctx) {
    ctx->last_error = text;
    ctx->services.log(ATMO_LOG_ERROR, text);
  } else {
    std::snprintf(g_orphan_error, kOrphanErrorBytes, "%s", text.c_str());  // the log line keeps it whole
    HostServices().log(ATMO_LOG_ERROR, text);
  }
  return code;
}

AtmoResult fail(AtmoContext_T* ctx, const char* function, const ReadError& e) {
  return fail(ctx, e.code, function, e.message);
}

// No exception may cross the ABI.
template <typename Body>
AtmoResult guarded(AtmoContext_T* ctx, const char* function, Body&& body) noexcept {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    return fail(ctx, ATMO_ERROR_OUT_OF_MEMORY, function, "out of memory");
  } catch (const std::exception& e) {
    return fail(ctx, ATMO_ERROR_INTERNAL, function, std::string("internal error: ") + e.what());
  } catch (...) {
    return fail(ctx, ATMO_ERROR_INTERNAL, function, "internal error: unknown exception");
  }
}

AtmoContext_T* live_context(AtmoContext context) {
  return atmo::abi::is_live_context(context) ? context : nullptr;
}

const char* result_string(AtmoResult r) {
  switch (r) {
    case ATMO_SUCCESS: return "ATMO_SUCCESS";
    case ATMO_STATUS_NOTHING_TO_DRAW: return "ATMO_STATUS_NOTHING_TO_DRAW";
    case ATMO_STATUS_NOT_YET_SUPPORTED: return "ATMO_STATUS_NOT_YET_SUPPORTED";
    case ATMO_ERROR_INVALID_ARGUMENT: return "ATMO_ERROR_INVALID_ARGUMENT";
    case ATMO_ERROR_INCOMPATIBLE_VERSION: return "ATMO_ERROR_INCOMPATIBLE_VERSION";
    case ATMO_ERROR_STRUCT_TOO_SMALL: return "ATMO_ERROR_STRUCT_TOO_SMALL";
    case ATMO_ERROR_WRONG_STRUCT_TYPE: return "ATMO_ERROR_WRONG_STRUCT_TYPE";
    case ATMO_ERROR_NON_FINITE_VALUE: return "ATMO_ERROR_NON_FINITE_VALUE";
    case ATMO_ERROR_OUT_OF_RANGE: return "ATMO_ERROR_OUT_OF_RANGE";
    case ATMO_ERROR_CALL_OUT_OF_ORDER: return "ATMO_ERROR_CALL_OUT_OF_ORDER";
    case ATMO_ERROR_GL: return "ATMO_ERROR_GL";
    case ATMO_ERROR_OUT_OF_MEMORY: return "ATMO_ERROR_OUT_OF_MEMORY";
    case ATMO_ERROR_IO: return "ATMO_ERROR_IO";
    case ATMO_ERROR_INVALID_HANDLE: return "ATMO_ERROR_INVALID_HANDLE";
    case ATMO_ERROR_INTERNAL: return "ATMO_ERROR_INTERNAL";
    default: return r > 0 ? "unknown status" : "unknown error";
  }
}

const char* last_error(AtmoContext context) {
  AtmoContext_T* ctx = live_context(context);
  return ctx ? ctx->last_error.c_str() : g_orphan_error;
}

AtmoResult create_context(const AtmoContextCreateInfo* info_in, AtmoContext* out) {
  return guarded(nullptr, "create_context", [&]() -> AtmoResult {
    if (!out) return fail(nullptr, ATMO_ERROR_INVALID_ARGUMENT, "create_context", "out_context is NULL");
    *out = nullptr;
    AtmoContextCreateInfo info;
    ReadError e = read_struct(info_in, ATMO_TYPE_CONTEXT_CREATE_INFO, "AtmoContextCreateInfo", &info);
    if (e.code) return fail(nullptr, "create_context", e);
    HostServices services;
    if (info.services) {
      AtmoHostServices s;
      e = read_struct(info.services, ATMO_TYPE_HOST_SERVICES, "AtmoContextCreateInfo.services", &s);
      if (e.code) return fail(nullptr, "create_context", e);
      if ((s.allocate == nullptr) != (s.deallocate == nullptr)) {
        return fail(nullptr, ATMO_ERROR_INVALID_ARGUMENT, "create_context",
                    "AtmoHostServices: allocate and deallocate must both be set or both be NULL");
      }
      if (!((s.file_open && s.file_read && s.file_close) || (!s.file_open && !s.file_read && !s.file_close))) {
        return fail(nullptr, ATMO_ERROR_INVALID_ARGUMENT, "create_context",
                    "AtmoHostServices: file_open, file_read and file_close must all be set or all be NULL");
      }
      services = HostServices(s);
    }
    void* memory = services.allocate(sizeof(AtmoContext_T), alignof(AtmoContext_T));
    if (!memory) return fail(nullptr, ATMO_ERROR_OUT_OF_MEMORY, "create_context", "the allocator returned NULL");
    AtmoContext_T* ctx;
    try {
      ctx = new (memory) AtmoContext_T();
      ctx->services = services;
      ctx->asset_root = info.asset_root ? info.asset_root : atmo::abi::plugin_directory();
      ctx->application_name = info.application_name ? info.application_name : "";
      ctx->seed = info.seed;
    } catch (...) {
      services.deallocate(memory);
      throw;
    }
    atmo::abi::register_context(ctx);
    *out = ctx;
    return ATMO_SUCCESS;
  });
}

template <typename T>
void destroy_object(T* object, const HostServices& services) {
  object->~T();
  services.deallocate(object);
}

void destroy_view_object(AtmoView_T* view) {
  atmo::abi::unregister_view(view);
  HostServices services = view->context->services;
  destroy_object(view, services);
}

void destroy_context(AtmoContext context) {
  if (!context) return;
  guarded(nullptr, "destroy_context", [&]() -> AtmoResult {
    AtmoContext_T* ctx = live_context(context);
    if (!ctx) {
      HostServices().log(ATMO_LOG_HOST_MISBEHAVING, "destroy_context: not a live context (destroyed twice?)");
      return ATMO_ERROR_INVALID_HANDLE;
    }
    atmo::abi::stop_table_builds(ctx);  // cancels a running table build and joins its thread
    for (AtmoView_T* v : ctx->views) destroy_view_object(v);
    ctx->views.clear();
    if (ctx->gl_alive) {
      ctx->services.log(ATMO_LOG_HOST_MISBEHAVING,
                        "destroy_context: gl_shutdown was not called; the plugin's GL objects are leaked");
    }
    atmo::abi::unregister_context(ctx);
    HostServices services = ctx->services;
    destroy_object(ctx, services);
    return ATMO_SUCCESS;
  });
}

struct LoaderThunk {
  AtmoGlProcLoader load;
  void* user;
};

GLADapiproc load_through_host(void* thunk, const char* name) {
  auto* t = static_cast<LoaderThunk*>(thunk);
  void* p = t->load(t->user, name);
  GLADapiproc f = nullptr;
  std::memcpy(&f, &p, sizeof(p));
  return f;
}

AtmoResult gl_init(AtmoContext context) {
  AtmoContext_T* ctx = live_context(context);
  if (!ctx) return fail(nullptr, ATMO_ERROR_INVALID_HANDLE, "gl_init", "not a live context");
  return guarded(ctx, "gl_init", [&]() -> AtmoResult {
    if (ctx->gl_alive) return ATMO_SUCCESS;
    LoaderThunk thunk{ctx->services.gl_loader(), ctx->services.gl_loader_user()};
    if (!thunk.load) {
      return fail(ctx, ATMO_ERROR_GL, "gl_init",
                  "no GL loader: the host gave no gl_get_proc_address and neither eglGetProcAddress nor "
                  "glXGetProcAddressARB is loaded in the process");
    }
    std::string error;
    if (!ctx->renderer.init(&load_through_host, &thunk, &error)) return fail(ctx, ATMO_ERROR_GL, "gl_init", error);
    ctx->gl_alive = true;
    ctx->uploaded_lut_version = 0;
    return ATMO_SUCCESS;
  });
}

AtmoResult gl_shutdown(AtmoContext context) {
  AtmoContext_T* ctx = live_context(context);
  if (!ctx) return fail(nullptr, ATMO_ERROR_INVALID_HANDLE, "gl_shutdown", "not a live context");
  return guarded(ctx, "gl_shutdown", [&]() -> AtmoResult {
    if (!ctx->gl_alive) return ATMO_SUCCESS;
    ctx->night_renderer.destroy();
    ctx->cloud_renderer.destroy();
    ctx->fog_renderer.destroy();
    ctx->renderer.destroy();
    ctx->gl_alive = false;
    ctx->uploaded_lut_version = 0;
    return ATMO_SUCCESS;
  });
}

AtmoResult gl_context_lost(AtmoContext context) {
  AtmoContext_T* ctx = live_context(context);
  if (!ctx) return fail(nullptr, ATMO_ERROR_INVALID_HANDLE, "gl_context_lost", "not a live context");
  ctx->renderer.forget();
  ctx->night_renderer.forget();
  ctx->cloud_renderer.forget();
  ctx->fog_renderer.forget();
  ctx->gl_alive = false;
  ctx->uploaded_lut_version = 0;
  return ATMO_SUCCESS;
}

AtmoResult create_view(AtmoContext context, const AtmoViewCreateInfo* info_in, AtmoView* out) {
  AtmoContext_T* ctx = live_context(context);
  if (!ctx) return fail(nullptr, ATMO_ERROR_INVALID_HANDLE, "create_view", "not a live context");
  return guarded(ctx, "create_view", [&]() -> AtmoResult {
    if (!out) return fail(ctx, ATMO_ERROR_INVALID_ARGUMENT, "create_view", "out_view is NULL");
    *out = nullptr;
    AtmoViewCreateInfo info;
    ReadError e = read_struct(info_in, ATMO_TYPE_VIEW_CREATE_INFO, "AtmoViewCreateInfo", &info);
    if (e.code) return fail(ctx, "create_view", e);
    void* memory = ctx->services.allocate(sizeof(AtmoView_T), alignof(AtmoView_T));
    if (!memory) return fail(ctx, ATMO_ERROR_OUT_OF_MEMORY, "create_view", "the allocator returned NULL");
    auto* view = new (memory) AtmoView_T();
    view->context = ctx;
    view->channel_id = info.channel_id;
    try {
      ctx->views.push_back(view);
    } catch (...) {
      destroy_object(view, ctx->services);
      throw;
    }
    atmo::abi::register_view(view);
    *out = view;
    return ATMO_SUCCESS;
  });
}

void destroy_view(AtmoView view) {
  if (!view) return;
  if (!atmo::abi::is_live_view(view)) {
    HostServices().log(ATMO_LOG_HOST_MISBEHAVING, "destroy_view: not a live view (destroyed twice?)");
    return;
  }
  AtmoContext_T* ctx = view->context;
  for (size_t i = 0; i < ctx->views.size(); ++i) {
    if (ctx->views[i] == view) {
      ctx->views.erase(ctx->views.begin() + static_cast<long>(i));
      break;
    }
  }
  destroy_view_object(view);
}

AtmoResult set_atmosphere(AtmoContext context, const AtmoAtmosphereState* state) {
  AtmoContext_T* ctx = live_context(context);
  if (!ctx) return fail(nullptr, ATMO_ERROR_INVALID_HANDLE, "set_atmosphere", "not a live context");
  return guarded(ctx, "set_atmosphere", [&]() -> AtmoResult {
    AtmoAtmosphereState s;
    ReadError e = read_struct(state, ATMO_TYPE_ATMOSPHERE_STATE, "AtmoAtmosphereState", &s);
    if (e.code) return fail(ctx, "set_atmosphere", e);
    atmo::core::AtmosphereSettings settings;
    atmo::abi::Verdict v = atmo::abi::validate_atmosphere(s, &settings);
    if (!v.ok()) return fail(ctx, v.code, "set_atmosphere", v.message);
    ctx->atmosphere = settings;
    atmo::abi::air_changed(ctx);  // starts building the new air's tables now (worker thread)
    return ATMO_SUCCESS;
  });
}

AtmoResult set_frame(AtmoContext context, const AtmoFrameState* state) {
  AtmoContext_T* ctx = live_context(context);
  if (!ctx) return fail(nullptr, ATMO_ERROR_INVALID_HANDLE, "set_frame", "not a live context");
  return guarded(ctx, "set_frame", [&]() -> AtmoResult {
    AtmoFrameState s;
    ReadError e = read_struct(state, ATMO_TYPE_FRAME_STATE, "AtmoFrameState", &s);
    if (e.code) return fail(ctx, "set_frame", e);
    atmo::abi::Verdict v = atmo::abi::validate_frame(s);
    if (!v.ok()) return fail(ctx, v.code, "set_frame", v.message);
    ctx->utc_posix_s = s.utc_posix_s;
    ctx->dut1_s = s.dut1_s;
    ctx->frame_number = s.host_frame_number;
    ctx->have_frame = true;
    return ATMO_SUCCESS;
  });
}

AtmoView_T* live_view(AtmoView view, const char* function) {
  if (atmo::abi::is_live_view(view)) return view;
  fail(nullptr, ATMO_ERROR_INVALID_HANDLE, function, "not a live view");
  return nullptr;
}

AtmoResult set_view(AtmoView view_handle, const AtmoViewState* state) {
  AtmoView_T* view = live_view(view_handle, "set_view");
  if (!view) return ATMO_ERROR_INVALID_HANDLE;
  AtmoContext_T* ctx = view->context;
  return guarded(ctx, "set_view", [&]() -> AtmoResult {
    AtmoViewState s;
    ReadError e = read_struct(state, ATMO_TYPE_VIEW_STATE, "AtmoViewState", &s);
    if (e.code) return fail(ctx, "set_view", e);
    atmo::core::EyeFrame eye;
    atmo::abi::Verdict v = atmo::abi::validate_view(s, &eye);
    if (!v.ok()) return fail(ctx, v.code, "set_view", v.message);
    s.header.next = nullptr;  // the host's chain need not outlive the call
    view->state = s;
    view->eye = eye;
    view->have_state = true;
    ++view->state_serial;
    return ATMO_SUCCESS;
  });
}

// The night sky's stars and planets (the Moon, the moonlit sky and the faint
// background are drawn by the sky pass). The plan already said something can show.
AtmoResult night_sky_pass(AtmoContext_T* ctx, AtmoView_T* view, const atmo::core::Scene& scene,
                          const atmo::gl::PassInputs& inputs) {
  std::string error;
  if (!atmo::abi::collect_night_points(ctx, *view, scene, &error)) {
    return fail(ctx, ATMO_ERROR_INVALID_ARGUMENT, "render_pass(ATMO_PASS_NIGHT_SKY)", "astrometry: " + error);
  }
  if (view->night_points.empty()) return ATMO_STATUS_NOTHING_TO_DRAW;
  if (!ctx->night_renderer.initialised() && !ctx->night_renderer.init(&error)) {
    return fail(ctx, ATMO_ERROR_GL, "render_pass(ATMO_PASS_NIGHT_SKY)", error);
  }
  atmo::gl::NightSkyTextures textures;
  if (!ctx->renderer.night_sky_textures(inputs, &textures, &error) ||
      !ctx->night_renderer.draw_points(inputs, textures, view->night_points, &error)) {
    return fail(ctx, ATMO_ERROR_GL, "render_pass(ATMO_PASS_NIGHT_SKY)", error);
  }
  return ATMO_SUCCESS;
}

AtmoResult clouds_pass(AtmoContext_T* ctx, AtmoView_T* view, const atmo::core::Scene& scene,
                       const atmo::gl::PassInputs& inputs);
AtmoResult fog_pass(AtmoContext_T* ctx, AtmoView_T* view, const atmo::core::Scene& scene,
                    const atmo::gl::PassInputs& inputs);

// The clouds' shadow on the sunlit air for the sky and aerial-perspective
// passes (functions.glsl CloudShadowing): the map of get_cloud_shadows, made
// on the first such pass and kept by the relights, when there are clouds and
// the Sun lights them (under the Moon the map is the Moon's; the sky's Sun
// term is left alone). False and *error on a GL failure.
bool add_cloud_shadow(AtmoContext_T* ctx, AtmoView_T* view, const atmo::core::Scene& scene,
                      atmo::gl::PassInputs* inputs, std::string* error) {
  atmo::abi::ContextClouds& c = ctx->clouds;
  if (c.empty()) return true;  // no clouds: no cost
  const glm::dvec3 light = atmo::abi::cloud_light(ctx, view, scene).direction_enu;
  const glm::dmat3 clouds_from_eye_axes = atmo::abi::cloud_enu_from_eye_enu(c, view->eye.ecef_from_enu);
  if (glm::dot(clouds_from_eye_axes * scene.sun_direction_enu, light) < std::cos(0.5 * M_PI / 180.0)) return true;
  atmo::abi::relight_clouds(&c, light);
  atmo::abi::update_cloud_shadow(&c);
  GLuint texture = 0;
  if (!ctx->cloud_renderer.shadow_texture(c.shadow, c.field_version, c.shadow_version, &texture, error)) return false;
  if (!texture) return true;  // the light is too low for any map
  // A point relative to the eye (its ENU axes) -> the clouds' ENU -> (u, v, height).
  glm::dmat4 clouds_from_eye(clouds_from_eye_axes);
  clouds_from_eye[3] = glm::dvec4(atmo::abi::eye_in_cloud_frame(c, view->eye.eye_ecef_m), 1.0);
  inputs->cloud_shadow.texture = texture;
  inputs->cloud_shadow.uv_from_eye_enu = glm::mat4(atmo::clouds::cloud_shadow_uvz_from(c.shadow, clouds_from_eye));
  inputs->cloud_shadow.base_m = static_cast<float>(c.lowest_base_m);
  inputs->cloud_shadow.top_m = static_cast<float>(c.highest_top_m);
  inputs->cloud_shadow.version = (c.field_version << 32) ^ c.shadow_version;
  return true;
}

AtmoResult render_pass(AtmoView view_handle, const AtmoPassInfo* pass_in) {
  AtmoView_T* view = live_view(view_handle, "render_pass");
  if (!view) return ATMO_ERROR_INVALID_HANDLE;
  AtmoContext_T* ctx = view->context;
  return guarded(ctx, "render_pass", [&]() -> AtmoResult {
    AtmoPassInfo pass;
    ReadError e = read_struct(pass_in, ATMO_TYPE_PASS_INFO, "AtmoPassInfo", &pass);
    if (e.code) return fail(ctx, "render_pass", e);
    if (pass.pass >= ATMO_PASS_COUNT) {
      return fail(ctx, ATMO_ERROR_INVALID_ARGUMENT, "render_pass",
                  "AtmoPassInfo.pass = " + std::to_string(pass.pass) + " is not an AtmoPass");
    }
    if (!ctx->gl_alive) {
      return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, "render_pass",
                  "gl_init has not been called on this context (or the GL context was lost)");
    }
    if (!ctx->have_frame) return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, "render_pass", "set_frame has not been called");
    if (!view->have_state) return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, "render_pass", "set_view has not been called");

    switch (pass.pass) {
      case ATMO_PASS_CLOUDS:
        if (ctx->clouds.empty()) return ATMO_STATUS_NOTHING_TO_DRAW;  // no clouds: no cost
        break;
      case ATMO_PASS_LIGHT_GLOWS:
        if (!ctx->fog.enabled()) return ATMO_STATUS_NOTHING_TO_DRAW;  // no fog: no cost
        break;
      case ATMO_PASS_AERIAL_PERSPECTIVE:
        if (view->state.depth_texture == 0) return ATMO_STATUS_NOTHING_TO_DRAW;
        break;
      default:
        break;
    }
    atmo::core::Scene scene = atmo::abi::prepare_scene(ctx, *view);
    atmo::gl::PassInputs inputs = atmo::abi::make_pass_inputs(scene, *view, ctx->lut, ctx->multiple_scattering);
    if (pass.pass == ATMO_PASS_AERIAL_PERSPECTIVE || pass.pass == ATMO_PASS_CLOUDS) {
      // At night the haze over the geometry is lit by the Moon (the plan of this view's last sky or night pass).
      atmo::abi::light_haze_by_the_moon(*view, scene, &inputs);
    }
    if (pass.pass == ATMO_PASS_SKY || pass.pass == ATMO_PASS_NIGHT_SKY) {
      const atmo::core::night::NightPlan& night = atmo::abi::plan_night_sky(ctx, *view, scene, inputs);
      // Daylight: no star or planet can change a pixel, so the night pass does no work at all (no GL call).
      if (pass.pass == ATMO_PASS_NIGHT_SKY && atmo::abi::night_points_invisible(ctx, night)) {
        return ATMO_STATUS_NOTHING_TO_DRAW;
      }
      atmo::abi::add_night_terms(ctx, *view, scene, &inputs);
    }
    if (view->state.depth_texture != 0 && !glIsTexture(view->state.depth_texture)) {
      return fail(ctx, ATMO_ERROR_INVALID_ARGUMENT, "render_pass",
                  "AtmoViewState.depth_texture = " + std::to_string(view->state.depth_texture) +
                      " is not a texture in the current GL context");
    }
    if (ctx->uploaded_lut_version != ctx->lut_version) {
      ctx->renderer.upload_tables(ctx->lut, ctx->multiple_scattering);
      ctx->uploaded_lut_version = ctx->lut_version;
    }
    std::string error;
    if ((pass.pass == ATMO_PASS_SKY || pass.pass == ATMO_PASS_AERIAL_PERSPECTIVE || pass.pass == ATMO_PASS_CLOUDS) &&
        !add_cloud_shadow(ctx, view, scene, &inputs, &error))
      return fail(ctx, ATMO_ERROR_GL, "render_pass", error);
    if (pass.pass == ATMO_PASS_NIGHT_SKY) return night_sky_pass(ctx, view, scene, inputs);
    if (pass.pass == ATMO_PASS_LIGHT_GLOWS) return fog_pass(ctx, view, scene, inputs);
    if (pass.pass == ATMO_PASS_CLOUDS) return clouds_pass(ctx, view, scene, inputs);
    bool ok = pass.pass == ATMO_PASS_SKY ? ctx->renderer.draw_sky(inputs, &error)
                                         : ctx->renderer.draw_aerial_perspective(inputs, &error);
    if (!ok) return fail(ctx, ATMO_ERROR_GL, "render_pass", error);
    return ATMO_SUCCESS;
  });
}

AtmoResult set_clouds(AtmoContext context, const AtmoCloudsState* state) {
  AtmoContext_T* ctx = live_context(context);
  if (!ctx) return fail(nullptr, ATMO_ERROR_INVALID_HANDLE, "set_clouds", "not a live context");
  return guarded(ctx, "set_clouds", [&]() -> AtmoResult {
    AtmoCloudsState s;
    ReadError e = read_struct(state, ATMO_TYPE_CLOUDS_STATE, "AtmoCloudsState", &s);
    if (e.code) return fail(ctx, "set_clouds", e);
    std::vector<std::string> load_errors;
    atmo::abi::Verdict v = atmo::abi::build_clouds(s, *ctx, &ctx->clouds, &load_errors);
    for (const std::string& line : load_errors)
      ctx->services.log(line.find(": warning: ") != std::string::npos ? ATMO_LOG_WARNING : ATMO_LOG_ERROR, line);
    if (!v.ok()) return fail(ctx, v.code, "set_clouds", v.message);
    const atmo::clouds::CloudField& f = ctx->clouds.field;
    ctx->services.log(ATMO_LOG_INFO, "clouds: " + std::to_string(f.instances.size()) + " clouds from " +
                                         std::to_string(f.prototypes.size()) + " volumes, " +
                                         std::to_string(f.memory_bytes() >> 20) + " MiB of density");
    return ATMO_SUCCESS;
  });
}

AtmoResult clouds_pass(AtmoContext_T* ctx, AtmoView_T* view, const atmo::core::Scene& scene,
                       const atmo::gl::PassInputs& inputs) {
  atmo::abi::ContextClouds& c = ctx->clouds;
  atmo::gl::CloudFrameInputs frame;
  frame.light = atmo::abi::cloud_light(ctx, view, scene);
  atmo::abi::relight_clouds(&c, frame.light.direction_enu);
  frame.field = &c.field;
  frame.depths = &c.depths;
  frame.version = c.version;
  frame.eye_in_clouds_m = atmo::abi::eye_in_cloud_frame(c, view->eye.eye_ecef_m);
  frame.eye_enu_from_clouds = glm::transpose(atmo::abi::cloud_enu_from_eye_enu(c, view->eye.ecef_from_enu));
  frame.field_version = c.field_version;
  frame.direct_only = c.settings.direct_only;
  frame.impostors = c.settings.impostors;
  frame.octaves = atmo::clouds::default_octaves();
  frame.octaves.count = c.settings.octaves;
  frame.divisor = c.settings.march_divisor;
  frame.step_voxels = c.settings.march_step_voxels;
  bool drawn = false;
  std::string error;
  if (!ctx->cloud_renderer.draw(ctx->renderer, inputs, frame, &drawn, &error))
    return fail(ctx, ATMO_ERROR_GL, "render_pass(ATMO_PASS_CLOUDS)", error);
  const atmo::gl::CloudDrawStats& st = ctx->cloud_renderer.last_stats();
  ctx->services.log(ATMO_LOG_DEBUG, "clouds: " + std::to_string(st.in_view) + " in view, " +
                                        std::to_string(st.impostors_drawn) + " from impostors (" +
                                        std::to_string(st.impostors_created) + " new, " +
                                        std::to_string(st.impostors_updated) + " re-rendered, " +
                                        std::to_string(st.impostors_stale) + " stale left), " +
                                        std::to_string(st.marched) + " marched; impostor atlas " +
                                        std::to_string(ctx->cloud_renderer.impostor_bytes() >> 20) + " MiB");
  return drawn ? ATMO_SUCCESS : ATMO_STATUS_NOTHING_TO_DRAW;
}

// The glow threshold of a frame: the host's, or 1/2000 of the view's white.
double glow_threshold(const AtmoContext_T* ctx, const AtmoView_T* view) {
  if (ctx->lights.glow_threshold_cd_m2 > 0.0) return ctx->lights.glow_threshold_cd_m2;
  const double exposure = view->state.exposure_scale > 0.0 ? view->state.exposure_scale : atmo::abi::kDefaultExposureScale;
  return 1.0 / (2000.0 * exposure);
}

// The view's lights in the fog, made once per set_view / set_fog / set_lights.
const atmo::abi::FogFrame& view_fog_frame(AtmoContext_T* ctx, AtmoView_T* view) {
  if (!view->fog_frame || view->fog_frame_context_serial != ctx->fog_serial ||
      view->fog_frame_view_serial != view->state_serial) {
    view->fog_frame = atmo::abi::make_fog_frame(ctx->fog, ctx->lights, view->eye, glow_threshold(ctx, view));
    view->fog_frame_context_serial = ctx->fog_serial;
    view->fog_frame_view_serial = view->state_serial;
  }
  return *view->fog_frame;
}

AtmoResult fog_pass(AtmoContext_T* ctx, AtmoView_T* view, const atmo::core::Scene& scene,
                    const atmo::gl::PassInputs& inputs) {
  const atmo::abi::FogFrame& frame = view_fog_frame(ctx, view);
  atmo::gl::FogDrawInputs in;
  in.frame = &frame;
  in.extinction_per_m = static_cast<float>(ctx->fog.optics.extinction_per_m);
  in.albedo = static_cast<float>(ctx->fog.optics.albedo);
  // The fog's isotropic light from the sky, Sun and Moon: albedo times the mean radiance around it, the
  // sky above and the ground's reflection below (docs/FOG.md: a crude term, right in thin fog and at night).
  const atmo::core::SkyLighting& sky = atmo::abi::view_sky_lighting(ctx, view, scene);
  const glm::dvec3 sun = glm::dvec3(scene.atmosphere.sun_illuminance_lux) * std::max(scene.sun_direction_enu.z, 0.0);
  const glm::dvec3 moon = scene.bodies.moon_illuminance_rgb_lux * std::max(scene.bodies.moon_enu.z, 0.0);
  const glm::dvec3 horizontal = sky.horizontal_illuminance_lux + sun + moon;
  in.ambient_cd_m2 = glm::vec3(ctx->fog.optics.albedo * 0.5 *
                               (sky.average_radiance + ctx->atmosphere.ground_albedo * horizontal / M_PI));
  const double tan_half = 1.0 / std::max(std::abs(view->state.clip_from_view[5]), 1e-12);
  // 0.2836 of a pixel (2 tan_half / rows): the glow's 1/gamma core averaged over the pixel on the light.
  in.min_sin = static_cast<float>(0.5672 * tan_half / static_cast<double>(view->state.viewport[3]));
  std::string error;
  if (!ctx->fog_renderer.upload_tables(ctx->fog.airlight, ctx->fog.surface, ctx->fog.version, &error) ||
      !ctx->fog_renderer.draw(ctx->renderer, inputs, in, &error))
    return fail(ctx, ATMO_ERROR_GL, "render_pass(ATMO_PASS_LIGHT_GLOWS)", error);
  const atmo::gl::FogDrawStats& st = ctx->fog_renderer.last_stats();
  ctx->services.log(ATMO_LOG_DEBUG, "fog: " + std::to_string(st.lights) + " lights, " +
                                        std::to_string(st.glows_drawn) + " glows drawn over " +
                                        std::to_string(static_cast<long long>(st.covered_pixels)) + " pixels");
  return ATMO_SUCCESS;
}

AtmoResult set_fog(AtmoContext context, const AtmoFogState* state) {
  AtmoContext_T* ctx = live_context(context);
  if (!ctx) return fail(nullptr, ATMO_ERROR_INVALID_HANDLE, "set_fog", "not a live context");
  return guarded(ctx, "set_fog", [&]() -> AtmoResult {
    if (!state) {
      ctx->fog.optics = atmo::fog::FogOptics{};
      ctx->fog.optics.extinction_per_m = 0.0;
      ++ctx->fog_serial;
      return ATMO_SUCCESS;
    }
    AtmoFogState s;
    ReadError e = read_struct(state, ATMO_TYPE_FOG_STATE, "AtmoFogState", &s);
    if (e.code) return fail(ctx, "set_fog", e);
    atmo::abi::Verdict v = atmo::abi::set_fog_state(s, &ctx->fog);
    if (!v.ok()) return fail(ctx, v.code, "set_fog", v.message);
    ++ctx->fog_serial;
    return ATMO_SUCCESS;
  });
}

AtmoResult set_lights(AtmoContext context, const AtmoLightsState* state) {
  AtmoContext_T* ctx = live_context(context);
  if (!ctx) return fail(nullptr, ATMO_ERROR_INVALID_HANDLE, "set_lights", "not a live context");
  return guarded(ctx, "set_lights", [&]() -> AtmoResult {
    if (!state) {
      ctx->lights = atmo::abi::ContextLights{};
      ++ctx->fog_serial;
      return ATMO_SUCCESS;
    }
    AtmoLightsState s;
    ReadError e = read_struct(state, ATMO_TYPE_LIGHTS_STATE, "AtmoLightsState", &s);
    if (e.code) return fail(ctx, "set_lights", e);
    atmo::abi::Verdict v = atmo::abi::set_lights_state(s, &ctx->lights);
    if (!v.ok()) return fail(ctx, v.code, "set_lights", v.message);
    ++ctx->fog_serial;
    return ATMO_SUCCESS;
  });
}

AtmoResult get_fog_lighting(AtmoView view_handle, AtmoFogLighting* out) {
  AtmoView_T* view = live_view(view_handle, "get_fog_lighting");
  if (!view) return ATMO_ERROR_INVALID_HANDLE;
  AtmoContext_T* ctx = view->context;
  return guarded(ctx, "get_fog_lighting", [&]() -> AtmoResult {
    AtmoFogLighting f;
    ReadError e = read_struct(out, ATMO_TYPE_FOG_LIGHTING, "AtmoFogLighting", &f);
    if (e.code) return fail(ctx, "get_fog_lighting", e);
    if (!ctx->gl_alive)
      return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, "get_fog_lighting", "gl_init has not been called on this context");
    if (!ctx->have_frame)
      return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, "get_fog_lighting", "set_frame has not been called");
    if (!view->have_state)
      return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, "get_fog_lighting", "set_view has not been called");
    AtmoResult result = ATMO_STATUS_NOTHING_TO_DRAW;
    std::memset(reinterpret_cast<char*>(&f) + sizeof(f.header), 0, sizeof(f) - sizeof(f.header));
    if (ctx->fog.enabled() && !ctx->lights.lights.empty()) {
      const double threshold = glow_threshold(ctx, view);
      const atmo::abi::FogFrame& frame = view_fog_frame(ctx, view);
      // The view's world axes from the eye's ENU.
      glm::dmat3 world_from_ecef(1.0);
      if (view->state.world_frame == ATMO_WORLD_ENU) {
        const double* o = view->state.world_origin_geodetic;
        world_from_ecef = glm::transpose(atmo::core::ecef_from_enu(o[0], o[1]));
      }
      const glm::dmat3 world_from_enu = world_from_ecef * view->eye.ecef_from_enu;
      const std::vector<float> range = atmo::abi::surface_light_ranges(ctx->fog, frame, threshold);
      std::string error;
      if (!ctx->fog_renderer.upload_tables(ctx->fog.airlight, ctx->fog.surface, ctx->fog.version, &error) ||
          !ctx->fog_renderer.upload_host_lights(frame, world_from_enu, range, &error))
        return fail(ctx, ATMO_ERROR_GL, "get_fog_lighting", error);
      f.light_count = static_cast<uint32_t>(frame.lights.size());
      f.light_texture = ctx->fog_renderer.light_texture();
      f.surface_table = ctx->fog_renderer.surface_table();
      f.surface_table_size[0] = ctx->fog.surface.width;
      f.surface_table_size[1] = ctx->fog.surface.height / atmo::fog::kSurfaceLayers;
      f.medium[0] = ctx->fog.optics.extinction_per_m;
      f.medium[1] = ctx->fog.optics.albedo;
      f.medium[2] = frame.top_above_eye_m;
      for (int i = 0; i < 4; ++i) f.diffusion[i] = frame.diffusion[i];
      const glm::dvec3 up = world_from_enu * glm::dvec3(0.0, 0.0, 1.0);
      for (int i = 0; i < 3; ++i) f.up_world[i] = up[i];
      result = ATMO_SUCCESS;
    }
    const size_t n = out->header.struct_size < sizeof(f) ? out->header.struct_size : sizeof(f);
    f.header = out->header;
    std::memcpy(static_cast<void*>(out), &f, n);
    return result;
  });
}

AtmoResult get_lighting(AtmoView view_handle, AtmoLighting* out) {
  AtmoView_T* view = live_view(view_handle, "get_lighting");
  if (!view) return ATMO_ERROR_INVALID_HANDLE;
  AtmoContext_T* ctx = view->context;
  return guarded(ctx, "get_lighting", [&]() -> AtmoResult {
    AtmoLighting l;
    ReadError e = read_struct(out, ATMO_TYPE_LIGHTING, "AtmoLighting", &l);
    if (e.code) return fail(ctx, "get_lighting", e);
    if (!ctx->have_frame) return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, "get_lighting", "set_frame has not been called");
    if (!view->have_state) return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, "get_lighting", "set_view has not been called");
    atmo::core::Scene scene = atmo::abi::prepare_scene(ctx, *view);
    const glm::dvec3& enu = scene.sun_direction_enu;
    for (int i = 0; i < 3; ++i) {
      l.sun_direction_ecef[i] = scene.sun_direction_ecef[i];
      l.sun_direction_enu[i] = enu[i];
    }
    l.sun_elevation_rad = std::asin(glm::clamp(enu.z, -1.0, 1.0));
    double azimuth = std::atan2(enu.x, enu.y);
    l.sun_azimuth_rad = azimuth < 0.0 ? azimuth + 2.0 * M_PI : azimuth;
    const auto& atm = scene.atmosphere;
    float r = atm.bottom_radius_m + static_cast<float>(scene.eye_altitude_m);
    glm::vec3 t = atmo::twin::transmittance_to_sun(atm, ctx->lut, glm::vec2(ctx->lut.width, ctx->lut.height), r,
                                                   static_cast<float>(enu.z));
    for (int i = 0; i < 3; ++i) l.sun_illuminance_lux[i] = static_cast<double>(atm.sun_illuminance_lux[i] * t[i]);
    // The Moon: the same transmittance table along its direction (0 where the ray meets the Earth).
    const atmo::core::SkyBodies& bodies = scene.bodies;
    const glm::dvec3 moon_ecef = view->eye.ecef_from_enu * bodies.moon_enu;
    const glm::vec3 moon_t = atmo::twin::transmittance_to_sun(atm, ctx->lut, glm::vec2(ctx->lut.width, ctx->lut.height),
                                                              r, static_cast<float>(bodies.moon_enu.z));
    for (int i = 0; i < 3; ++i) {
      l.moon_direction_ecef[i] = moon_ecef[i];
      l.moon_direction_enu[i] = bodies.moon_enu[i];
      l.moon_illuminance_lux[i] = bodies.moon_illuminance_rgb_lux[i] * static_cast<double>(moon_t[i]);
    }
    l.moon_elevation_rad = std::asin(glm::clamp(bodies.moon_enu.z, -1.0, 1.0));
    const double moon_azimuth = std::atan2(bodies.moon_enu.x, bodies.moon_enu.y);
    l.moon_azimuth_rad = moon_azimuth < 0.0 ? moon_azimuth + 2.0 * M_PI : moon_azimuth;
    l.moon_illuminated_fraction = bodies.moon_illuminated_fraction;
    l.moon_phase_angle_rad = bodies.moon_phase_angle_rad;
    const atmo::core::SkyLighting& sky = atmo::abi::view_sky_lighting(ctx, view, scene);
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 9; ++k) l.sky_irradiance_sh9[k][i] = sky.irradiance_sh9[k][i];
      l.sky_illuminance_horizontal_lux[i] = sky.horizontal_illuminance_lux[i];
      l.sky_average_radiance[i] = sky.average_radiance[i];
    }
    if (ctx->gl_alive) {
      const double thickness_m = static_cast<double>(atm.top_radius_m - atm.bottom_radius_m);
      if (atmo::abi::resolve_sky_method(view->state.sky_method, scene.eye_altitude_m, thickness_m) !=
          atmo::gl::SkyMethod::kMarch) {
        l.aerial_inscatter_texture = ctx->renderer.aerial_inscatter_texture();
        l.aerial_transmittance_texture = ctx->renderer.aerial_transmittance_texture();
      }
      l.aerial_range_m = atmo::abi::aerial_volume_range_m(scene, view->state, view->eye.view_from_clip);
      l.aerial_slices = static_cast<uint32_t>(ctx->renderer.lut_settings().aerial_slices);
    }
    // Write back what the host's struct can hold, keeping its header.
    size_t n = out->header.struct_size < sizeof(l) ? out->header.struct_size : sizeof(l);
    l.header = out->header;
    std::memcpy(static_cast<void*>(out), &l, n);
    return ATMO_SUCCESS;
  });
}

AtmoResult get_cloud_shadows(AtmoView view_handle, AtmoCloudShadows* out) {
  AtmoView_T* view = live_view(view_handle, "get_cloud_shadows");
  if (!view) return ATMO_ERROR_INVALID_HANDLE;
  AtmoContext_T* ctx = view->context;
  return guarded(ctx, "get_cloud_shadows", [&]() -> AtmoResult {
    AtmoCloudShadows m;
    ReadError e = read_struct(out, ATMO_TYPE_CLOUD_SHADOWS, "AtmoCloudShadows", &m);
    if (e.code) return fail(ctx, "get_cloud_shadows", e);
    if (!ctx->gl_alive)
      return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, "get_cloud_shadows", "gl_init has not been called on this context");
    if (!ctx->have_frame)
      return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, "get_cloud_shadows", "set_frame has not been called");
    if (!view->have_state)
      return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, "get_cloud_shadows", "set_view has not been called");
    AtmoResult result = ATMO_STATUS_NOTHING_TO_DRAW;
    atmo::abi::ContextClouds& c = ctx->clouds;
    if (!c.empty()) {
      const atmo::core::Scene scene = atmo::abi::prepare_scene(ctx, *view);
      atmo::abi::relight_clouds(&c, atmo::abi::cloud_light(ctx, view, scene).direction_enu);
      atmo::abi::update_cloud_shadow(&c);
      GLuint texture = 0;
      std::string error;
      if (!ctx->cloud_renderer.shadow_texture(c.shadow, c.field_version, c.shadow_version, &texture, &error))
        return fail(ctx, ATMO_ERROR_GL, "get_cloud_shadows", error);
      if (texture) {
        // The host's world -> ECEF -> the clouds' ENU -> the map's (u, v).
        glm::dmat4 ecef_from_world(1.0);
        if (view->state.world_frame == ATMO_WORLD_ENU) {
          const double* o = view->state.world_origin_geodetic;
          ecef_from_world = glm::dmat4(atmo::core::ecef_from_enu(o[0], o[1]));
          ecef_from_world[3] = glm::dvec4(atmo::core::ecef_from_geodetic({o[0], o[1], o[2]}), 1.0);
        }
        glm::dmat4 clouds_from_ecef(glm::transpose(c.ecef_from_enu));
        clouds_from_ecef[3] = glm::dvec4(-(glm::transpose(c.ecef_from_enu) * c.origin_ecef_m), 1.0);
        const glm::dmat4 uv = atmo::clouds::cloud_shadow_uv_from_enu(c.shadow) * clouds_from_ecef * ecef_from_world;
        for (int col = 0; col < 4; ++col)
          for (int row = 0; row < 4; ++row) m.uv_from_world[col * 4 + row] = uv[col][row];
        const glm::dvec3 light_world = glm::transpose(glm::dmat3(ecef_from_world)) *
                                       (c.ecef_from_enu * c.shadow.light_direction_enu);
        for (int i = 0; i < 3; ++i) m.light_direction_world[i] = light_world[i];
        m.texture = texture;
        m.size = static_cast<uint32_t>(c.shadow.size);
        m.texel_m = c.shadow.texel_m;
        result = ATMO_SUCCESS;
      }
    }
    if (result != ATMO_SUCCESS) {
      m.texture = 0;
      m.size = 0;
    }
    const size_t n = out->header.struct_size < sizeof(m) ? out->header.struct_size : sizeof(m);
    m.header = out->header;
    std::memcpy(static_cast<void*>(out), &m, n);
    return result;
  });
}

const AtmoPluginApi kApi = {
    {ATMO_TYPE_PLUGIN_API, sizeof(AtmoPluginApi), nullptr},
    ATMO_INTERFACE_VERSION_1,
    kPluginVersion,
    "Atmo",
    &result_string,
    &last_error,
    &create_context,
    &destroy_context,
    &gl_init,
    &gl_shutdown,
    &gl_context_lost,
    &create_view,
    &destroy_view,
    &set_atmosphere,
    &set_frame,
    &set_view,
    &render_pass,
    &get_lighting,
    &set_clouds,
    &get_cloud_shadows,
    &set_fog,
    &set_lights,
    &get_fog_lighting,
};

}  // namespace

extern "C" ATMO_EXPORT AtmoResult atmo_negotiate(const AtmoNegotiateInfo* host, AtmoPluginApi* api) {
  return guarded(nullptr, "atmo_negotiate", [&]() -> AtmoResult {
    AtmoNegotiateInfo info;
    ReadError e = read_struct(host, ATMO_TYPE_NEGOTIATE_INFO, "AtmoNegotiateInfo", &info);
    if (e.code) return fail(nullptr, "atmo_negotiate", e);
    if (!api) return fail(nullptr, ATMO_ERROR_INVALID_ARGUMENT, "atmo_negotiate", "api is NULL");
    if (api->header.type != ATMO_TYPE_PLUGIN_API) {
      return fail(nullptr, ATMO_ERROR_WRONG_STRUCT_TYPE, "atmo_negotiate", "api->header.type is not ATMO_TYPE_PLUGIN_API");
    }
    if (api->header.struct_size < atmo::abi::V1Size<AtmoPluginApi>::value) {
      return fail(nullptr, ATMO_ERROR_STRUCT_TOO_SMALL, "atmo_negotiate",
                  "api->header.struct_size is " + std::to_string(api->header.struct_size) +
                      " bytes, version 1 needs " + std::to_string(atmo::abi::V1Size<AtmoPluginApi>::value));
    }
    if (info.min_interface_version == 0 || info.min_interface_version > info.max_interface_version) {
      return fail(nullptr, ATMO_ERROR_INVALID_ARGUMENT, "atmo_negotiate",
                  "host interface range [" + std::to_string(info.min_interface_version) + ", " +
                      std::to_string(info.max_interface_version) + "] is empty or starts at 0");
    }
    uint32_t chosen = info.max_interface_version < kMaxInterface ? info.max_interface_version : kMaxInterface;
    uint32_t lowest = info.min_interface_version > kMinInterface ? info.min_interface_version : kMinInterface;
    if (chosen < lowest) {
      return fail(nullptr, ATMO_ERROR_INCOMPATIBLE_VERSION, "atmo_negotiate",
                  "host supports interface versions [" + std::to_string(info.min_interface_version) + ", " +
                      std::to_string(info.max_interface_version) + "], this plugin [" + std::to_string(kMinInterface) +
                      ", " + std::to_string(kMaxInterface) + "]");
    }
    // Fill what the host's table can hold; tell it how much that was.
    uint32_t n = api->header.struct_size < sizeof(kApi) ? api->header.struct_size : sizeof(kApi);
    const void* host_next = api->header.next;
    std::memcpy(static_cast<void*>(api), &kApi, n);
    api->header.struct_size = n;
    api->header.next = host_next;
    api->interface_version = chosen;
    return ATMO_SUCCESS;
  });
}
