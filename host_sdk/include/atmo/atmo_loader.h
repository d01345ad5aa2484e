/*
 * atmo_loader.h — loads libatmo.so the way every host should: dlopen with
 * RTLD_LOCAL, look up the one entry point, negotiate an interface version.
 * C99, part of the host SDK (static library atmo_host_sdk).
 */
#ifndef ATMO_ATMO_LOADER_H
#define ATMO_ATMO_LOADER_H

#include "atmo/atmo.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct AtmoLoadedPlugin {
  void* library;          /* dlopen handle; NULL when not loaded */
  PFN_atmo_negotiate negotiate;
  AtmoPluginApi api;      /* the negotiated function table */
  char error[512];        /* why loading failed, "" on success */
} AtmoLoadedPlugin;

/* Loads the plugin at `path` (a file path, or a bare name searched by the
   dynamic loader) and negotiates versions in [min_version, max_version].
   Returns ATMO_SUCCESS, or an error with out->error naming the cause.
   On failure the library is closed again. [any-thread][no-gl] */
AtmoResult atmo_load_plugin(const char* path, uint32_t min_version, uint32_t max_version,
                            const char* host_name, AtmoLoadedPlugin* out);

/* Closes the library. Destroy every context first. NULL or unloaded is fine. [any-thread][no-gl] */
void atmo_unload_plugin(AtmoLoadedPlugin* plugin);

#ifdef __cplusplus
}
#endif

#endif /* ATMO_ATMO_LOADER_H */
