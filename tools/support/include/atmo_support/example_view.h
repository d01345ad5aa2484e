// example_view.h — a known-good camera and host depth for the validator,
// benchmarks and GL tests, so each does not build its own.
#pragma once

#include <vector>

#include "atmo/atmo.h"

namespace atmo::support {

// A valid AtmoViewState: geodetic eye over Innsbruck (47.26° N, 11.35° E) at
// `height_m`, ENU world, looking north and level, 60° vertical field of view,
// near 1 m, far 100 km (standard depth), the full `width` x `height` viewport,
// exposure 1e-4.
AtmoViewState example_view_state(int width, int height, unsigned depth_texture, double height_m = 600.0);

// A GL_DEPTH_COMPONENT32F texture (nearest filtering): window depth
// `geometry_depth` in the lower half (host geometry; 0.9999 is about 10 km for
// example_view_state's projection) and the far plane, 1.0, above. [gl-current]
unsigned make_split_depth_texture(int width, int height, float geometry_depth);

// A GL_DEPTH_COMPONENT32F texture (nearest filtering) holding `depth`, width x
// height window-depth values, row 0 at the bottom (GL order); the 2D binding is
// left as it was. [gl-current]
unsigned make_depth_texture(int width, int height, const std::vector<float>& depth);

}  // namespace atmo::support
