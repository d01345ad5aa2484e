// vdb_module_client.cpp — finds, loads and calls libatmo_vdb.so (vdb_module.h).
#include "abi/vdb_module_client.h"

#include <dlfcn.h>

#include <algorithm>
#include <memory>
#include <mutex>

#include "vdb/vdb_module.h"

#ifdef ATMO_VDB_MODULE_LINKED
extern "C" const AtmoVdbModule* atmo_vdb_module(uint32_t version);
#endif

namespace atmo::vdb {

namespace {

// The module, loaded once per load of libatmo.so. Closed by the static
// destructor, i.e. at dlclose(libatmo.so) or exit: contexts are gone by then
// (a host destroys them before unloading), and no VDB read is in flight.
class Module {
 public:
  ~Module() {
    if (handle_) dlclose(handle_);
  }
  // The table, or NULL with *error set.
  const AtmoVdbModule* get(std::string* error) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!table_ && error_.empty()) open();
    *error = error_;
    return table_;
  }

 private:
#ifdef ATMO_VDB_MODULE_LINKED
  // atmo_plugin_static: the module's code is linked in (tests only).
  void open() { table_ = atmo_vdb_module(ATMO_VDB_MODULE_VERSION); }
#else
  void open() {
    const std::string path = vdb_module_path();
    // RTLD_LOCAL: OpenVDB's symbols stay out of the host's namespace.
    handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle_) {
      const char* e = dlerror();
      error_ = "cannot load the VDB module " + path + " (ship it next to libatmo.so): " + (e ? e : "?");
      return;
    }
    const auto entry = reinterpret_cast<AtmoVdbModuleEntry>(dlsym(handle_, ATMO_VDB_MODULE_ENTRY));
    const AtmoVdbModule* t = entry ? entry(ATMO_VDB_MODULE_VERSION) : nullptr;
    if (!t || t->struct_size < sizeof(AtmoVdbModule) || t->version != ATMO_VDB_MODULE_VERSION) {
      error_ = "the VDB module " + path + " does not speak version " + std::to_string(ATMO_VDB_MODULE_VERSION) +
               (entry ? " (a module from another build?)" : " (no " ATMO_VDB_MODULE_ENTRY ")");
      dlclose(handle_);
      handle_ = nullptr;
      return;
    }
    table_ = t;
  }
#endif

  std::mutex mutex_;
  void* handle_ = nullptr;
  const AtmoVdbModule* table_ = nullptr;
  std::string error_;  // sticky: a missing module is reported, not searched for on every layer
};

Module& module() {
  static Module m;
  return m;
}

LoadResult from_module(const AtmoVdbLoadResult& c, const std::string& path) {
  LoadResult r;
  if (c.struct_size < sizeof(AtmoVdbLoadResult)) {
    r.error = "the VDB module " + path + " returned a result of " + std::to_string(c.struct_size) + " bytes, " +
              "expected " + std::to_string(sizeof(AtmoVdbLoadResult));
    return r;
  }
  r.ok = c.ok != 0;
  r.error = c.error;
  for (uint32_t i = 0; i < c.warning_count; ++i) r.warnings.emplace_back(c.warnings[i]);
  if (!r.ok) return r;
  clouds::CloudVolume& v = r.volume;
  v.name = c.name;
  v.density = clouds::DenseGrid(c.dims[0], c.dims[1], c.dims[2]);
  std::copy(c.density, c.density + v.density.values.size(), v.density.values.begin());
  v.voxel_size_m = c.voxel_size_m;
  v.origin_enu_m = glm::dvec3(c.origin_enu_m[0], c.origin_enu_m[1], c.origin_enu_m[2]);
  v.rotation = glm::dquat(c.rotation_wxyz[0], c.rotation_wxyz[1], c.rotation_wxyz[2], c.rotation_wxyz[3]);
  v.optics.extinction_per_m = c.extinction_per_m;
  v.optics.albedo = c.albedo;
  v.optics.droplet_diameter_um = c.droplet_diameter_um;
  return r;
}

}  // namespace

std::string vdb_module_path() {
  Dl_info info{};
  std::string dir = ".";
  if (dladdr(reinterpret_cast<void*>(&vdb_module_path), &info) && info.dli_fname) {
    const std::string self = info.dli_fname;
    const size_t slash = self.rfind('/');
    if (slash != std::string::npos) dir = self.substr(0, slash);
  }
  return dir + "/" ATMO_VDB_MODULE_FILE;
}

LoadResult load_vdb_through_module(const uint8_t* bytes, size_t size, const std::string& source_name,
                                   const LoadOptions& options) {
  std::string error;
  const AtmoVdbModule* m = module().get(&error);
  if (!m) {
    LoadResult r;
    r.error = source_name + ": " + error;
    return r;
  }
  AtmoVdbLoadOptions o{};
  o.struct_size = sizeof o;
  o.grid_name = options.grid_name.c_str();
  o.max_voxels = options.max_voxels;
  o.metres_per_unit = options.metres_per_unit;
  o.density_scale = options.density_scale;
  const auto release = [m](AtmoVdbLoadResult* c) { m->release_result(c); };
  std::unique_ptr<AtmoVdbLoadResult, decltype(release)> c(m->load_from_memory(bytes, size, source_name.c_str(), &o),
                                                          release);
  return from_module(*c, vdb_module_path());
}

}  // namespace atmo::vdb
