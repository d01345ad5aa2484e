// gpu_timers.h — GL_TIME_ELAPSED queries per frame section, kept in a ring so
// an interactive host reads results a few frames late without stalling.
#pragma once

#include <array>
#include <cstddef>

namespace atmo::sample {

class GpuTimers {
 public:
  static constexpr int kMaxSections = 16;
  static constexpr int kRing = 4;

  // [gl-current]
  void gl_init(int sections);
  void gl_shutdown();

  void begin_frame();
  // Sections must not overlap (GL_TIME_ELAPSED queries cannot nest).
  void begin(int section);
  void end();
  // Ends the frame. wait: read this frame's results now (stalls);
  // otherwise read whatever older frames have finished.
  void end_frame(bool wait);

  // Newest results in milliseconds; a section not run in that frame is NaN.
  const std::array<double, kMaxSections>& milliseconds() const { return ms_; }
  bool has_results() const { return has_results_; }

 private:
  void read(int slot);
  bool available(int slot) const;

  int sections_ = 0;
  unsigned queries_[kRing][kMaxSections] = {};
  bool used_[kRing][kMaxSections] = {};
  bool pending_[kRing] = {};
  int slot_ = 0;
  int active_ = -1;
  bool has_results_ = false;
  std::array<double, kMaxSections> ms_{};
};

}  // namespace atmo::sample
