#include "seams.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace atmo::channels {

int display_level(float linear, float exposure_scale) {
  if (std::isnan(linear)) return -1;
  // tone_map_to_display's per-value chain (tools/support image.cpp): exposure, aces_filmic, srgb_encode.
  const float v = support::srgb_encode(support::aces_filmic(linear * exposure_scale));
  if (std::isnan(v)) return -1;
  return static_cast<int>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

BandDiff compare_bands(const support::Image& a, const support::Image& b, float exposure_scale) {
  if (a.width != b.width || a.height != b.height)
    throw std::runtime_error("compare_bands: " + std::to_string(a.width) + "x" + std::to_string(a.height) + " against " +
                             std::to_string(b.width) + "x" + std::to_string(b.height));
  BandDiff d;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      const float* pa = a.pixel(x, y);
      const float* pb = b.pixel(x, y);
      for (int c = 0; c < 3; ++c) {
        const double va = pa[c], vb = pb[c];
        if (!std::isfinite(va) || !std::isfinite(vb)) {  // a failure on either side, equal or not
          ++d.values_nonfinite;
          continue;
        }
        if (pa[c] != pb[c]) ++d.values_differing;
        const double diff = std::fabs(va - vb);
        const double rel = diff / std::max({std::fabs(va), std::fabs(vb), kRelativeFloorCdM2});
        const int levels = std::abs(display_level(pa[c], exposure_scale) - display_level(pb[c], exposure_scale));
        d.max_levels = std::max(d.max_levels, levels);
        d.max_abs = std::max(d.max_abs, diff);
        if (rel > d.max_relative) {
          d.max_relative = rel;
          d.worst_x = x;
          d.worst_y = y;
        }
      }
    }
  }
  return d;
}

support::Image crop_columns(const support::Image& image, int x0, int w) {
  if (x0 < 0 || w < 0 || x0 + w > image.width) throw std::runtime_error("crop_columns: outside the image");
  support::Image out = support::make_image(w, image.height);
  for (int y = 0; y < image.height; ++y)
    std::copy(image.pixel(x0, y), image.pixel(x0, y) + 4 * static_cast<size_t>(w), out.pixel(0, y));
  return out;
}

support::Image stitch(const std::vector<support::Image>& channels, int band) {
  if (channels.empty()) return {};
  const int w = channels.front().width, h = channels.front().height;
  const int n = static_cast<int>(channels.size());
  for (const support::Image& c : channels)
    if (c.width != w || c.height != h) throw std::runtime_error("stitch: channels of different sizes");
  if (band < 0 || band > w) throw std::runtime_error("stitch: band outside a channel");
  support::Image out = support::make_image(n * w - (n - 1) * band, h);
  for (int i = 0; i < n; ++i) {
    const int x0 = i * (w - band);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        // This channel's weight: ramps up over its left band, down over its right band.
        double weight = 1.0;
        if (i > 0 && x < band) weight = (x + 0.5) / band;
        if (i < n - 1 && x >= w - band) weight = 1.0 - (x - (w - band) + 0.5) / band;
        const float* src = channels[i].pixel(x, y);
        float* dst = out.pixel(x0 + x, y);
        const bool first = !(i > 0 && x < band);  // the only contribution so far
        for (int c = 0; c < 3; ++c)
          dst[c] = first ? static_cast<float>(weight * src[c]) : dst[c] + static_cast<float>(weight * src[c]);
        dst[3] = 1.0f;
      }
    }
  }
  return out;
}

}  // namespace atmo::channels
