#include "core/clouds/cloud_temporal.h"

#include <algorithm>
#include <cmath>

namespace atmo::clouds {

CloudViewCost cloud_view_cost(CloudQuality quality) {
  switch (quality) {
    case CloudQuality::kLow:
      return {4, 96, true};
    case CloudQuality::kMedium:
      return {2, 64, true};
    case CloudQuality::kHigh:
      return {2, 192, false};
    case CloudQuality::kFull:
      return {1, 384, false};
  }
  return cloud_view_cost(kDefaultCloudQuality);
}

bool temporal_history_usable(const TemporalView& last, const TemporalView& now) {
  if (last.width != now.width || last.height != now.height || last.width <= 0 || last.height <= 0) return false;
  if (last.content_version != now.content_version) return false;
  if (now.host_frame_number != last.host_frame_number && now.host_frame_number != last.host_frame_number + 1)
    return false;
  if (glm::length(now.eye_in_clouds_m - last.eye_in_clouds_m) > kTemporalCutDistanceM) return false;
  // The angle between the two views' axes in the clouds' frame: forward and up.
  const glm::dmat3 last_axes = glm::transpose(last.view_from_enu * last.eye_enu_from_clouds);  // view -> clouds
  const glm::dmat3 now_axes = glm::transpose(now.view_from_enu * now.eye_enu_from_clouds);
  const double cos_cut = std::cos(kTemporalCutAngleRad);
  for (int axis : {1, 2})
    if (glm::dot(last_axes[axis], now_axes[axis]) < cos_cut) return false;
  // A new projection (zoom, another frustum) is a cut too, beyond 1 %.
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      const double a = last.clip_from_view[c][r], b = now.clip_from_view[c][r];
      if (std::abs(a - b) > 0.01 * std::max({1.0, std::abs(a), std::abs(b)})) return false;
    }
  return true;
}

glm::dmat4 last_clip_from_eye_enu(const TemporalView& last, const TemporalView& now) {
  // x in now's eye ENU -> the clouds' frame -> last's eye ENU -> last's view ->
  // clip.
  const glm::dmat3 r = last.eye_enu_from_clouds * glm::transpose(now.eye_enu_from_clouds);
  const glm::dvec3 shift = last.eye_enu_from_clouds * (now.eye_in_clouds_m - last.eye_in_clouds_m);
  glm::dmat4 last_enu_from_now(r);
  last_enu_from_now[3] = glm::dvec4(shift, 1.0);
  return last.clip_from_view * glm::dmat4(last.view_from_enu) * last_enu_from_now;
}

glm::ivec2 temporal_trace_offset(uint64_t k) {
  static constexpr std::array<glm::ivec2, 4> kOrder = {glm::ivec2(0, 0), glm::ivec2(1, 1), glm::ivec2(1, 0),
                                                       glm::ivec2(0, 1)};
  return kOrder[k % 4];
}

}  // namespace atmo::clouds
