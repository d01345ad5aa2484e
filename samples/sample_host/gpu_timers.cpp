#include "gpu_timers.h"

#include <cmath>
#include <limits>

#include <glad/gl.h>

namespace atmo::sample {

void GpuTimers::gl_init(int sections) {
  sections_ = sections < kMaxSections ? sections : kMaxSections;
  for (auto& slot : queries_) glGenQueries(sections_, slot);
  ms_.fill(std::numeric_limits<double>::quiet_NaN());
}

void GpuTimers::gl_shutdown() {
  if (sections_ == 0) return;
  if (active_ >= 0) glEndQuery(GL_TIME_ELAPSED);
  for (auto& slot : queries_) glDeleteQueries(sections_, slot);
  sections_ = 0;
  active_ = -1;
}

void GpuTimers::begin_frame() {
  slot_ = (slot_ + 1) % kRing;
  if (pending_[slot_]) read(slot_);  // only if the GPU is kRing frames behind
  for (bool& u : used_[slot_]) u = false;
}

void GpuTimers::begin(int section) {
  if (section < 0 || section >= sections_) return;
  if (active_ >= 0) end();
  glBeginQuery(GL_TIME_ELAPSED, queries_[slot_][section]);
  used_[slot_][section] = true;
  active_ = section;
}

void GpuTimers::end() {
  if (active_ < 0) return;
  glEndQuery(GL_TIME_ELAPSED);
  active_ = -1;
}

void GpuTimers::end_frame(bool wait) {
  end();
  pending_[slot_] = true;
  if (wait) {
    read(slot_);
    return;
  }
  // Oldest first, so the newest finished frame wins.
  for (int k = 1; k <= kRing; ++k) {
    const int s = (slot_ + k) % kRing;
    if (pending_[s] && available(s)) read(s);
  }
}

bool GpuTimers::available(int slot) const {
  for (int i = 0; i < sections_; ++i) {
    if (!used_[slot][i]) continue;
    GLuint ready = GL_FALSE;
    glGetQueryObjectuiv(queries_[slot][i], GL_QUERY_RESULT_AVAILABLE, &ready);
    if (!ready) return false;
  }
  return true;
}

void GpuTimers::read(int slot) {
  for (int i = 0; i < kMaxSections; ++i) {
    if (i < sections_ && used_[slot][i]) {
      GLuint64 ns = 0;
      glGetQueryObjectui64v(queries_[slot][i], GL_QUERY_RESULT, &ns);
      ms_[static_cast<size_t>(i)] = static_cast<double>(ns) * 1e-6;
    } else {
      ms_[static_cast<size_t>(i)] = std::numeric_limits<double>::quiet_NaN();
    }
  }
  pending_[slot] = false;
  has_results_ = true;
}

}  // namespace atmo::sample
