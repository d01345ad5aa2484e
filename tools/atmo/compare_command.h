// compare_command.h — `atmo compare A B`: how far two renders are apart.
// EXR (linear cd/m^2): relative luminance error per pixel (median, p95, max,
// with a floor so black pixels do not divide by zero) and PSNR against the
// larger image's peak; PNG (display-referred): PSNR with peak 1.
#pragma once

#include <string>

namespace atmo::compare {

struct Options {
  std::string a, b;
  double min_psnr_db = 0.0;          // 0: not checked
  double max_relative_p95 = 0.0;     // 0: not checked (EXR only)
  double luminance_floor_cd_m2 = 1.0;
};

// 0: within the given tolerances; 1: outside; 2: error.
int run_compare(const Options& options);

}  // namespace atmo::compare
