// Image comparison: PSNR/RMSE over RGB and relative luminance error.
#pragma once

#include <cstddef>

#include "atmo_support/image.h"

namespace atmo::support {

struct ImageDiff {
  double psnr_db = 0.0;     // 20 log10(peak / rmse); +inf when rmse == 0
  double rmse = 0.0;        // over R, G, B of the pixels finite in both images
  double max_abs = 0.0;     // largest |a - b| of one channel, same pixels
  size_t nonfinite_a = 0;   // pixels of a with a NaN/Inf in R, G or B
  size_t nonfinite_b = 0;
  size_t pixels = 0;        // pixels compared (finite in both)
};

// RGB only. Throws std::invalid_argument if the sizes differ or peak <= 0.
ImageDiff compare_images(const Image& a, const Image& b, double peak);

// Pixels with a NaN or Inf in any of R, G, B, A.
size_t count_nonfinite(const Image& image);

// Rec. 709 relative luminance 0.2126 R + 0.7152 G + 0.0722 B.
double luminance(const float* rgb);

struct LuminanceErrorStats {
  double median = 0.0, p95 = 0.0, max = 0.0;
};

// Per pixel |Y_t - Y_r| / max(Y_r, floor), Y = Rec. 709 luminance; a
// non-finite error counts as +inf. Percentiles interpolate linearly between
// ranks (like numpy). All zero for empty images. Throws std::invalid_argument
// if the sizes differ.
LuminanceErrorStats relative_luminance_error(const Image& test, const Image& reference, double floor);

}  // namespace atmo::support
