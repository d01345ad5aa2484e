// vdb_module.cpp — libatmo_vdb.so: vdb_io.h behind the C table of vdb_module.h.
#include "vdb/vdb_module.h"

#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "vdb/vdb_io.h"

// log4cplus (a dependency of libopenvdb) starts its thread pool when it is
// loaded. Weak: resolved from libopenvdb's dependencies at load time, and a
// build against an OpenVDB without log4cplus simply has none to stop.
namespace log4cplus {
__attribute__((weak)) void shutdownThreadPool();
}

namespace {

// The C result and the C++ objects its pointers point into.
struct Holder : AtmoVdbLoadResult {
  atmo::vdb::LoadResult r;
  std::vector<const char*> warning_ptrs;
};

AtmoVdbLoadResult* out_of_memory() {
  static AtmoVdbLoadResult r = [] {
    AtmoVdbLoadResult x{};
    x.struct_size = sizeof x;
    x.error = "libatmo_vdb: out of memory while reading the file";
    x.name = "";
    return x;
  }();
  return &r;
}

AtmoVdbLoadResult* load_from_memory(const void* bytes, size_t size, const char* source_name,
                                    const AtmoVdbLoadOptions* options) {
  try {
    std::unique_ptr<Holder> h(new Holder{});
    h->struct_size = sizeof(AtmoVdbLoadResult);
    if (!options || options->struct_size < sizeof *options || (!bytes && size > 0) || !source_name || !options->grid_name) {
      h->r.error = "libatmo_vdb: load_from_memory: NULL argument or options.struct_size " +
                   std::to_string(options ? options->struct_size : 0) + " < " +
                   std::to_string(sizeof(AtmoVdbLoadOptions));
    } else {
      atmo::vdb::LoadOptions o;
      o.grid_name = options->grid_name;
      o.max_voxels = static_cast<size_t>(options->max_voxels);
      o.metres_per_unit = options->metres_per_unit;
      o.density_scale = options->density_scale;
      h->r = atmo::vdb::load_vdb_from_memory(size ? std::string(static_cast<const char*>(bytes), size) : std::string(),
                                             source_name, o);
    }
    const atmo::vdb::LoadResult& r = h->r;
    const atmo::clouds::CloudVolume& v = r.volume;
    for (const std::string& w : r.warnings) h->warning_ptrs.push_back(w.c_str());
    h->ok = r.ok ? 1 : 0;
    h->error = r.error.c_str();
    h->warnings = h->warning_ptrs.data();
    h->warning_count = static_cast<uint32_t>(h->warning_ptrs.size());
    h->name = v.name.c_str();
    h->dims[0] = v.density.nx;
    h->dims[1] = v.density.ny;
    h->dims[2] = v.density.nz;
    h->density = v.density.values.data();
    h->voxel_size_m = v.voxel_size_m;
    for (int i = 0; i < 3; ++i) h->origin_enu_m[i] = v.origin_enu_m[i];
    h->rotation_wxyz[0] = v.rotation.w;
    h->rotation_wxyz[1] = v.rotation.x;
    h->rotation_wxyz[2] = v.rotation.y;
    h->rotation_wxyz[3] = v.rotation.z;
    h->extinction_per_m = v.optics.extinction_per_m;
    h->albedo = v.optics.albedo;
    h->droplet_diameter_um = v.optics.droplet_diameter_um;
    return h.release();
  } catch (...) {  // std::bad_alloc: vdb_io itself reports everything else
    return out_of_memory();
  }
}

void release_result(AtmoVdbLoadResult* result) {
  if (!result || result == out_of_memory()) return;
  delete static_cast<Holder*>(result);
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const AtmoVdbModule* atmo_vdb_module(uint32_t version) {
  static const AtmoVdbModule table = {sizeof(AtmoVdbModule), ATMO_VDB_MODULE_VERSION, &load_from_memory,
                                      &release_result};
  static std::once_flag once;
  std::call_once(once, [] {
    if (log4cplus::shutdownThreadPool) log4cplus::shutdownThreadPool();
  });
  return version == ATMO_VDB_MODULE_VERSION ? &table : nullptr;
}
