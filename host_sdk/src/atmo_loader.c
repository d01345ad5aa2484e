/* The host SDK's plugin loader. See atmo_loader.h. */
#define _GNU_SOURCE
#include "atmo/atmo_loader.h"

#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

AtmoResult atmo_load_plugin(const char* path, uint32_t min_version, uint32_t max_version,
                            const char* host_name, AtmoLoadedPlugin* out) {
  if (!out) return ATMO_ERROR_INVALID_ARGUMENT;
  memset(out, 0, sizeof(*out));
  if (!path) {
    snprintf(out->error, sizeof(out->error), "atmo_load_plugin: path is NULL");
    return ATMO_ERROR_INVALID_ARGUMENT;
  }
  /* RTLD_LOCAL: the plugin's dependencies must not resolve the host's symbols,
     nor the other way round. RTLD_NOW: fail here, not mid-frame. Under
     AddressSanitizer the code stays mapped after dlclose, so a leak report
     can still name the plugin's functions. */
  int flags = RTLD_NOW | RTLD_LOCAL;
#if defined(__SANITIZE_ADDRESS__)
  flags |= RTLD_NODELETE;
#endif
  out->library = dlopen(path, flags);
  if (!out->library) {
    const char* why = dlerror();
    snprintf(out->error, sizeof(out->error), "cannot load plugin '%s': %s", path, why ? why : "unknown");
    return ATMO_ERROR_IO;
  }
  void* symbol = dlsym(out->library, ATMO_NEGOTIATE_SYMBOL);
  if (!symbol) {
    snprintf(out->error, sizeof(out->error), "'%s' does not export %s: not an Atmo plugin", path,
             ATMO_NEGOTIATE_SYMBOL);
    dlclose(out->library);
    out->library = NULL;
    return ATMO_ERROR_INCOMPATIBLE_VERSION;
  }
  memcpy(&out->negotiate, &symbol, sizeof(symbol)); /* object -> function pointer, POSIX-sanctioned */

  AtmoNegotiateInfo info;
  memset(&info, 0, sizeof(info));
  info.header.type = ATMO_TYPE_NEGOTIATE_INFO;
  info.header.struct_size = (uint32_t)sizeof(info);
  info.min_interface_version = min_version;
  info.max_interface_version = max_version;
  info.host_name = host_name;
  out->api.header.type = ATMO_TYPE_PLUGIN_API;
  out->api.header.struct_size = (uint32_t)sizeof(out->api);
  AtmoResult result = out->negotiate(&info, &out->api);
  if (result < 0) {
    snprintf(out->error, sizeof(out->error),
             "plugin '%s' refused interface versions [%u, %u] (result %d)", path, min_version,
             max_version, (int)result);
    dlclose(out->library);
    out->library = NULL;
    out->negotiate = NULL;
    return result;
  }
  return ATMO_SUCCESS;
}

void atmo_unload_plugin(AtmoLoadedPlugin* plugin) {
  if (!plugin || !plugin->library) return;
  dlclose(plugin->library);
  plugin->library = NULL;
  plugin->negotiate = NULL;
}
