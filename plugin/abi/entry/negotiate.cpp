// negotiate.cpp — the one exported symbol: atmo_negotiate picks the interface
// version and fills the host's function table (entry_points.h lists the
// functions, one file per concern). Every function checks its handles and
// structs, runs behind the exception barrier (call.h), and on error leaves
// state unchanged and records a message naming what and where.
#include <cstring>
#include <string>

#include "abi/entry/call.h"
#include "abi/entry/entry_points.h"

namespace atmo::abi {

namespace {

constexpr uint32_t kPluginVersion = (0u << 16) | (1u << 8) | 0u;
constexpr uint32_t kMinInterface = ATMO_INTERFACE_VERSION_1;
constexpr uint32_t kMaxInterface = ATMO_INTERFACE_VERSION_1;

const char* result_string(AtmoResult r) {
  switch (r) {
    case ATMO_SUCCESS:
      return "ATMO_SUCCESS";
    case ATMO_STATUS_NOTHING_TO_DRAW:
      return "ATMO_STATUS_NOTHING_TO_DRAW";
    case ATMO_STATUS_NOT_YET_SUPPORTED:
      return "ATMO_STATUS_NOT_YET_SUPPORTED";
    case ATMO_ERROR_INVALID_ARGUMENT:
      return "ATMO_ERROR_INVALID_ARGUMENT";
    case ATMO_ERROR_INCOMPATIBLE_VERSION:
      return "ATMO_ERROR_INCOMPATIBLE_VERSION";
    case ATMO_ERROR_STRUCT_TOO_SMALL:
      return "ATMO_ERROR_STRUCT_TOO_SMALL";
    case ATMO_ERROR_WRONG_STRUCT_TYPE:
      return "ATMO_ERROR_WRONG_STRUCT_TYPE";
    case ATMO_ERROR_NON_FINITE_VALUE:
      return "ATMO_ERROR_NON_FINITE_VALUE";
    case ATMO_ERROR_OUT_OF_RANGE:
      return "ATMO_ERROR_OUT_OF_RANGE";
    case ATMO_ERROR_CALL_OUT_OF_ORDER:
      return "ATMO_ERROR_CALL_OUT_OF_ORDER";
    case ATMO_ERROR_GL:
      return "ATMO_ERROR_GL";
    case ATMO_ERROR_OUT_OF_MEMORY:
      return "ATMO_ERROR_OUT_OF_MEMORY";
    case ATMO_ERROR_IO:
      return "ATMO_ERROR_IO";
    case ATMO_ERROR_INVALID_HANDLE:
      return "ATMO_ERROR_INVALID_HANDLE";
    case ATMO_ERROR_INTERNAL:
      return "ATMO_ERROR_INTERNAL";
    default:
      return r > 0 ? "unknown status" : "unknown error";
  }
}

const char* last_error(AtmoContext context) {
  AtmoContext_T* ctx = live_context(context);
  return ctx ? ctx->last_error.c_str() : orphan_error();
}

const AtmoPluginApi kApi = {
    {ATMO_TYPE_PLUGIN_API, sizeof(AtmoPluginApi), nullptr},
    ATMO_INTERFACE_VERSION_1,
    kPluginVersion,
    "Atmo",
    &result_string,
    &last_error,
    &entry::create_context,
    &entry::destroy_context,
    &entry::gl_init,
    &entry::gl_shutdown,
    &entry::gl_context_lost,
    &entry::create_view,
    &entry::destroy_view,
    &entry::set_atmosphere,
    &entry::set_frame,
    &entry::set_view,
    &entry::render_pass,
    &entry::get_lighting,
    &entry::set_clouds,
    &entry::get_cloud_shadows,
    &entry::set_fog,
    &entry::set_lights,
    &entry::get_fog_lighting,
    &entry::set_light_group_pose,
    &entry::update_lights,
    &entry::set_occluders,
    &entry::set_occluder_poses,
    &entry::get_sky_occlusion,
    &entry::get_state_hash,
};

}  // namespace

}  // namespace atmo::abi

using atmo::abi::fail;
using atmo::abi::guarded;
using atmo::abi::kApi;
using atmo::abi::kMaxInterface;
using atmo::abi::kMinInterface;
using atmo::abi::read_struct;
using atmo::abi::ReadError;
using atmo::abi::V1Size;

extern "C" ATMO_EXPORT AtmoResult atmo_negotiate(const AtmoNegotiateInfo* host, AtmoPluginApi* api) {
  return guarded(nullptr, "atmo_negotiate", [&]() -> AtmoResult {
    AtmoNegotiateInfo info;
    ReadError e = read_struct(host, ATMO_TYPE_NEGOTIATE_INFO, "AtmoNegotiateInfo", &info);
    if (e.code) return fail(nullptr, "atmo_negotiate", e);
    if (!api) return fail(nullptr, ATMO_ERROR_INVALID_ARGUMENT, "atmo_negotiate", "api is NULL");
    if (api->header.type != ATMO_TYPE_PLUGIN_API) {
      return fail(nullptr, ATMO_ERROR_WRONG_STRUCT_TYPE, "atmo_negotiate",
                  "api->header.type is not ATMO_TYPE_PLUGIN_API");
    }
    if (api->header.struct_size < V1Size<AtmoPluginApi>::value) {
      return fail(nullptr, ATMO_ERROR_STRUCT_TOO_SMALL, "atmo_negotiate",
                  "api->header.struct_size is " + std::to_string(api->header.struct_size) + " bytes, version 1 needs " +
                      std::to_string(V1Size<AtmoPluginApi>::value));
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
