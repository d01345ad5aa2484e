// Loading libatmo.so starts no thread and unloading it leaves nothing mapped
// (docs/ABI.md, "Threads"): dlopen + dlclose 50 times, once more with a
// context created and destroyed, once more with a VDB cloud layer read; after
// each dlclose the thread count (/proc/self/task) and the mappings of
// libatmo*, libopenvdb and liblog4cplus (/proc/self/maps) are back where they
// were. This test links neither the plugin nor OpenVDB, so its own baseline
// holds none of them.
#include <dirent.h>
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "atmo/atmo.hpp"

namespace {

// Threads of this process, and their names for the messages.
int thread_count(std::string* names = nullptr) {
  int n = 0;
  if (DIR* d = opendir("/proc/self/task")) {
    while (const dirent* e = readdir(d)) {
      if (e->d_name[0] == '.') continue;
      ++n;
      std::string comm;
      std::getline(std::ifstream(std::string("/proc/self/task/") + e->d_name + "/comm"), comm);
      if (names) *names += " " + std::string(e->d_name) + ":" + comm;
    }
    closedir(d);
  }
  return n;
}

std::string thread_names() {
  std::string names;
  thread_count(&names);
  return names;
}

// Mapped regions per library of interest, by file name.
std::map<std::string, int> library_mappings() {
  std::map<std::string, int> out;
  std::ifstream maps("/proc/self/maps");
  for (std::string line; std::getline(maps, line);) {
    const size_t slash = line.rfind('/');
    if (slash == std::string::npos) continue;
    const std::string file = line.substr(slash + 1);
    for (const char* prefix : {"libatmo", "libopenvdb", "liblog4cplus"})
      if (file.rfind(prefix, 0) == 0) ++out[file];
  }
  return out;
}

// Whether any of OpenVDB or its log4cplus is mapped.
bool maps_openvdb(const std::map<std::string, int>& m) {
  for (const auto& entry : m)
    if (entry.first.rfind("libopenvdb", 0) == 0 || entry.first.rfind("liblog4cplus", 0) == 0) return true;
  return false;
}

std::string describe(const std::map<std::string, int>& m) {
  std::string s;
  for (const auto& [file, n] : m) s += " " + file + " x" + std::to_string(n);
  return s.empty() ? " (none)" : s;
}

struct Snapshot {
  int threads;
  std::map<std::string, int> mappings;
};
Snapshot snapshot() { return {thread_count(), library_mappings()}; }

// What a host does: dlopen (no RTLD_NODELETE, unlike the SDK loader under
// ASan), negotiate, use, dlclose.
class Loaded {
 public:
  explicit Loaded(const std::string& path = ATMO_PLUGIN_PATH) {
    handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle_) {
      ADD_FAILURE() << "dlopen " << path << ": " << dlerror();
      return;
    }
    const auto negotiate = reinterpret_cast<PFN_atmo_negotiate>(dlsym(handle_, ATMO_NEGOTIATE_SYMBOL));
    if (!negotiate) {
      ADD_FAILURE() << "no " ATMO_NEGOTIATE_SYMBOL;
      return;
    }
    AtmoNegotiateInfo info = atmo::make<AtmoNegotiateInfo>(ATMO_TYPE_NEGOTIATE_INFO);
    info.min_interface_version = ATMO_INTERFACE_VERSION_1;
    info.max_interface_version = ATMO_INTERFACE_VERSION_CURRENT;
    info.host_name = "plugin_unload_test";
    api_ = atmo::make<AtmoPluginApi>(ATMO_TYPE_PLUGIN_API);
    ok_ = negotiate(&info, &api_) >= 0;
    EXPECT_TRUE(ok_) << "atmo_negotiate failed";
  }
  ~Loaded() {
    if (handle_) {
      EXPECT_EQ(dlclose(handle_), 0) << dlerror();
    }
  }
  bool ok() const { return ok_; }
  const AtmoPluginApi& api() const { return api_; }

 private:
  void* handle_ = nullptr;
  AtmoPluginApi api_{};
  bool ok_ = false;
};

void copy(const glm::dmat4& m, double out[16]) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[c * 4 + r] = m[c][r];
}

