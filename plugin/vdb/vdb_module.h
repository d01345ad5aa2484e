/* vdb_module.h — the internal C ABI between libatmo.so and libatmo_vdb.so.
 *
 * OpenVDB pulls in log4cplus, whose static initialiser starts 4 threads, and
 * its 530 STB_GNU_UNIQUE symbols make glibc keep it mapped once loaded. So
 * libatmo.so does not link OpenVDB: the VDB reader lives in libatmo_vdb.so,
 * built and shipped next to libatmo.so, which the plugin dlopens the first
 * time a VDB cloud layer is read (vdb_module_client.h). Not a public ABI (no
 * host sees it), but versioned and size-checked like one, so a stale module
 * left next to a newer plugin is refused with a message, not called blindly.
 *
 * The module exports ATMO_VDB_MODULE_ENTRY and nothing else. Plain C types
 * only: no C++ object crosses the boundary, and no exception. */
#pragma once

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define ATMO_VDB_MODULE_VERSION 1u
#define ATMO_VDB_MODULE_FILE "libatmo_vdb.so"
#define ATMO_VDB_MODULE_ENTRY "atmo_vdb_module"

/* vdb::LoadOptions (vdb_io.h), field for field. */
typedef struct AtmoVdbLoadOptions {
  uint32_t struct_size; /* sizeof(AtmoVdbLoadOptions) */
  const char* grid_name; /* "" = the first float fog-volume grid; never NULL */
  uint64_t max_voxels;
  double metres_per_unit;
  double density_scale;
} AtmoVdbLoadOptions;

/* vdb::LoadResult (vdb_io.h). Owned by the module: every pointer stays valid
 * until release_result. */
typedef struct AtmoVdbLoadResult {
  uint32_t struct_size; /* sizeof(AtmoVdbLoadResult) as the module knows it */
  int32_t ok;
  const char* error; /* "" when ok */
  const char* const* warnings;
  uint32_t warning_count;
  /* The volume (cloud_volume.h), meaningful when ok. */
  const char* name;
  int32_t dims[3];      /* density.nx, ny, nz */
  const float* density; /* dims[0] * dims[1] * dims[2] values, x fastest */
  float voxel_size_m;
  double origin_enu_m[3];
  double rotation_wxyz[4];
  float extinction_per_m;
  float albedo;
  float droplet_diameter_um;
} AtmoVdbLoadResult;

typedef struct AtmoVdbModule {
  uint32_t struct_size; /* sizeof(AtmoVdbModule) as the module knows it */
  uint32_t version;     /* ATMO_VDB_MODULE_VERSION */
  /* vdb::load_vdb_from_memory. Never NULL: an allocation failure too comes
   * back as !ok with a message (a static result, which release_result
   * ignores). */
  AtmoVdbLoadResult* (*load_from_memory)(const void* bytes, size_t size, const char* source_name,
                                         const AtmoVdbLoadOptions* options);
  void (*release_result)(AtmoVdbLoadResult* result);
} AtmoVdbModule;

/* The one export: the module's table for `version`, or NULL if it does not
 * speak it. Stops the log4cplus threads that loading OpenVDB started (the
 * plugin starts no thread of its own before create_context, and OpenVDB logs
 * synchronously, so the pool is never used). */
typedef const AtmoVdbModule* (*AtmoVdbModuleEntry)(uint32_t version);

#ifdef __cplusplus
}
#endif
