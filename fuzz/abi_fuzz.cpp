// abi_fuzz.cpp — the ABI's struct readers through the plugin's C API:
// set_atmosphere, set_frame, set_view, set_clouds, set_lights, update_lights, set_light_group_pose, set_fog,
// set_occluders, set_occluder_poses and get_lighting with any bytes, any struct_size and type tag, extension chains
// (cycles too), and arrays of any count and stride (abi_input.h). No GL: one
// context per process, made once; each input starts from the same state (no
// clouds, fog or lights, the default air and a fresh view).
//
// Contract (atmo.h): no crash, hang, leak or sanitizer report; every result is
// a documented code; an error's last_error names the function; every log line
// is a valid severity and string.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "abi_input.h"
#include "fuzz_check.h"
#include "vdb/vdb_io.h"

namespace {

using atmo_fuzz::CallHead;

struct Reader {
  const uint8_t* data;
  size_t size;
  size_t at = 0;
  bool done() const { return at >= size; }
  // n bytes from the input, zero past its end.
  void read(void* out, size_t n) {
    std::memset(out, 0, n);
    const size_t have = at < size ? std::min(n, size - at) : 0;
    if (have) std::memcpy(out, data + at, have);
    at += n;
  }
};

// The host's file service: one in-memory file, the small valid VDB cut short.
struct FuzzFile {
  std::string bytes;
  size_t at = 0;
};
std::string g_vdb;        // the whole file
size_t g_vdb_cut = 0;     // bytes served (0: all)

void* file_open(void*, const char* path) {
  FUZZ_CHECK(path != nullptr, "file_open gets a path");
  if (std::strstr(path, "missing")) return nullptr;
  FuzzFile* f = new FuzzFile;
  f->bytes = g_vdb_cut ? g_vdb.substr(0, g_vdb_cut) : g_vdb;
  return f;
}
int64_t file_read(void*, void* file, void* buffer, uint64_t size) {
  FuzzFile* f = static_cast<FuzzFile*>(file);
  const size_t n = std::min<size_t>(size, f->bytes.size() - f->at);
  std::memcpy(buffer, f->bytes.data() + f->at, n);
  f->at += n;
  return static_cast<int64_t>(n);
}
void file_close(void*, void* file) { delete static_cast<FuzzFile*>(file); }

void log_line(void*, int32_t severity, const char* message) {
  FUZZ_CHECK(severity >= ATMO_LOG_DEBUG && severity <= ATMO_LOG_HOST_MISBEHAVING, "a log severity");
  FUZZ_CHECK(message != nullptr, "a log message");
  (void)std::strlen(message);  // a valid C string (ASan checks the read)
}

void* allocate(void*, size_t size, size_t alignment) {
  FUZZ_CHECK(alignment && (alignment & (alignment - 1)) == 0, "alignment is a power of two");
  void* p = nullptr;
  return posix_memalign(&p, std::max(alignment, sizeof(void*)), size ? size : 1) == 0 ? p : nullptr;
}
void deallocate(void*, void* p) { std::free(p); }

AtmoPluginApi g_api;
AtmoContext g_ctx = nullptr;

void init() {
  AtmoNegotiateInfo host{ATMO_HEADER(ATMO_TYPE_NEGOTIATE_INFO, AtmoNegotiateInfo), 1, 1, "atmo-fuzz", 1, 0};
  g_api.header = ATMO_HEADER(ATMO_TYPE_PLUGIN_API, AtmoPluginApi);
  FUZZ_CHECK(atmo_negotiate(&host, &g_api) == ATMO_SUCCESS, "negotiate");
  AtmoHostServices services{};
  services.header = ATMO_HEADER(ATMO_TYPE_HOST_SERVICES, AtmoHostServices);
  services.log = log_line;
  services.allocate = allocate;
  services.deallocate = deallocate;
  services.file_open = file_open;
  services.file_read = file_read;
  services.file_close = file_close;
  AtmoContextCreateInfo info{};
  info.header = ATMO_HEADER(ATMO_TYPE_CONTEXT_CREATE_INFO, AtmoContextCreateInfo);
  info.services = &services;
  info.asset_root = "/fuzz/assets";
  info.application_name = "atmo-fuzz";
  FUZZ_CHECK(g_api.create_context(&info, &g_ctx) == ATMO_SUCCESS, "create_context");
  atmo::clouds::CloudVolume v;
  v.name = "fuzz";
  v.density = atmo::clouds::DenseGrid(4, 3, 2, 0.25f);
  v.voxel_size_m = 20.0f;
  FUZZ_CHECK(atmo::vdb::write_vdb_to_memory({v, v}, &g_vdb).empty(), "the served VDB");
  // Warm the caches that take seconds under the sanitizers, outside any input's time limit: the default
  // air's tables, the sky lighting, the fog's tables for the default phase function.
  AtmoView view = nullptr;
  AtmoViewCreateInfo view_info{};
  view_info.header = ATMO_HEADER(ATMO_TYPE_VIEW_CREATE_INFO, AtmoViewCreateInfo);
  FUZZ_CHECK(g_api.create_view(g_ctx, &view_info, &view) == ATMO_SUCCESS, "create_view");
  const AtmoFrameState frame = atmo_fuzz::typical_frame();
  const AtmoViewState view_state = atmo_fuzz::typical_view(500.0);
  AtmoLighting lighting{};
  lighting.header = ATMO_HEADER(ATMO_TYPE_LIGHTING, AtmoLighting);
  AtmoFogState fog{};
  fog.header = ATMO_HEADER(ATMO_TYPE_FOG_STATE, AtmoFogState);
  fog.visibility_m = 300.0;
  FUZZ_CHECK(g_api.set_frame(g_ctx, &frame) == ATMO_SUCCESS && g_api.set_view(view, &view_state) == ATMO_SUCCESS &&
                 g_api.get_lighting(view, &lighting) == ATMO_SUCCESS && g_api.set_fog(g_ctx, &fog) == ATMO_SUCCESS,
             "warming up");
  g_api.destroy_view(view);
}

bool known_result(AtmoResult r) {
  const std::string name = g_api.result_string(r);
  return name.rfind("ATMO_", 0) == 0;
}

void check_result(AtmoResult r, const char* function) {
  FUZZ_CHECK(known_result(r), function);
  if (r < 0) {
    const std::string error = g_api.last_error(g_ctx);
    FUZZ_CHECK(error.find(function) != std::string::npos, "last_error names the function");
  }
}

// One struct as the host passes it: a buffer of exactly header.struct_size
// bytes (at least the header), the chain of extension headers it points to.
template <typename T>
struct HostStruct {
  std::vector<unsigned char> bytes;
  std::vector<AtmoStructHeader> chain;
  T value;  // what the input wrote, before the header is applied
  const T* get() const { return reinterpret_cast<const T*>(bytes.data()); }
};

template <typename T>
void read_struct(Reader& in, const CallHead& head, AtmoStructType type, HostStruct<T>* out) {
  in.read(&out->value, sizeof(T));
  AtmoStructHeader& h = out->value.header;
  if (!(head.flags & atmo_fuzz::kWrongType)) h.type = static_cast<uint32_t>(type);
  h.struct_size = (head.flags & atmo_fuzz::kSizeFromInput) ? std::min<uint32_t>(head.struct_size, sizeof(T) + 256)
                                                            : static_cast<uint32_t>(sizeof(T));
  const int links = head.chain & 7;
  out->chain.assign(static_cast<size_t>(links), AtmoStructHeader{});
  for (int i = 0; i < links; ++i) {
    out->chain[i].type = (i % 2) ? 0x41540000u + head.chain : static_cast<uint32_t>(type);
    out->chain[i].struct_size = static_cast<uint32_t>(sizeof(AtmoStructHeader));
    out->chain[i].next = i + 1 < links ? &out->chain[i + 1] : ((head.chain & 8) ? &out->chain[0] : nullptr);
  }
  h.next = links ? &out->chain[0] : nullptr;
}

// Lays the struct out in a buffer of exactly the size it claims.
template <typename T>
void finish(HostStruct<T>* s) {
  const size_t n = std::max<size_t>(s->value.header.struct_size, sizeof(AtmoStructHeader));
  s->bytes.assign(n, 0);
  std::memcpy(s->bytes.data(), &s->value, std::min(n, sizeof(T)));
}

// A count * stride array from the input, capped at 4 MiB (count shrinks).
std::vector<unsigned char> read_array(Reader& in, uint32_t* count, uint32_t stride, uint32_t max_count) {
  constexpr size_t kMaxBytes = 4u << 20;
  if (*count > max_count) return std::vector<unsigned char>(16, 0);  // must be refused unread
  if (stride && static_cast<size_t>(*count) * stride > kMaxBytes) *count = static_cast<uint32_t>(kMaxBytes / stride);
  std::vector<unsigned char> a(std::max<size_t>(static_cast<size_t>(*count) * stride, 1));
  in.read(a.data(), static_cast<size_t>(*count) * stride);
  return a;
}

void reset_state(AtmoView* view) {
  AtmoAtmosphereState air{};
  air.header = ATMO_HEADER(ATMO_TYPE_ATMOSPHERE_STATE, AtmoAtmosphereState);
  check_result(g_api.set_atmosphere(g_ctx, &air), "set_atmosphere");
  AtmoCloudsState clouds{};
  clouds.header = ATMO_HEADER(ATMO_TYPE_CLOUDS_STATE, AtmoCloudsState);
  check_result(g_api.set_clouds(g_ctx, &clouds), "set_clouds");
  check_result(g_api.set_fog(g_ctx, nullptr), "set_fog");
  check_result(g_api.set_lights(g_ctx, nullptr), "set_lights");
  check_result(g_api.set_occluders(g_ctx, nullptr), "set_occluders");
  AtmoViewCreateInfo info{ATMO_HEADER(ATMO_TYPE_VIEW_CREATE_INFO, AtmoViewCreateInfo), 7, 0};
  FUZZ_CHECK(g_api.create_view(g_ctx, &info, view) == ATMO_SUCCESS, "create_view");
}

// A call whose struct holds no pointer: the bytes as they are, NULL on kNullStruct.
template <typename T, typename Call>
void plain_call(Reader& in, const CallHead& head, AtmoStructType type, const char* function, Call&& api_call) {
  HostStruct<T> s;
  read_struct(in, head, type, &s);
  finish(&s);
  check_result(api_call((head.flags & atmo_fuzz::kNullStruct) ? nullptr : s.get()), function);
}

// A call whose struct points at an array of lights (AtmoLightsState,
// AtmoLightsUpdate): the array follows the struct; flag 8 makes its pointer NULL.
template <typename T, typename Call>
void light_array_call(Reader& in, const CallHead& head, AtmoStructType type, const char* function, Call&& api_call) {
  HostStruct<T> s;
  read_struct(in, head, type, &s);
  uint32_t count = head.count;
  // light_size 0 means version 1's size (atmo.h): the array is sized as the plugin reads it.
  const uint32_t element = head.stride ? head.stride : static_cast<uint32_t>(sizeof(AtmoLightPoint));
  std::vector<unsigned char> lights = read_array(in, &count, element, ATMO_LIGHTS_MAX);
  s.value.light_count = count;
  s.value.light_size = head.stride;
  s.value.lights = (head.flags & 8) ? nullptr : reinterpret_cast<const AtmoLightPoint*>(lights.data());
  finish(&s);
  check_result(api_call((head.flags & atmo_fuzz::kNullStruct) ? nullptr : s.get()), function);
}

void call(Reader& in, AtmoView view) {
  CallHead head;
  in.read(&head, sizeof(head));
  const bool null = head.flags & atmo_fuzz::kNullStruct;
  switch (head.op % atmo_fuzz::kOpCount) {
    case atmo_fuzz::kSetAtmosphere:
      return plain_call<AtmoAtmosphereState>(in, head, ATMO_TYPE_ATMOSPHERE_STATE, "set_atmosphere",
                                             [](const AtmoAtmosphereState* p) { return g_api.set_atmosphere(g_ctx, p); });
    case atmo_fuzz::kSetFrame:
      return plain_call<AtmoFrameState>(in, head, ATMO_TYPE_FRAME_STATE, "set_frame",
                                        [](const AtmoFrameState* p) { return g_api.set_frame(g_ctx, p); });
    case atmo_fuzz::kSetView:
      return plain_call<AtmoViewState>(in, head, ATMO_TYPE_VIEW_STATE, "set_view",
                                       [view](const AtmoViewState* p) { return g_api.set_view(view, p); });
    case atmo_fuzz::kSetFog: {
      HostStruct<AtmoFogState> s;
      read_struct(in, head, ATMO_TYPE_FOG_STATE, &s);
      // The fog's tables are rebuilt for each new phase function or table size (seconds here, under the
      // sanitizers): a valid phase_asymmetry and airlight_table_size become 0 (the defaults),
      // so they are built once; values out of range stay and are refused. tests/fog cover the tables.
      AtmoFogState& f = s.value;
      if (f.phase_asymmetry >= -0.95 && f.phase_asymmetry <= 0.95) f.phase_asymmetry = 0.0;
      if (f.airlight_table_size >= 8 && f.airlight_table_size <= 512) f.airlight_table_size = 0;
      finish(&s);
      check_result(g_api.set_fog(g_ctx, null ? nullptr : s.get()), "set_fog");
      break;
    }
    case atmo_fuzz::kSetLights:
      return light_array_call<AtmoLightsState>(in, head, ATMO_TYPE_LIGHTS_STATE, "set_lights",
                                               [](const AtmoLightsState* p) { return g_api.set_lights(g_ctx, p); });
    case atmo_fuzz::kUpdateLights:
      return light_array_call<AtmoLightsUpdate>(in, head, ATMO_TYPE_LIGHTS_UPDATE, "update_lights",
                                                [](const AtmoLightsUpdate* p) { return g_api.update_lights(g_ctx, p); });
    case atmo_fuzz::kSetLightGroupPose:
      return plain_call<AtmoLightGroupPose>(in, head, ATMO_TYPE_LIGHT_GROUP_POSE, "set_light_group_pose",
                                            [](const AtmoLightGroupPose* p) {
                                              return g_api.set_light_group_pose(g_ctx, p);
                                            });
    case atmo_fuzz::kSetOccluders: {
      HostStruct<AtmoOccludersState> s;
      read_struct(in, head, ATMO_TYPE_OCCLUDERS_STATE, &s);
      uint32_t count = head.count;
      const uint32_t element = head.stride ? head.stride : static_cast<uint32_t>(sizeof(AtmoOccluderObject));
      std::vector<unsigned char> objects = read_array(in, &count, element, ATMO_OCCLUDER_OBJECTS_MAX);
      // Each object's spheres follow; its pointer and count are the harness's (a host's pointers are its own).
      const bool read = count <= ATMO_OCCLUDER_OBJECTS_MAX;  // else refused unread (read_array gave 16 bytes)
      std::vector<std::vector<unsigned char>> spheres(read ? count : 0);
      if (read && element >= sizeof(AtmoOccluderObject)) {
        for (uint32_t i = 0; i < count; ++i) {
          AtmoOccluderObject o;
          std::memcpy(&o, objects.data() + static_cast<size_t>(i) * element, sizeof(o));
          const uint32_t n = head.reserved & 31u;
          spheres[i].assign(std::max<size_t>(static_cast<size_t>(n) * sizeof(AtmoOccluderSphere), 1), 0);
          in.read(spheres[i].data(), static_cast<size_t>(n) * sizeof(AtmoOccluderSphere));
          o.sphere_size = 0;
          if (head.reserved & 128u) {
            o.spheres = nullptr;  // the input's count with no array: refused unread
          } else {
            o.spheres = reinterpret_cast<const AtmoOccluderSphere*>(spheres[i].data());
            o.sphere_count = n;
          }
          std::memcpy(objects.data() + static_cast<size_t>(i) * element, &o, sizeof(o));
        }
      }
      s.value.object_count = count;
      s.value.object_size = head.stride;
      s.value.objects = (head.flags & 8) ? nullptr : reinterpret_cast<const AtmoOccluderObject*>(objects.data());
      finish(&s);
      check_result(g_api.set_occluders(g_ctx, null ? nullptr : s.get()), "set_occluders");
      break;
    }
    case atmo_fuzz::kSetOccluderPoses: {
      HostStruct<AtmoOccluderPoses> s;
      read_struct(in, head, ATMO_TYPE_OCCLUDER_POSES, &s);
      uint32_t count = head.count;
      std::vector<unsigned char> poses = read_array(in, &count, 16 * sizeof(double), ATMO_OCCLUDER_OBJECTS_MAX);
      s.value.count = count;
      s.value.world_from_object = (head.flags & 8) ? nullptr : reinterpret_cast<const double*>(poses.data());
      finish(&s);
      check_result(g_api.set_occluder_poses(g_ctx, null ? nullptr : s.get()), "set_occluder_poses");
      break;
    }
    case atmo_fuzz::kSetClouds: {
      HostStruct<AtmoCloudsState> s;
      read_struct(in, head, ATMO_TYPE_CLOUDS_STATE, &s);
      // Layer 0's struct_size is the stride (atmo.h), at least a header.
      const uint32_t stride = std::max<uint32_t>(head.stride % 1024, sizeof(AtmoStructHeader));
      // At most 4 layers (a VDB layer is read and lit on the calling thread).
      uint32_t count = head.count <= 64 ? std::min<uint32_t>(head.count, 4) : head.count;
      std::vector<unsigned char> layers = read_array(in, &count, stride, 64);
      for (uint32_t i = 0; i < count && count <= 64; ++i) {
        unsigned char* p = layers.data() + static_cast<size_t>(i) * stride;
        AtmoStructHeader h;
        std::memcpy(&h, p, sizeof(h));
        if (!(head.flags & atmo_fuzz::kWrongType)) h.type = ATMO_TYPE_CLOUD_LAYER;
        h.struct_size = i == 0 ? stride : std::min(h.struct_size, stride);  // within its own stride
        h.next = nullptr;
        std::memcpy(p, &h, sizeof(h));
        // A procedural layer takes seconds to generate (5-140 s measured here, under the sanitizers), so
        // it never passes: its area_size_m, the last field validated, is made invalid, and every check
        // before it still runs. tests/clouds cover the generator.
        constexpr size_t type_at = offsetof(AtmoCloudLayer, type), area_at = offsetof(AtmoCloudLayer, area_size_m);
        uint32_t type = ATMO_CLOUD_VDB_FILE;
        if (type_at + sizeof(type) <= stride) std::memcpy(&type, p + type_at, sizeof(type));
        if (type < ATMO_CLOUD_VDB_FILE && area_at + sizeof(double) <= stride) {
          const double invalid_area_m = 1e9;
          std::memcpy(p + area_at, &invalid_area_m, sizeof(invalid_area_m));
        }
        // The string pointers, where the layer's bytes reach them.
        constexpr size_t path_at = offsetof(AtmoCloudLayer, vdb_path), grid_at = offsetof(AtmoCloudLayer, vdb_grid);
        if (path_at + sizeof(void*) <= stride) {
          const unsigned char choice = p[path_at];
          g_vdb_cut = static_cast<size_t>(p[path_at + 1]) * 64;
          const char* path = atmo_fuzz::kPaths[choice % std::size(atmo_fuzz::kPaths)];
          std::memcpy(p + path_at, &path, sizeof(path));
        }
        if (grid_at + sizeof(void*) <= stride) {
          const char* grid = atmo_fuzz::kGrids[p[grid_at] % std::size(atmo_fuzz::kGrids)];
          std::memcpy(p + grid_at, &grid, sizeof(grid));
        }
      }
      s.value.layer_count = count;
      s.value.layers = reinterpret_cast<const AtmoCloudLayer*>(layers.data());
      if (head.flags & 8) s.value.layers = nullptr;
      finish(&s);
      check_result(g_api.set_clouds(g_ctx, null ? nullptr : s.get()), "set_clouds");
      break;
    }
    case atmo_fuzz::kGetLighting: {
      HostStruct<AtmoLighting> s;
      read_struct(in, head, ATMO_TYPE_LIGHTING, &s);
      finish(&s);
      AtmoLighting* out = null ? nullptr : reinterpret_cast<AtmoLighting*>(s.bytes.data());
      check_result(g_api.get_lighting(view, out), "get_lighting");
      break;
    }
    case atmo_fuzz::kGetStateHash: {
      HostStruct<AtmoStateHash> s;
      read_struct(in, head, ATMO_TYPE_STATE_HASH, &s);
      finish(&s);
      AtmoStateHash* out = null ? nullptr : reinterpret_cast<AtmoStateHash*>(s.bytes.data());
      check_result(g_api.get_state_hash(view, out), "get_state_hash");
      break;
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  init();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  AtmoView view = nullptr;
  reset_state(&view);
  Reader in{data, size};
  for (int calls = 0; !in.done() && calls < 16; ++calls) call(in, view);
  g_api.destroy_view(view);
  return 0;
}