// A context that builds its tables (get_lighting, no GL needed), then changes
// its air, which starts its table worker, and is destroyed while the worker
// builds; before it, an error with no context (kept per thread, last_error(NULL)).
void use_a_context(const AtmoPluginApi& api, int base_threads) {
  AtmoContext ctx = nullptr;
  EXPECT_LT(api.create_context(nullptr, &ctx), 0);
  EXPECT_NE(std::string(api.last_error(nullptr)).find("create_context"), std::string::npos)
      << api.last_error(nullptr);
  AtmoContextCreateInfo info = atmo::make<AtmoContextCreateInfo>(ATMO_TYPE_CONTEXT_CREATE_INFO);
  ASSERT_EQ(api.create_context(&info, &ctx), ATMO_SUCCESS) << api.last_error(nullptr);
  AtmoViewCreateInfo vinfo = atmo::make<AtmoViewCreateInfo>(ATMO_TYPE_VIEW_CREATE_INFO);
  AtmoView view = nullptr;
  EXPECT_EQ(api.create_view(ctx, &vinfo, &view), ATMO_SUCCESS) << api.last_error(ctx);
  AtmoFrameState frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = 1718989800.0;  // 2024-06-21T17:10Z
  EXPECT_EQ(api.set_frame(ctx, &frame), ATMO_SUCCESS) << api.last_error(ctx);
  AtmoViewState vs = atmo::make<AtmoViewState>(ATMO_TYPE_VIEW_STATE);
  vs.eye_kind = ATMO_POSITION_GEODETIC;
  vs.eye_geodetic[0] = vs.world_origin_geodetic[0] = 47.26;
  vs.eye_geodetic[1] = vs.world_origin_geodetic[1] = 11.35;
  vs.eye_geodetic[2] = 300.0;
  vs.world_frame = ATMO_WORLD_ENU;
  copy(glm::lookAt(glm::dvec3(0.0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)), vs.view_from_world);
  copy(glm::perspective(glm::radians(60.0), 1.0, 1.0, 1e5), vs.clip_from_view);
  vs.viewport[2] = vs.viewport[3] = 64;
  EXPECT_EQ(api.set_view(view, &vs), ATMO_SUCCESS) << api.last_error(ctx);
  AtmoLighting lighting = atmo::make<AtmoLighting>(ATMO_TYPE_LIGHTING);
  EXPECT_EQ(api.get_lighting(view, &lighting), ATMO_SUCCESS) << api.last_error(ctx);  // builds the tables
  AtmoAtmosphereState air = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
  air.visibility_m = 20000.0;
  EXPECT_EQ(api.set_atmosphere(ctx, &air), ATMO_SUCCESS) << api.last_error(ctx);
  EXPECT_GT(thread_count(), base_threads) << "set_atmosphere after the first build starts the table worker";
  api.destroy_view(view);
  api.destroy_context(ctx);
}

// The shipped VDB cloud, or a small procedural cumulus layer.
AtmoCloudLayer cloud_layer(AtmoCloudLayerType type) {
  AtmoCloudLayer layer = atmo::make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
  layer.type = type;
  if (type == ATMO_CLOUD_VDB_FILE) {
    layer.vdb_path = ATMO_SOURCE_DIR "/config/scenarios/clouds/cumulus_single.vdb";
    layer.position_enu_m[2] = 1500.0;
  } else {
    layer.coverage_oktas = 1;
    layer.base_m = 1200.0;
    layer.top_m = 1600.0;
    layer.area_size_m = 1000.0;
  }
  return layer;
}

// set_clouds with one layer on a new context (it reads a VDB file at once);
// the result, and the context's last error in *error.
AtmoResult set_one_layer(const AtmoPluginApi& api, const AtmoCloudLayer& layer, std::string* error) {
  AtmoContextCreateInfo info = atmo::make<AtmoContextCreateInfo>(ATMO_TYPE_CONTEXT_CREATE_INFO);
  AtmoContext ctx = nullptr;
  const AtmoResult created = api.create_context(&info, &ctx);
  if (created < 0) {
    *error = api.last_error(nullptr);
    return created;
  }
  AtmoCloudsState clouds = atmo::make<AtmoCloudsState>(ATMO_TYPE_CLOUDS_STATE);
  clouds.layers = &layer;
  clouds.layer_count = 1;
  const AtmoResult r = api.set_clouds(ctx, &clouds);
  *error = api.last_error(ctx);
  api.destroy_context(ctx);
  return r;
}

void use_a_vdb_layer(const AtmoPluginApi& api) {
  std::string error;
  EXPECT_EQ(set_one_layer(api, cloud_layer(ATMO_CLOUD_VDB_FILE), &error), ATMO_SUCCESS) << error;
}

void expect_back_to(const Snapshot& base, const char* what, int cycle) {
  const Snapshot now = snapshot();
  EXPECT_EQ(now.threads, base.threads) << what << ", cycle " << cycle << ": threads" << thread_names()
                                       << ", baseline " << base.threads;
  EXPECT_EQ(now.mappings, base.mappings) << what << ", cycle " << cycle << ": mapped" << describe(now.mappings)
                                         << "; baseline" << describe(base.mappings);
}

