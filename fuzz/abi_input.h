// abi_input.h — the byte format of the ABI fuzz target's inputs (abi_fuzz.cpp
// reads it, make_abi_seeds.cpp writes the seed corpus in it).
//
// An input is a sequence of calls, each:
//   CallHead                       what to call and how to lie about the struct
//   sizeof(T) bytes                the struct as the host wrote it (its pointers
//                                  and header.next are replaced, see below)
//   count * stride bytes           set_clouds' layers / set_lights' lights
// Missing bytes at the end of the input read as zero.
//
// Pointers never come from the input: the harness points them at memory it
// owns, sized exactly as the struct's own fields claim, so AddressSanitizer
// reports any read past what a host passed. header.next points into a chain
// of `chain & 7` headers (the last one links back to the first when
// chain & 8: a cycle). A cloud layer's vdb_path/vdb_grid bytes choose one of
// kPaths/kGrids by their low byte; the file service serves a small valid VDB
// (two volumes) cut to path byte 1 * 64 bytes (0: whole), and no file for
// "missing.vdb".
#pragma once

#include <cstdint>

#include "atmo/atmo.h"

namespace atmo_fuzz {

enum Op : uint8_t {
  kSetAtmosphere = 0,
  kSetFrame = 1,
  kSetView = 2,
  kSetClouds = 3,
  kSetLights = 4,
  kSetFog = 5,
  kGetLighting = 6,
  kOpCount = 7
};

enum CallFlags : uint8_t {
  kNullStruct = 1,       // pass NULL instead of the struct
  kWrongType = 2,        // header.type from the input's bytes, not the right tag
  kSizeFromInput = 4,    // header.struct_size (and the buffer) = CallHead.struct_size, not sizeof(T)
};

#pragma pack(push, 1)
struct CallHead {
  uint8_t op;            // Op, modulo kOpCount
  uint8_t flags;         // CallFlags
  uint8_t chain;         // extension chain, see above
  uint8_t reserved;
  uint32_t struct_size;  // with kSizeFromInput; capped at sizeof(T) + 256
  uint32_t count;        // layers or lights in the array (capped so the array stays <= 4 MiB)
  uint32_t stride;       // bytes between them: layer 0's struct_size, or AtmoLightsState.light_size
};
#pragma pack(pop)

inline const char* const kPaths[] = {nullptr, "", "cloud.vdb", "missing.vdb", "/abs/cloud.vdb", "sub/../cloud.vdb"};
inline const char* const kGrids[] = {nullptr, "", "density", "density_1", "temperature"};

}  // namespace atmo_fuzz
