// cloud_temporal.h — the layer march's cost per view and its temporal
// upsampling, the CPU half (no GL): which image pixels a frame traces (one of
// each 2x2 block, in an order the view's own pass count keys, so the picture
// is a function of the view's sequence of frames, never of other views or of
// time), when a view's last frame can be reused (not across a camera cut),
// and the matrix that carries a point seen now into the last frame's clip
// space. The GL half is gl/cloud_temporal and shaders/clouds_resolve.frag.
#pragma once

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

namespace atmo::clouds {

// The cost knob of a view (AtmoViewState.cloud_quality): the layer march's
// image resolution (1/divisor of the viewport per axis), its step budget per
// pixel, and whether each frame traces a quarter of the image's pixels and
// reprojects the rest from the view's last frame. docs/CLOUDS.md charts each
// level's error against its cost.
enum class CloudQuality { kLow = 1, kMedium = 2, kHigh = 3, kFull = 4 };
constexpr CloudQuality kDefaultCloudQuality = CloudQuality::kMedium;

struct CloudViewCost {
  int divisor = 2;
  int max_steps = 192;
  bool temporal = true;
};
CloudViewCost cloud_view_cost(CloudQuality quality);

// A cut: the eye moved or turned more than this since the view's last frame
// (or the image changed): the history is dropped and the frame is the
// quarter of traced pixels, interpolated.
constexpr double kTemporalCutDistanceM = 1000.0;
constexpr double kTemporalCutAngleRad = 30.0 * 3.14159265358979323846 / 180.0;

// What the temporal pass needs of a view's frame.
struct TemporalView {
  glm::dvec3 eye_in_clouds_m{0.0};
  glm::dmat3 eye_enu_from_clouds{1.0};  // rotation: the clouds' ENU axes to the eye's
  glm::dmat3 view_from_enu{1.0};        // rotation: the eye's ENU axes to the view's
  glm::dmat4 clip_from_view{1.0};
  int width = 0, height = 0;  // the clouds' image, pixels
  uint64_t host_frame_number = 0;
  uint64_t content_version = 0;  // what the march samples (the clipmap, the light): a change resets
};

// Whether `last` (the view's previous clouds frame) can serve `now`: the same
// image size and content (a rebuilt clipmap or relit clouds would lag up to 3
// frames behind in the reprojected pixels), a host frame number equal to the
// last one or the next (a host that does not count frames leaves it
// unchanged), and no cut.
bool temporal_history_usable(const TemporalView& last, const TemporalView& now);

// clip_last = M * (x, 1) for x a point relative to now's eye, in now's ENU
// axes.
glm::dmat4 last_clip_from_eye_enu(const TemporalView& last, const TemporalView& now);

// The pixel of each 2x2 block that pass `k` of a view's history traces:
// (0,0), (1,1), (1,0), (0,1), so every pixel is traced once in 4 passes and
// no image pixel is more than 3 reprojections away from its own trace.
glm::ivec2 temporal_trace_offset(uint64_t k);

}  // namespace atmo::clouds