TEST(PluginUnload, LoadingStartsNoThreadAndUnloadingUnmapsEverything) {
  const Snapshot base = snapshot();
  std::printf("baseline: %d thread(s), mapped%s\n", base.threads, describe(base.mappings).c_str());
  ASSERT_TRUE(base.mappings.empty()) << "the test itself maps" << describe(base.mappings);
  for (int i = 0; i < 50; ++i) {
    {
      Loaded plugin;
      ASSERT_TRUE(plugin.ok());
      const Snapshot loaded = snapshot();
      // Loaded: the plugin alone (no OpenVDB, no log4cplus), no new thread.
      EXPECT_EQ(loaded.threads, base.threads) << "after dlopen, cycle " << i << ":" << thread_names();
      EXPECT_FALSE(maps_openvdb(loaded.mappings)) << "after dlopen, cycle " << i << ": mapped" << describe(loaded.mappings);
      if (i == 0) std::printf("loaded: %d thread(s), mapped%s\n", loaded.threads, describe(loaded.mappings).c_str());
    }
    expect_back_to(base, "dlopen + dlclose", i);
    if (HasFailure()) return;
  }
  {
    Loaded plugin;
    ASSERT_TRUE(plugin.ok());
    use_a_context(plugin.api(), base.threads);
    EXPECT_EQ(thread_count(), base.threads) << "after destroy_context:" << thread_names();
  }
  expect_back_to(base, "a context created and destroyed", 0);
}

// Once a VDB layer has been read, OpenVDB (and log4cplus, TBB) stay mapped:
// glibc marks libopenvdb NODELETE for its STB_GNU_UNIQUE symbols, so no
// dlclose can unmap it. libatmo.so and libatmo_vdb.so still unload, no thread
// is left (the module stops log4cplus's pool), and a second load reuses what
// stayed: from the first VDB cycle on, nothing grows.
TEST(PluginUnload, AVdbLayerLeavesNoThreadAndUnloadsThePluginAndModule) {
  const Snapshot base = snapshot();
  std::printf("baseline: %d thread(s), mapped%s\n", base.threads, describe(base.mappings).c_str());
  Snapshot after_first{};
  for (int i = 0; i < 3; ++i) {
    {
      Loaded plugin;
      ASSERT_TRUE(plugin.ok());
      use_a_vdb_layer(plugin.api());
      EXPECT_EQ(library_mappings().count("libatmo_vdb.so"), 1u) << "the VDB module was not loaded, cycle " << i;
      EXPECT_EQ(thread_count(), base.threads) << "after a VDB layer was read, cycle " << i << ":" << thread_names();
    }
    const Snapshot now = snapshot();
    std::printf("VDB cycle %d unloaded: %d thread(s), mapped%s\n", i, now.threads, describe(now.mappings).c_str());
    EXPECT_EQ(now.threads, base.threads) << "VDB cycle " << i << ": threads" << thread_names();
    for (const auto& [file, n] : now.mappings)
      EXPECT_NE(file.rfind("libatmo", 0), 0u) << "VDB cycle " << i << ": " << file << " still mapped (" << n << ")";
    if (i == 0) after_first = now;
    else EXPECT_EQ(now.mappings, after_first.mappings) << "VDB cycle " << i << ": mapped" << describe(now.mappings);
  }
}

// A plugin without its module next to it: VDB layers fail with an error that
// names the path looked for, procedural clouds still work, nothing of
// OpenVDB is mapped.
TEST(PluginUnload, WithoutTheModuleOnlyVdbLayersFailAndTheErrorNamesThePath) {
  const std::string dir = ::testing::TempDir() + "atmo_without_vdb_module";
  std::filesystem::create_directories(dir);
  const std::string copy = dir + "/libatmo.so";
  std::filesystem::copy_file(ATMO_PLUGIN_PATH, copy, std::filesystem::copy_options::overwrite_existing);
  ASSERT_FALSE(std::filesystem::exists(dir + "/libatmo_vdb.so"));
  // (ctest runs each test in its own process, where nothing maps OpenVDB yet.)
  const bool openvdb_before = maps_openvdb(library_mappings());
  {
    Loaded plugin(copy);
    ASSERT_TRUE(plugin.ok());
    std::string error;
    EXPECT_EQ(set_one_layer(plugin.api(), cloud_layer(ATMO_CLOUD_VDB_FILE), &error), ATMO_ERROR_IO);
    std::printf("without the module: %s\n", error.c_str());
    EXPECT_NE(error.find("AtmoCloudsState.layers[0]"), std::string::npos) << error;
    EXPECT_NE(error.find(dir + "/libatmo_vdb.so"), std::string::npos) << error;
    EXPECT_EQ(set_one_layer(plugin.api(), cloud_layer(ATMO_CLOUD_CUMULUS), &error), ATMO_SUCCESS) << error;
    EXPECT_EQ(maps_openvdb(library_mappings()), openvdb_before) << describe(library_mappings());
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
