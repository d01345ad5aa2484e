// chart_png_check PNG WIDTH HEIGHT [MIN_INK] [MIN_COLOURS]
// Passes (exit 0) when the PNG written by atmo-chart has the requested size, a
// white background, at least MIN_INK non-white pixels (default 500), and at
// least MIN_COLOURS distinct saturated hues (default 3: one per series; grey,
// black and white text, axes, grid and the reference line do not count).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "atmo_support/image.h"

namespace {

// Hue in degrees [0, 360) and chroma (max - min) of an RGB triple in [0, 1].
void hue_chroma(const float* p, float* hue, float* chroma) {
  const float r = p[0], g = p[1], b = p[2];
  const float mx = std::max({r, g, b}), mn = std::min({r, g, b});
  const float c = mx - mn;
  *chroma = c;
  if (c <= 0.0f) {
    *hue = 0.0f;
    return;
  }
  float h;
  if (mx == r)
    h = std::fmod((g - b) / c, 6.0f);
  else if (mx == g)
    h = (b - r) / c + 2.0f;
  else
    h = (r - g) / c + 4.0f;
  h *= 60.0f;
  if (h < 0.0f) h += 360.0f;
  *hue = h;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s PNG WIDTH HEIGHT [MIN_INK] [MIN_COLOURS]\n", argv[0]);
    return 2;
  }
  const std::string path = argv[1];
  const int want_w = std::atoi(argv[2]), want_h = std::atoi(argv[3]);
  const long min_ink = argc > 4 ? std::atol(argv[4]) : 500;
  const int min_colours = argc > 5 ? std::atoi(argv[5]) : 3;

  atmo::support::Image image;
  std::string error;
  if (!atmo::support::read_png(path, &image, &error)) {
    std::printf("FAIL %s\n", error.c_str());
    return 1;
  }
  bool ok = true;
  std::printf("%s: %dx%d (want %dx%d)\n", path.c_str(), image.width, image.height, want_w, want_h);
  if (image.width != want_w || image.height != want_h) {
    std::printf("FAIL size\n");
    ok = false;
  }

  // Background: the four corners are white.
  const int xs[2] = {0, image.width - 1}, ys[2] = {0, image.height - 1};
  for (int x : xs)
    for (int y : ys) {
      const float* p = image.pixel(x, y);
      if (std::min({p[0], p[1], p[2]}) < 0.97f) {
        std::printf("FAIL corner (%d,%d) is not white: %.3f %.3f %.3f\n", x, y, p[0], p[1], p[2]);
        ok = false;
      }
    }

  // Ink, and saturated pixels counted in twelve 30-degree hue bins.
  long ink = 0;
  std::array<long, 12> bins{};
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const float* p = image.pixel(x, y);
      if (std::min({p[0], p[1], p[2]}) < 0.9f) ++ink;
      float hue, chroma;
      hue_chroma(p, &hue, &chroma);
      if (chroma >= 0.3f) ++bins[static_cast<size_t>(hue / 30.0f) % bins.size()];
    }
  // A series' colour covers its line, markers and labels: hundreds of pixels.
  // Anti-aliased edges between two colours give a few stray hues; ignore them.
  const long min_bin = 60;
  int colours = 0;
  std::printf("non-white pixels: %ld (want >= %ld)\nsaturated pixels per 30-degree hue bin:", ink, min_ink);
  for (long n : bins) std::printf(" %ld", n);
  // A run of neighbouring full bins (one hue straddling a boundary) counts once.
  const size_t nb = bins.size();
  for (size_t i = 0; i < nb; ++i)
    if (bins[i] >= min_bin && bins[(i + nb - 1) % nb] < min_bin) ++colours;
  if (colours == 0 && bins[0] >= min_bin) colours = 1;  // every bin full
  std::printf("\ndistinct saturated colours: %d (want >= %d)\n", colours, min_colours);
  if (ink < min_ink) {
    std::printf("FAIL too little drawn: the chart looks blank\n");
    ok = false;
  }
  if (colours < min_colours) {
    std::printf("FAIL fewer distinct series colours than expected\n");
    ok = false;
  }
  std::printf(ok ? "PASS\n" : "FAIL\n");
  return ok ? 0 : 1;
}
