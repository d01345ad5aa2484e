#include "default_paths.h"

#include <unistd.h>

#include <climits>

namespace atmo::cli {
namespace {

// `relative` from the folder holding this executable, when that file exists; else `fallback`.
std::string next_to_executable(const char* relative, const char* fallback) {
  char exe[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n > 0) {
    std::string path(exe, static_cast<size_t>(n));
    path = path.substr(0, path.rfind('/') + 1) + relative;
    if (access(path.c_str(), R_OK) == 0) return path;
  }
  return fallback;
}

}  // namespace

std::string default_plugin_path() {
  return next_to_executable(ATMO_INSTALLED_PLUGIN_FROM_BIN, ATMO_DEFAULT_PLUGIN_PATH);
}

std::string default_star_catalog_path() {
  return next_to_executable(ATMO_INSTALLED_STAR_CATALOG_FROM_BIN, ATMO_DEFAULT_STAR_CATALOG);
}

}  // namespace atmo::cli
