#include "atmo_support/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace atmo::support {

namespace {

void check_sizes(const Image& a, const Image& b, const char* what) {
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument(std::string(what) + ": image sizes differ (" + std::to_string(a.width) + "x" +
                                std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" +
                                std::to_string(b.height) + ")");
  if (a.rgba.size() != a.pixel_count() * 4 || b.rgba.size() != b.pixel_count() * 4)
    throw std::invalid_argument(std::string(what) + ": rgba size does not match width*height*4");
}

bool finite_rgb(const float* p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

// Linear interpolation between closest ranks (numpy's default); v sorted.
double percentile(const std::vector<double>& v, double q) {
  if (v.empty()) return 0.0;
  const double pos = q * static_cast<double>(v.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, v.size() - 1);
  const double t = pos - static_cast<double>(lo);
  if (t == 0.0 || v[lo] == v[hi]) return v[lo];  // also avoids inf - inf
  return v[lo] + (v[hi] - v[lo]) * t;
}

}  // namespace

ImageDiff compare_images(const Image& a, const Image& b, double peak) {
  check_sizes(a, b, "compare_images");
  if (!(peak > 0.0)) throw std::invalid_argument("compare_images: peak must be > 0");
  ImageDiff d;
  double sum_sq = 0.0;
  for (size_t i = 0; i < a.pixel_count(); ++i) {
    const float* pa = &a.rgba[i * 4];
    const float* pb = &b.rgba[i * 4];
    const bool fa = finite_rgb(pa), fb = finite_rgb(pb);
    d.nonfinite_a += !fa;
    d.nonfinite_b += !fb;
    if (!fa || !fb) continue;
    ++d.pixels;
    for (int c = 0; c < 3; ++c) {
      const double e = static_cast<double>(pa[c]) - static_cast<double>(pb[c]);
      sum_sq += e * e;
      d.max_abs = std::max(d.max_abs, std::fabs(e));
    }
  }
  d.rmse = d.pixels ? std::sqrt(sum_sq / (3.0 * static_cast<double>(d.pixels))) : 0.0;
  d.psnr_db = d.rmse > 0.0 ? 20.0 * std::log10(peak / d.rmse) : std::numeric_limits<double>::infinity();
  return d;
}

size_t count_nonfinite(const Image& image) {
  size_t n = 0;
  for (size_t i = 0; i + 3 < image.rgba.size(); i += 4) {
    const float* p = &image.rgba[i];
    n += !(finite_rgb(p) && std::isfinite(p[3]));
  }
  return n;
}

double luminance(const float* rgb) {
  return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
}

LuminanceErrorStats relative_luminance_error(const Image& test, const Image& reference, double floor) {
  check_sizes(test, reference, "relative_luminance_error");
  LuminanceErrorStats s;
  std::vector<double> err(test.pixel_count());
  for (size_t i = 0; i < err.size(); ++i) {
    const double yt = luminance(&test.rgba[i * 4]);
    const double yr = luminance(&reference.rgba[i * 4]);
    const double e = std::fabs(yt - yr) / std::max(yr, floor);
    err[i] = std::isfinite(e) ? e : std::numeric_limits<double>::infinity();
  }
  if (err.empty()) return s;
  std::sort(err.begin(), err.end());
  s.median = percentile(err, 0.5);
  s.p95 = percentile(err, 0.95);
  s.max = err.back();
  return s;
}

}  // namespace atmo::support
