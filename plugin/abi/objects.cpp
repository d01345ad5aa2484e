#include "abi/objects.h"

#include <algorithm>
#include <mutex>
#include <unordered_set>

namespace atmo::abi {

namespace {
std::mutex& registry_mutex() {
  static std::mutex m;
  return m;
}
std::unordered_set<const void*>& contexts() {
  static std::unordered_set<const void*> s;
  return s;
}
std::unordered_set<const void*>& views() {
  static std::unordered_set<const void*> s;
  return s;
}
}  // namespace

void register_context(AtmoContext_T* c) {
  std::lock_guard<std::mutex> lock(registry_mutex());
  contexts().insert(c);
}
void unregister_context(AtmoContext_T* c) {
  std::lock_guard<std::mutex> lock(registry_mutex());
  contexts().erase(c);
}
bool is_live_context(const AtmoContext_T* c) {
  std::lock_guard<std::mutex> lock(registry_mutex());
  return c && contexts().count(c) != 0;
}
void register_view(AtmoView_T* v) {
  std::lock_guard<std::mutex> lock(registry_mutex());
  views().insert(v);
}
void unregister_view(AtmoView_T* v) {
  std::lock_guard<std::mutex> lock(registry_mutex());
  views().erase(v);
}
bool is_live_view(const AtmoView_T* v) {
  std::lock_guard<std::mutex> lock(registry_mutex());
  return v && views().count(v) != 0;
}

}  // namespace atmo::abi
