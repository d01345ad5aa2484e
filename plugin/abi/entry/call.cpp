#include "abi/entry/call.h"

namespace atmo::abi {

namespace {
thread_local std::string g_orphan_error;
}

AtmoResult fail(AtmoContext_T* ctx, AtmoResult code, const char* function, const std::string& message) {
  std::string text = std::string(function) + ": " + message;
  if (ctx) {
    ctx->last_error = text;
    ctx->services.log(ATMO_LOG_ERROR, text);
  } else {
    g_orphan_error = text;
    HostServices().log(ATMO_LOG_ERROR, text);
  }
  return code;
}

const char* orphan_error() { return g_orphan_error.c_str(); }

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
