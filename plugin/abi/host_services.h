// host_services.h — the host's optional services with the fallbacks atmo.h
// documents: stderr logging, aligned_alloc, stdio files, and GL loading via
// eglGetProcAddress / glXGetProcAddressARB already loaded in the process.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "atmo/atmo.h"

namespace atmo::abi {

// The most bytes one file read through read_file may hold (atmo.h).
constexpr size_t kMaxFileBytes = ATMO_FILE_SIZE_MAX;

class HostServices {
 public:
  HostServices() = default;
  // Copies the services the host set; members beyond its struct_size stay NULL.
  explicit HostServices(const AtmoHostServices& s) : s_(s) {}

  // The stderr fallback names the application (AtmoContextCreateInfo.application_name).
  void set_application_name(const std::string& name) { application_name_ = name; }
  void log(AtmoLogSeverity severity, const std::string& message) const;
  void* allocate(size_t size, size_t alignment) const;
  void deallocate(void* p) const;
  // Reads a whole file (relative paths against asset_root), at most kMaxFileBytes.
  // False + *error naming the path on failure (also when the host's file_read
  // returns more than it was asked for: nothing past the buffer is read).
  bool read_file(const std::string& path, const std::string& asset_root, std::vector<uint8_t>* out,
                 std::string* error) const;
  // GL loader: the host's, or the fallback; null if neither exists.
  AtmoGlProcLoader gl_loader() const;
  void* gl_loader_user() const { return s_.user; }
  bool has_host_gl_loader() const { return s_.gl_get_proc_address != nullptr; }

 private:
  AtmoHostServices s_{};
  std::string application_name_;
};

// Directory holding libatmo.so, for the default asset_root.
std::string plugin_directory();

}  // namespace atmo::abi
