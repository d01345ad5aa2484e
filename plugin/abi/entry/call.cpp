#include "abi/entry/call.h"

#include <cstdio>

namespace atmo::abi {

namespace {
// Errors with no live context to hold them (create_context, bad handles).
// A plain buffer, not a std::string: a thread_local with a destructor
// registers it with glibc (__cxa_thread_atexit), which then keeps libatmo.so
// mapped after dlclose for as long as that thread lives.
constexpr size_t kOrphanErrorBytes = 1024;
thread_local char g_orphan_error[kOrphanErrorBytes];
}  // namespace

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

const char* orphan_error() { return g_orphan_error; }

AtmoContext_T* live_context(AtmoContext context) { return is_live_context(context) ? context : nullptr; }

AtmoView_T* live_view(AtmoView view, const char* function) {
  if (is_live_view(view)) return view;
  fail(nullptr, ATMO_ERROR_INVALID_HANDLE, function, "not a live view");
  return nullptr;
}

AtmoResult require_frame_and_view(AtmoContext_T* ctx, const AtmoView_T& view, const char* function, bool needs_gl) {
  if (needs_gl && !ctx->gl_alive)
    return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, function,
                "gl_init has not been called on this context (or the GL context was lost)");
  if (!ctx->have_frame) return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, function, "set_frame has not been called");
  if (!view.have_state) return fail(ctx, ATMO_ERROR_CALL_OUT_OF_ORDER, function, "set_view has not been called");
  return ATMO_SUCCESS;
}

std::string pass_log_prefix(const AtmoContext_T* ctx, const AtmoView_T* view) {
  return "frame " + std::to_string(ctx->frame_number) + ", channel " + std::to_string(view->channel_id) + ": ";
}

}  // namespace atmo::abi
