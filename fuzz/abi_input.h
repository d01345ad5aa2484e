// abi_input.h — the byte format of the ABI fuzz target's inputs (abi_fuzz.cpp
// reads it, make_abi_seeds.cpp writes the seed corpus in it).
//
// An input is a sequence of calls, each:
//   CallHead                       what to call and how to lie about the struct
//   sizeof(T) bytes                the struct as the host wrote it (its pointers
//                                  and header.next are replaced, see below)
//   count * stride bytes           set_clouds' layers / set_lights' and update_lights' lights /
//                                  set_occluders' objects / set_occluder_poses' matrices (16 doubles each)
//   per object: reserved's low 5 bits * 32 bytes   set_occluders: each object's spheres (its sphere_count is
//                                  set to those, unless reserved bit 7 asks for the input's count with
//                                  NULL spheres)
// Missing bytes at the end of the input read as zero.
//
// Pointers never come from the input: the harness points them at memory it
// owns, sized exactly as the struct's own fields claim, so AddressSanitizer
// reports any read past what a host passed. header.next points into a chain
// of `chain & 7` headers (the last one links back to the first when
// chain & 8: a cycle). A cloud layer's vdb_path/vdb_grid bytes choose one of
// kPaths/kGrids by their low byte; the file service serves a small valid VDB
// (two volumes) cut to path byte 1 * 64 bytes (0: whole), and no file for
// "missing.vdb". Cost: set_clouds gets at most 4 layers, and a procedural
// layer's area_size_m (the last field validated) is set out of range, so it
// is validated but never generated (seconds each); a valid fog phase_asymmetry
// and airlight_table_size become 0 (the defaults), so the fog's tables are built
// once per process, not per input.
#pragma once

#include <cstdint>
#include <cstring>

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
  kUpdateLights = 7,
  kSetLightGroupPose = 8,
  kSetOccluders = 9,
  kSetOccluderPoses = 10,
  kGetStateHash = 11,
  kOpCount = 12
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

// Valid states (the seeds start from them; the harness warms its caches with them).
inline AtmoFrameState typical_frame() {
  AtmoFrameState f{};
  f.header = ATMO_HEADER(ATMO_TYPE_FRAME_STATE, AtmoFrameState);
  f.host_frame_number = 1;
  f.utc_posix_s = 1781000000.0;  // 2026-06-09, daytime in Europe
  f.dut1_s = 0.1;
  return f;
}

// A 60-degree perspective at 47 N 8 E, 500 m up, looking north in an ENU world.
inline AtmoViewState typical_view(double height_m) {
  AtmoViewState v{};
  v.header = ATMO_HEADER(ATMO_TYPE_VIEW_STATE, AtmoViewState);
  v.eye_kind = ATMO_POSITION_GEODETIC;
  v.world_frame = ATMO_WORLD_ENU;
  v.eye_geodetic[0] = 47.0;
  v.eye_geodetic[1] = 8.0;
  v.eye_geodetic[2] = height_m;
  v.world_origin_geodetic[0] = 47.0;
  v.world_origin_geodetic[1] = 8.0;
  // view_from_world: camera x = east, y = up, -z = north.
  const double view_from_world[16] = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1};
  std::memcpy(v.view_from_world, view_from_world, sizeof(view_from_world));
  const double f = 1.7320508, n = 0.5, far = 100000.0;
  const double clip_from_view[16] = {f / 1.5, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + n) / (n - far), -1,
                                     0, 0, 2 * far * n / (n - far), 0};
  std::memcpy(v.clip_from_view, clip_from_view, sizeof(clip_from_view));
  v.viewport[2] = 320;
  v.viewport[3] = 240;
  return v;
}

}  // namespace atmo_fuzz
