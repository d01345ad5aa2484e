// vdb_module_client.h — the VDB reader as libatmo.so sees it: vdb_io.h's
// load_vdb_from_memory, run in libatmo_vdb.so (vdb_module.h), which is loaded
// with dlopen the first time it is needed and closed when libatmo.so unloads.
// Loading libatmo.so therefore maps no OpenVDB and starts no thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "vdb/vdb_io.h"

namespace atmo::vdb {

// As load_vdb_from_memory. A module that is missing, fails to load, or speaks
// another version gives !ok with an error naming its path and the reason.
LoadResult load_vdb_through_module(const uint8_t* bytes, size_t size, const std::string& source_name,
                                   const LoadOptions& options);

// The module's path: ATMO_VDB_MODULE_FILE in the folder of the object this
// code is linked into (libatmo.so; a test executable for atmo_plugin_static).
std::string vdb_module_path();

}  // namespace atmo::vdb
