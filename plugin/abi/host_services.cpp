#include "abi/host_services.h"

#include <dlfcn.h>

#include <cstdio>
#include <cstdlib>

namespace atmo::abi {

namespace {
using EglGetProcAddress = void* (*)(const char*);

// Fallback GL loader: whatever GL loader the host process already has.
void* fallback_gl_proc(void* /*user*/, const char* name) {
  static EglGetProcAddress get = [] {
    void* f = dlsym(RTLD_DEFAULT, "eglGetProcAddress");
    if (!f) f = dlsym(RTLD_DEFAULT, "glXGetProcAddressARB");
    EglGetProcAddress fn = nullptr;
    static_assert(sizeof(fn) == sizeof(f), "function and object pointers differ in size");
    if (f) __builtin_memcpy(&fn, &f, sizeof(f));
    return fn;
  }();
  return get ? get(name) : nullptr;
}

std::string too_large(const std::string& path) {
  return "'" + path + "' is larger than " + std::to_string(kMaxFileBytes) +
         " bytes (ATMO_FILE_SIZE_MAX), the most a file may hold";
}

const char* severity_name(AtmoLogSeverity s) {
  switch (s) {
    case ATMO_LOG_DEBUG: return "debug";
    case ATMO_LOG_INFO: return "info";
    case ATMO_LOG_WARNING: return "warning";
    case ATMO_LOG_ERROR: return "error";
    case ATMO_LOG_HOST_MISBEHAVING: return "host misbehaving";
  }
  return "?";
}
}  // namespace

void HostServices::log(AtmoLogSeverity severity, const std::string& message) const {
  if (s_.log) {
    s_.log(s_.user, severity, message.c_str());
  } else if (severity >= ATMO_LOG_WARNING) {
    const std::string app = application_name_.empty() ? "" : application_name_ + ": ";
    std::fprintf(stderr, "[atmo] %s%s: %s\n", app.c_str(), severity_name(severity), message.c_str());
  }
}

void* HostServices::allocate(size_t size, size_t alignment) const {
  if (s_.allocate && s_.deallocate) return s_.allocate(s_.user, size, alignment);
  size_t rounded = (size + alignment - 1) / alignment * alignment;  // aligned_alloc wants a multiple
  return std::aligned_alloc(alignment, rounded);
}

void HostServices::deallocate(void* p) const {
  if (!p) return;
  if (s_.allocate && s_.deallocate) {
    s_.deallocate(s_.user, p);
  } else {
    std::free(p);
  }
}

bool HostServices::read_file(const std::string& path, const std::string& asset_root, std::vector<uint8_t>* out,
                             std::string* error) const {
  std::string full = (!path.empty() && path[0] == '/') || asset_root.empty() ? path : asset_root + "/" + path;
  out->clear();
  uint8_t chunk[65536];
  if (s_.file_open && s_.file_read && s_.file_close) {
    void* f = s_.file_open(s_.user, full.c_str());
    if (!f) {
      if (error) *error = "host file service cannot open '" + full + "'";
      return false;
    }
    for (;;) {
      const int64_t n = s_.file_read(s_.user, f, chunk, sizeof(chunk));
      std::string why;
      if (n < 0) {
        why = "host file service failed reading '" + full + "' (file_read returned " + std::to_string(n) + ")";
      } else if (static_cast<uint64_t>(n) > sizeof(chunk)) {  // never copy more than the buffer holds
        why = "host file service: file_read returned " + std::to_string(n) + " bytes for a buffer of " +
              std::to_string(sizeof(chunk)) + " reading '" + full + "'";
        log(ATMO_LOG_HOST_MISBEHAVING, why);
      } else if (out->size() + static_cast<size_t>(n) > kMaxFileBytes) {
        why = too_large(full);
      }
      if (!why.empty()) {
        s_.file_close(s_.user, f);
        out->clear();
        if (error) *error = why;
        return false;
      }
      if (n == 0) break;
      out->insert(out->end(), chunk, chunk + n);
    }
    s_.file_close(s_.user, f);
    return true;
  }
  std::FILE* f = std::fopen(full.c_str(), "rb");
  if (!f) {
    if (error) *error = "cannot open '" + full + "'";
    return false;
  }
  size_t n;
  bool too_long = false;
  while (!too_long && (n = std::fread(chunk, 1, sizeof(chunk), f)) > 0) {
    too_long = out->size() + n > kMaxFileBytes;
    if (!too_long) out->insert(out->end(), chunk, chunk + n);
  }
  bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed || too_long) {
    out->clear();
    if (error) *error = too_long ? too_large(full) : "error reading '" + full + "'";
    return false;
  }
  return true;
}

AtmoGlProcLoader HostServices::gl_loader() const {
  if (s_.gl_get_proc_address) return s_.gl_get_proc_address;
  void* probe = dlsym(RTLD_DEFAULT, "eglGetProcAddress");
  if (!probe) probe = dlsym(RTLD_DEFAULT, "glXGetProcAddressARB");
  return probe ? &fallback_gl_proc : nullptr;
}

std::string plugin_directory() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&plugin_directory), &info) && info.dli_fname) {
    std::string path = info.dli_fname;
    size_t slash = path.rfind('/');
    return slash == std::string::npos ? "." : path.substr(0, slash);
  }
  return ".";
}

}  // namespace atmo::abi
