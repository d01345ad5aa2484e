// lifecycle.cpp — contexts, their GL objects and their views.
#include <cstring>
#include <future>
#include <system_error>
#include <new>
#include <string>

#include "abi/entry/call.h"
#include "abi/entry/entry_points.h"
#include "abi/scene_inputs.h"
#include "core/fog/fog_frame.h"

namespace atmo::abi::entry {

namespace {

template <typename T>
void destroy_object(T* object, const HostServices& services) {
  object->~T();
  services.deallocate(object);
}

void destroy_view_object(AtmoView_T* view) {
  unregister_view(view);
  HostServices services = view->context->services;
  destroy_object(view, services);
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

}  // namespace

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
      ctx->application_name = info.application_name ? info.application_name : "";
      ctx->services = services;
      ctx->services.set_application_name(ctx->application_name);
      ctx->asset_root = info.asset_root ? info.asset_root : plugin_directory();
      ctx->seed = info.seed;
      try {
        ctx->fog_prepared = std::async(std::launch::async, [] {
          const atmo::fog::FogMedium defaults;
          atmo::fog::fog_tables(atmo::fog::FogOptics{}.phase_g, defaults.airlight_table_size,
                                atmo::fog::FogMedium::kSurfaceTableSize);
        });
      } catch (const std::system_error&) {
        // No thread to spare: the first set_fog makes it.
      }
    } catch (...) {
      services.deallocate(memory);
      throw;
    }
    register_context(ctx);
    *out = ctx;
    return ATMO_SUCCESS;
  });
}

void destroy_context(AtmoContext context) {
  if (!context) return;
  guarded(nullptr, "destroy_context", [&]() -> AtmoResult {
    AtmoContext_T* ctx = live_context(context);
    if (!ctx) {
      HostServices().log(ATMO_LOG_HOST_MISBEHAVING, "destroy_context: not a live context (destroyed twice?)");
      return ATMO_ERROR_INVALID_HANDLE;
    }
    stop_table_builds(ctx);  // cancels a running table build and joins its thread
    for (AtmoView_T* v : ctx->views) destroy_view_object(v);
    ctx->views.clear();
    if (ctx->gl_alive) {
      ctx->services.log(ATMO_LOG_HOST_MISBEHAVING,
                        "destroy_context: gl_shutdown was not called; the plugin's GL objects are leaked");
    }
    unregister_context(ctx);
    HostServices services = ctx->services;
    destroy_object(ctx, services);
    return ATMO_SUCCESS;
  });
}

AtmoResult gl_init(AtmoContext context) {
  return with_context(context, "gl_init", [&](AtmoContext_T* ctx) -> AtmoResult {
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
    ctx->uploaded_tables_version = 0;
    return ATMO_SUCCESS;
  });
}

namespace {

// gl_shutdown deletes the context's GL objects; gl_context_lost forgets their
// names, which died with the GL context. Either way the tables upload again.
void drop_gl_objects(AtmoContext_T* ctx, bool destroy) {
  auto drop = [destroy](auto& holder) {
    if (destroy) holder.destroy(); else holder.forget();
  };
  drop(ctx->night_renderer);
  drop(ctx->cloud_renderer);
  drop(ctx->fog_renderer);
  drop(ctx->light_point_renderer);
  drop(ctx->occlusion_renderer);
  drop(ctx->renderer);
  ctx->gl_alive = false;
  ctx->uploaded_tables_version = 0;
}

}  // namespace

AtmoResult gl_shutdown(AtmoContext context) {
  return with_context(context, "gl_shutdown", [&](AtmoContext_T* ctx) -> AtmoResult {
    if (ctx->gl_alive) drop_gl_objects(ctx, /*destroy=*/true);
    return ATMO_SUCCESS;
  });
}

AtmoResult gl_context_lost(AtmoContext context) {
  AtmoContext_T* ctx = live_context(context);
  if (!ctx) return fail(nullptr, ATMO_ERROR_INVALID_HANDLE, "gl_context_lost", "not a live context");
  drop_gl_objects(ctx, /*destroy=*/false);
  return ATMO_SUCCESS;
}

AtmoResult create_view(AtmoContext context, const AtmoViewCreateInfo* info_in, AtmoView* out) {
  return with_context(context, "create_view", [&](AtmoContext_T* ctx) -> AtmoResult {
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
    view->serial = ++ctx->views_created;
    try {
      ctx->views.push_back(view);
    } catch (...) {
      destroy_object(view, ctx->services);
      throw;
    }
    register_view(view);
    *out = view;
    return ATMO_SUCCESS;
  });
}

void destroy_view(AtmoView view) {
  if (!view) return;
  if (!is_live_view(view)) {
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
  try {
    ctx->cloud_renderer.retire_view(view->serial);  // its history is freed by the next clouds pass
    ctx->occlusion_renderer.retire_view(view->serial);  // its image is freed by the next image pass
  } catch (...) {
    // Out of memory: the history stays until gl_shutdown frees every GL object.
  }
  destroy_view_object(view);
}

}  // namespace atmo::abi::entry
