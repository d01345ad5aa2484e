// call.h — what every entry point shares: errors that name the function,
// the exception barrier, handle checks, the order checks and the write-back
// of an output struct the host may have sized for an older version.
#pragma once

#include <cstring>
#include <new>
#include <string>

#include "abi/objects.h"
#include "abi/struct_io.h"
#include "atmo/atmo.h"

namespace atmo::abi {

// Records "function: message" on the context (or, with none, for
// last_error(NULL)), logs it as an error and returns code.
AtmoResult fail(AtmoContext_T* ctx, AtmoResult code, const char* function, const std::string& message);
inline AtmoResult fail(AtmoContext_T* ctx, const char* function, const ReadError& e) {
  return fail(ctx, e.code, function, e.message);
}
// The message last_error(NULL) returns: errors with no live context to hold them.
const char* orphan_error();

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

// The handle if it is live, else null (live_view also records the error).
AtmoContext_T* live_context(AtmoContext context);
AtmoView_T* live_view(AtmoView view, const char* function);

// The shapes of the entry points. with_context / with_view: the handle check
// (an error names `function`) and the exception barrier around
// body(ctx[, view]). context_call / view_call also read the host's struct
// `in` of `type` (refused when NULL, undersized or of another type; `name`
// names it in messages) and pass the copy to apply(ctx, [view,] s), which
// validates it and applies it or fills the host's output.
template <typename Body>
AtmoResult with_context(AtmoContext context, const char* function, Body&& body) {
  AtmoContext_T* ctx = live_context(context);
  if (!ctx) return fail(nullptr, ATMO_ERROR_INVALID_HANDLE, function, "not a live context");
  return guarded(ctx, function, [&]() -> AtmoResult { return body(ctx); });
}

template <typename Body>
AtmoResult with_view(AtmoView view_handle, const char* function, Body&& body) {
  AtmoView_T* view = live_view(view_handle, function);
  if (!view) return ATMO_ERROR_INVALID_HANDLE;
  AtmoContext_T* ctx = view->context;
  return guarded(ctx, function, [&]() -> AtmoResult { return body(ctx, view); });
}

template <typename T, typename Apply>
AtmoResult context_call(AtmoContext context, const char* function, const T* in, AtmoStructType type, const char* name,
                        Apply&& apply) {
  return with_context(context, function, [&](AtmoContext_T* ctx) -> AtmoResult {
    T s;
    ReadError e = read_struct(in, type, name, &s);
    if (e.code) return fail(ctx, function, e);
    return apply(ctx, s);
  });
}

template <typename T, typename Apply>
AtmoResult view_call(AtmoView view_handle, const char* function, const T* in, AtmoStructType type, const char* name,
                     Apply&& apply) {
  return with_view(view_handle, function, [&](AtmoContext_T* ctx, AtmoView_T* view) -> AtmoResult {
    T s;
    ReadError e = read_struct(in, type, name, &s);
    if (e.code) return fail(ctx, function, e);
    return apply(ctx, view, s);
  });
}

// ATMO_SUCCESS when the calls a view's output needs came first: gl_init (when
// `needs_gl`), set_frame and set_view; else CALL_OUT_OF_ORDER naming the missing one.
AtmoResult require_frame_and_view(AtmoContext_T* ctx, const AtmoView_T& view, const char* function, bool needs_gl);

// What a pass's log lines begin with: the host's frame number and the view's
// channel (AtmoFrameState.host_frame_number, AtmoViewCreateInfo.channel_id;
// they name the frame in logs and change no result).
std::string pass_log_prefix(const AtmoContext_T* ctx, const AtmoView_T* view);

// Copies what the host's struct can hold (its header.struct_size, already
// checked to be at least version 1) and keeps the host's header.
template <typename T>
void write_back(T* out, T value) {
  const size_t n = out->header.struct_size < sizeof(T) ? out->header.struct_size : sizeof(T);
  value.header = out->header;
  std::memcpy(static_cast<void*>(out), &value, n);
}

// A view's getter: view_call on the host's output struct, the order check
// (gl_init when `needs_gl`, set_frame, set_view), then body(ctx, view, value)
// fills the output, which is written back unless the body failed (an error
// leaves the host's struct as it was).
template <typename T, typename Body>
AtmoResult view_output_call(AtmoView view_handle, const char* function, T* out, AtmoStructType type, const char* name,
                            bool needs_gl, Body&& body) {
  return view_call(view_handle, function, out, type, name,
                   [&](AtmoContext_T* ctx, AtmoView_T* view, T& value) -> AtmoResult {
                     if (AtmoResult r = require_frame_and_view(ctx, *view, function, needs_gl)) return r;
                     const AtmoResult result = body(ctx, view, value);
                     if (result >= 0) write_back(out, value);
                     return result;
                   });
}

}  // namespace atmo::abi
