#include "compare_command.h"

#include <algorithm>
#include <cstdio>

#include "atmo_support/image.h"
#include "atmo_support/image_metrics.h"

namespace atmo::compare {

namespace {
bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
bool read_any(const std::string& path, support::Image* out, std::string* error) {
  if (ends_with(path, ".exr")) return support::read_exr(path, out, error);
  if (ends_with(path, ".png")) return support::read_png(path, out, error);
  *error = path + ": not an .exr or .png file";
  return false;
}
double peak_of(const support::Image& img) {
  double peak = 0.0;
  for (size_t i = 0; i < img.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) peak = std::max(peak, static_cast<double>(img.rgba[i * 4 + c]));
  return peak;
}
}  // namespace

int run_compare(const Options& o) {
  support::Image a, b;
  std::string error;
  if (!read_any(o.a, &a, &error) || !read_any(o.b, &b, &error)) {
    std::fprintf(stderr, "atmo compare: %s\n", error.c_str());
    return 2;
  }
  if (a.width != b.width || a.height != b.height) {
    std::fprintf(stderr, "atmo compare: sizes differ: %dx%d vs %dx%d\n", a.width, a.height, b.width, b.height);
    return 2;
  }
  const bool linear = ends_with(o.a, ".exr");
  const double peak = linear ? std::max(peak_of(a), peak_of(b)) : 1.0;
  support::ImageDiff diff = support::compare_images(a, b, peak);
  std::printf("%s vs %s: %dx%d, PSNR %.2f dB (peak %.4g), RMSE %.4g, max |difference| %.4g, non-finite %zu / %zu\n",
              o.a.c_str(), o.b.c_str(), a.width, a.height, diff.psnr_db, peak, diff.rmse, diff.max_abs,
              diff.nonfinite_a, diff.nonfinite_b);
  bool ok = diff.nonfinite_a == 0 && diff.nonfinite_b == 0;
  if (o.min_psnr_db > 0 && !(diff.psnr_db >= o.min_psnr_db)) {
    std::printf("FAIL: PSNR %.2f dB < %.2f dB\n", diff.psnr_db, o.min_psnr_db);
    ok = false;
  }
  if (linear) {
    support::LuminanceErrorStats s = support::relative_luminance_error(a, b, o.luminance_floor_cd_m2);
    std::printf("relative luminance error (floor %.3g cd/m^2): median %.3e, p95 %.3e, max %.3e\n",
                o.luminance_floor_cd_m2, s.median, s.p95, s.max);
    if (o.max_relative_p95 > 0 && !(s.p95 <= o.max_relative_p95)) {
      std::printf("FAIL: p95 relative luminance error %.3e > %.3e\n", s.p95, o.max_relative_p95);
      ok = false;
    }
  }
  std::printf("%s\n", ok ? "PASS" : "FAIL");
  return ok ? 0 : 1;
}

}  // namespace atmo::compare
