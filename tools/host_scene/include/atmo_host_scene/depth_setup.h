// depth_setup.h — the host's GL depth state for a depth convention, set for a
// scope and restored after (the GL context must be current and glad loaded).
#ifndef ATMO_HOST_SCENE_DEPTH_SETUP_H
#define ATMO_HOST_SCENE_DEPTH_SETUP_H

#include "atmo_host_scene/camera.h"

namespace atmo::host_scene {

// Reversed needs glClipControl (GL 4.5 or ARB_clip_control).
bool depth_convention_supported(DepthConvention convention);

// Value to clear the depth buffer to: 0 for Reversed (infinity), else 1.
double clear_depth_value(DepthConvention convention);

// Sets depth test on, depth writes on, and for
//   Reversed:              glClipControl(LOWER_LEFT, ZERO_TO_ONE), GEQUAL, clear depth 0;
//   Standard, Logarithmic: glClipControl(LOWER_LEFT, NEGATIVE_ONE_TO_ONE), LEQUAL, clear depth 1.
// The destructor restores what it changed.
class DepthSetup {
 public:
  explicit DepthSetup(DepthConvention convention);
  ~DepthSetup();
  DepthSetup(const DepthSetup&) = delete;
  DepthSetup& operator=(const DepthSetup&) = delete;

  // False if the convention needs glClipControl and it is missing (nothing set).
  bool ok() const { return ok_; }

 private:
  bool ok_ = false;
  bool has_clip_control_ = false;
  int clip_origin_ = 0;
  int clip_depth_mode_ = 0;
  int depth_func_ = 0;
  double clear_depth_ = 1.0;
  unsigned char depth_test_ = 0;
  unsigned char depth_mask_ = 0;
};

}  // namespace atmo::host_scene

#endif  // ATMO_HOST_SCENE_DEPTH_SETUP_H
