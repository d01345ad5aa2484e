// state_hash.h — a 64-bit hash of values fed one by one (the state hash of
// get_state_hash: channels compare it, docs/MULTI_CHANNEL.md). Fed field by
// field, never as raw structs, so padding bytes never enter it; doubles by
// their bits (-0 and 0 differ: the same inputs give the same bits). Not
// cryptographic: it tells two channels' states apart, nothing more.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace atmo::core {

class StateHasher {
 public:
  explicit StateHasher(uint64_t seed = 0) : h_(0x9E3779B97F4A7C15ull ^ seed) {}
  uint64_t value() const { return mix(h_ ^ (count_ * 0xD6E8FEB86659FD93ull)); }

  void add(uint64_t w) {
    h_ = mix(h_ ^ w) + 0x632BE59BD9B4E019ull;
    ++count_;
  }
  void add(int64_t v) { add(static_cast<uint64_t>(v)); }
  void add(int v) { add(static_cast<uint64_t>(static_cast<int64_t>(v))); }
  void add(uint32_t v) { add(static_cast<uint64_t>(v)); }
  void add(bool v) { add(static_cast<uint64_t>(v ? 1 : 0)); }
  void add(double v) {
    uint64_t w = 0;
    std::memcpy(&w, &v, sizeof w);
    add(w);
  }
  void add(float v) { add(static_cast<double>(v)); }
  template <int N, typename T, glm::qualifier Q>
  void add(const glm::vec<N, T, Q>& v) {
    for (int i = 0; i < N; ++i) add(v[i]);
  }
  template <int C, int R, typename T, glm::qualifier Q>
  void add(const glm::mat<C, R, T, Q>& m) {
    for (int c = 0; c < C; ++c) add(m[c]);
  }
  void add(const glm::dquat& q) {
    add(q.w), add(q.x), add(q.y), add(q.z);
  }
  void add(const std::string& s) {
    add(static_cast<uint64_t>(s.size()));
    add_bytes(s.data(), s.size());
  }
  // Raw bytes (only of arrays of plain numbers: no padding), 8 at a time.
  void add_bytes(const void* data, size_t n) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
      uint64_t w;
      std::memcpy(&w, p + i, 8);
      add(w);
    }
    uint64_t tail = 0;
    std::memcpy(&tail, p + i, n - i);
    add(tail ^ (static_cast<uint64_t>(n - i) << 56));
  }
  void add(const std::vector<float>& v) {
    add(static_cast<uint64_t>(v.size()));
    add_bytes(v.data(), v.size() * sizeof(float));
  }

 private:
  // SplitMix64's finaliser.
  static uint64_t mix(uint64_t x) {
    x ^= x >> 30;
    x *= 0xBF58476D1CE4E5B9ull;
    x ^= x >> 27;
    x *= 0x94D049BB133111EBull;
    return x ^ (x >> 31);
  }
  uint64_t h_;
  uint64_t count_ = 0;
};

}  // namespace atmo::core
