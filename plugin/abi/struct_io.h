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
ATMO_V1_SIZE(AtmoLightPoint, 96);
ATMO_V1_SIZE(AtmoLightGroupPose, 152);
ATMO_V1_SIZE(AtmoLightsUpdate, 40);
ATMO_V1_SIZE(AtmoOccluderSphere, 32);
ATMO_V1_SIZE(AtmoOccluderObject, 168);
ATMO_V1_SIZE(AtmoOccludersState, 64);
ATMO_V1_SIZE(AtmoOccluderPoses, 32);
ATMO_V1_SIZE(AtmoSkyOcclusion, 2312);
ATMO_V1_SIZE(AtmoStateHash, 96);
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

// The stride of an array the host passes (atmo.h, "ARRAYS"): `size` is the
// element's sizeof as the host compiled it, 0 the version-1 size; otherwise
// within [version-1 size, ATMO_ARRAY_ELEMENT_SIZE_MAX] and a multiple of 8 (the
// elements hold doubles). `field` names the size field in messages.
template <typename T>
ReadError array_stride(uint32_t size, const char* field, uint32_t* stride) {
  ReadError e;
  const uint32_t v1 = V1Size<T>::value;
  *stride = size == 0 ? v1 : size;
  if (*stride < v1) {
    e = {ATMO_ERROR_STRUCT_TOO_SMALL,
         std::string(field) + " is " + std::to_string(size) + " bytes, version 1 needs " + std::to_string(v1)};
  } else if (*stride > ATMO_ARRAY_ELEMENT_SIZE_MAX || *stride % 8 != 0) {
    e = {ATMO_ERROR_OUT_OF_RANGE, std::string(field) + " = " + std::to_string(size) +
                                      " bytes: a stride must be a multiple of 8 in [" + std::to_string(v1) + ", " +
                                      std::to_string(ATMO_ARRAY_ELEMENT_SIZE_MAX) + "] (0: " +
                                      std::to_string(v1) + ")"};
  }
  return e;
}

}  // namespace atmo::abi
