// struct_io.h — reading versioned structs across the ABI: check the type tag,
// reject a struct smaller than its version-1 size, copy what the caller has
// (older, smaller structs get zero-filled new fields) and walk `next`,
// skipping extension types this plugin does not know.
#pragma once

#include <cstddef>
#include <cstring>
#include <string>

#include "atmo/atmo.h"

namespace atmo::abi {

// Version-1 sizes, frozen: a test checks sizeof == these, so a layout change
// that would break old hosts fails to compile or test.
template <typename T> struct V1Size;
#define ATMO_V1_SIZE(T, bytes) \
  template <> struct V1Size<T> { static constexpr uint32_t value = bytes; }
ATMO_V1_SIZE(AtmoNegotiateInfo, 40);
ATMO_V1_SIZE(AtmoPluginApi, 144);
ATMO_V1_SIZE(AtmoHostServices, 80);
ATMO_V1_SIZE(AtmoContextCreateInfo, 48);
ATMO_V1_SIZE(AtmoViewCreateInfo, 24);
ATMO_V1_SIZE(AtmoAtmosphereState, 40);
ATMO_V1_SIZE(AtmoFrameState, 40);
ATMO_V1_SIZE(AtmoViewState, 408);
ATMO_V1_SIZE(AtmoPassInfo, 24);
ATMO_V1_SIZE(AtmoLighting, 104);
ATMO_V1_SIZE(AtmoCloudLayer, 168);
ATMO_V1_SIZE(AtmoCloudsState, 80);
ATMO_V1_SIZE(AtmoCloudShadows, 184);
ATMO_V1_SIZE(AtmoFogState, 64);
ATMO_V1_SIZE(AtmoLightsState, 72);
ATMO_V1_SIZE(AtmoFogLighting, 136);
#undef ATMO_V1_SIZE

struct ReadError {
  AtmoResult code = ATMO_SUCCESS;
  std::string message;
};

// Reads *in as a T tagged `type`. `what` names the argument in messages.
template <typename T>
ReadError read_struct(const void* in, AtmoStructType type, const char* what, T* out) {
  ReadError e;
  if (!in) {
    e = {ATMO_ERROR_INVALID_ARGUMENT, std::string(what) + " is NULL"};
    return e;
  }
  AtmoStructHeader header;
  std::memcpy(&header, in, sizeof(header));
  if (header.type != static_cast<uint32_t>(type)) {
    e = {ATMO_ERROR_WRONG_STRUCT_TYPE, std::string(what) + ".header.type is " + std::to_string(header.type) +
                                           ", expected " + std::to_string(static_cast<uint32_t>(type))};
    return e;
  }
#ifndef ATMO_FAULT_ACCEPT_UNDERSIZED  // test-only fault: a plugin that trusts any size
  if (header.struct_size < V1Size<T>::value) {
    e = {ATMO_ERROR_STRUCT_TOO_SMALL, std::string(what) + ".header.struct_size is " +
                                          std::to_string(header.struct_size) + " bytes, version 1 needs " +
                                          std::to_string(V1Size<T>::value)};
    return e;
  }
#endif
  std::memset(static_cast<void*>(out), 0, sizeof(T));
  size_t n = header.struct_size < sizeof(T) ? header.struct_size : sizeof(T);
  std::memcpy(static_cast<void*>(out), in, n);
  // Extension chain: nothing is defined in version 1, so every entry is
  // skipped; the walk only guards against cycles (at most 64 links are read).
  const AtmoStructHeader* link = static_cast<const AtmoStructHeader*>(header.next);
  for (int i = 0; link && i < 64; ++i) link = static_cast<const AtmoStructHeader*>(link->next);
  return e;
}

}  // namespace atmo::abi
