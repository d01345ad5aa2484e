// seams.h — what rank 0 of atmo-channels does with the pixels it gathers: the
// seam comparison (one channel's band drawn by two processes) in linear float
// and in 8-bit display output, and the stitched panorama (docs/MULTI_CHANNEL.md).
// Pure; images are atmo_support's (RGBA float, row 0 at the top).
#pragma once

#include <vector>

#include "atmo_support/image.h"

namespace atmo::channels {

// The 8-bit display value of a linear value (cd/m^2): the plugin's display encoding as the host SDK gives it
// (atmo_support::tone_map_to_display: exposure, the ACES fit, the sRGB transfer function), times 255,
// rounded. NaN gives -1 (never equal to a real level).
int display_level(float linear_cd_m2, float exposure_scale);

// The floor of the relative difference, cd/m^2: |a - b| / max(|a|, |b|, floor).
inline constexpr double kRelativeFloorCdM2 = 1e-3;
// The seam check's limits (docs/MULTI_CHANNEL.md).
inline constexpr int kMaxLevels = 1;
inline constexpr double kMaxRelative = 1e-3;

struct BandDiff {
  int max_levels = 0;       // the largest |level difference| of any R, G, B value
  double max_relative = 0;  // the largest |a - b| / max(|a|, |b|, floor) of any R, G, B value
  double max_abs = 0;       // cd/m^2
  int worst_x = -1, worst_y = -1;  // where max_relative is (-1: no difference)
  long values_differing = 0;       // R, G, B values not bitwise equal
  long values_nonfinite = 0;       // NaN or Inf on either side (a failure)
  bool ok() const { return max_levels <= kMaxLevels && max_relative <= kMaxRelative && values_nonfinite == 0; }
};

// Compares two images of the same size (R, G, B; alpha ignored).
BandDiff compare_bands(const support::Image& a, const support::Image& b, float exposure_scale);

// Columns [x0, x0 + w) of an image.
support::Image crop_columns(const support::Image& image, int x0, int w);

// The channels side by side, each overlapping the next by `band` columns, the shared columns cross-faded
// linearly in linear light (the left channel's weight from 1 to 0 across the band, pixel centres at
// (k + 0.5) / band), as an edge-blended display shows them. Width N * W - (N - 1) * band.
support::Image stitch(const std::vector<support::Image>& channels, int band);

}  // namespace atmo::channels
