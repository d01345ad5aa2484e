// Checks two frames of atmo-vtk-host, one with the plugin and one with
// --no-atmo (same size, same camera):
//  (a) the image: the sky above the horizon is not black and blue-ish; far
//      terrain (just below the horizon) is nearer in colour to the horizon sky
//      than near terrain (the bottom rows) is, by at least a factor of 2;
//  (b) VTK's own rendering after the plugin's passes is unchanged: the overlay
//      renderer's box (layer 1, drawn after the main renderer's passes) is
//      bit-identical in both frames, and it is not blank.
// The --no-atmo frame tells sky from geometry: VTK's background there is exactly black.
//
// usage: vtk_host_image_check ATMO_DIR NO_ATMO_DIR FRAME_PNG_NAME
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "atmo_support/image.h"

namespace {

using atmo::support::Image;

struct Rgb {
  double r = 0, g = 0, b = 0;
  int n = 0;
  void add(const float* p) {
    r += p[0];
    g += p[1];
    b += p[2];
    ++n;
  }
  Rgb mean() const { return n ? Rgb{r / n, g / n, b / n, n} : Rgb{}; }
};

double distance(const Rgb& a, const Rgb& b) {
  return std::sqrt((a.r - b.r) * (a.r - b.r) + (a.g - b.g) * (a.g - b.g) + (a.b - b.b) * (a.b - b.b));
}

void print(const char* name, const Rgb& c) {
  std::printf("  %-30s (%.3f, %.3f, %.3f) over %d pixels\n", name, c.r, c.g, c.b, c.n);
}

bool load(const std::string& dir, const std::string& name, Image* image, int box[4]) {
  std::string error;
  if (!atmo::support::read_png(dir + "/" + name, image, &error)) {
    std::fprintf(stderr, "vtk_host_image_check: %s\n", error.c_str());
    return false;
  }
  std::ifstream in(dir + "/overlay.txt");
  if (!(in >> box[0] >> box[1] >> box[2] >> box[3])) {
    std::fprintf(stderr, "vtk_host_image_check: %s/overlay.txt: expected 'x0 y0 x1 y1'\n", dir.c_str());
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: vtk_host_image_check ATMO_DIR NO_ATMO_DIR FRAME_PNG_NAME\n");
    return 2;
  }
  Image atmo, plain;
  int box[4], plain_box[4];
  if (!load(argv[1], argv[3], &atmo, box) || !load(argv[2], argv[3], &plain, plain_box)) return 1;
  if (atmo.width != plain.width || atmo.height != plain.height) {
    std::fprintf(stderr, "vtk_host_image_check: sizes differ: %dx%d and %dx%d\n", atmo.width, atmo.height,
                 plain.width, plain.height);
    return 1;
  }
  const int w = atmo.width, h = atmo.height;
  int failures = 0;
  const auto fail = [&](const char* what) {
    std::printf("FAIL: %s\n", what);
    ++failures;
  };
  const auto in_box = [&](int x, int y) { return x >= box[0] && x < box[2] && y >= box[1] && y < box[3]; };
  const auto is_sky = [&](int x, int y) {
    const float* p = plain.pixel(x, y);
    return !in_box(x, y) && p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f;
  };

  // (b) The overlay box, both frames.
  std::printf("(b) overlay box x [%d, %d), y [%d, %d) from the top:\n", box[0], box[2], box[1], box[3]);
  if (box[0] != plain_box[0] || box[1] != plain_box[1] || box[2] != plain_box[2] || box[3] != plain_box[3])
    fail("the overlay boxes of the two runs differ");
  long compared = 0, differing = 0, outside_differing = 0, outside = 0;
  std::set<unsigned> colours;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float *a = atmo.pixel(x, y), *p = plain.pixel(x, y);
      const bool same = a[0] == p[0] && a[1] == p[1] && a[2] == p[2];
      if (in_box(x, y)) {
        ++compared;
        differing += !same;
        colours.insert(unsigned(a[0] * 255.0f + 0.5f) << 16 | unsigned(a[1] * 255.0f + 0.5f) << 8 |
                       unsigned(a[2] * 255.0f + 0.5f));
      } else {
        ++outside;
        outside_differing += !same;
      }
    }
  }
  std::printf("  %ld pixels compared, %ld differ; %zu distinct colours in the box\n", compared, differing,
              colours.size());
  std::printf("  outside the box %ld of %ld pixels differ (the plugin's sky and haze)\n", outside_differing, outside);
  if (compared < 100) fail("the overlay box is too small to compare");
  if (differing) fail("the overlay differs with and without the plugin's passes");
  if (colours.size() < 20) fail("the overlay box is (nearly) blank: nothing of VTK's was compared");
  if (outside_differing < outside / 2) fail("the plugin changed less than half of the frame outside the overlay");

  // (a) The image.
  Rgb sky_top, horizon_sky, far_terrain, near_terrain, far_plain, near_plain;
  for (int y = 0; y < h / 4; ++y)
    for (int x = 0; x < w; ++x)
      if (is_sky(x, y)) sky_top.add(atmo.pixel(x, y));
  // The horizon of each column: its first non-sky row; columns where something
  // stands above the terrain's horizon (masts, the isosurface) are left out.
  std::vector<int> first(w, -1);
  for (int x = 0; x < w; ++x)
    for (int y = 0; y < h && first[x] < 0; ++y)
      if (!is_sky(x, y) && !in_box(x, y)) first[x] = y;
  std::vector<int> sorted;
  for (int f : first)
    if (f > 0) sorted.push_back(f);
  std::sort(sorted.begin(), sorted.end());
  const int horizon = sorted.empty() ? -1 : sorted[sorted.size() * 3 / 4];  // most columns: terrain
  int columns = 0;
  for (int x = 0; x < w; ++x) {
    if (first[x] < 4 || std::abs(first[x] - horizon) > 3) continue;
    bool clean = true;
    for (int y = first[x] - 3; y < first[x] + 4 && clean; ++y) clean = y < h && (y < first[x]) == is_sky(x, y);
    if (!clean) continue;
    ++columns;
    for (int y = first[x] - 3; y < first[x]; ++y) horizon_sky.add(atmo.pixel(x, y));
    for (int y = first[x] + 1; y < first[x] + 4; ++y) {
      far_terrain.add(atmo.pixel(x, y));
      far_plain.add(plain.pixel(x, y));
    }
  }
  for (int y = h - std::max(2, h / 10); y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (!is_sky(x, y) && !in_box(x, y)) {
        near_terrain.add(atmo.pixel(x, y));
        near_plain.add(plain.pixel(x, y));
      }
  sky_top = sky_top.mean();
  horizon_sky = horizon_sky.mean();
  far_terrain = far_terrain.mean();
  near_terrain = near_terrain.mean();
  far_plain = far_plain.mean();
  near_plain = near_plain.mean();
  std::printf("(a) %dx%d, horizon near row %d, %d clean horizon columns; display RGB in [0, 1]:\n", w, h, horizon,
              columns);
  print("sky, top quarter", sky_top);
  print("sky, 3 rows above the horizon", horizon_sky);
  print("far terrain, 3 rows below it", far_terrain);
  print("near terrain, bottom rows", near_terrain);
  print("far terrain, --no-atmo", far_plain);
  print("near terrain, --no-atmo", near_plain);
  const double d_far = distance(far_terrain, horizon_sky), d_near = distance(near_terrain, horizon_sky);
  const double d_far_plain = distance(far_plain, horizon_sky), d_near_plain = distance(near_plain, horizon_sky);
  std::printf("  distance to the horizon sky's colour: far terrain %.3f, near terrain %.3f (ratio %.2f); "
              "--no-atmo: far %.3f, near %.3f\n",
              d_far, d_near, d_near > 0 ? d_far / d_near : 0.0, d_far_plain, d_near_plain);
  const double sky_luma = 0.2126 * sky_top.r + 0.7152 * sky_top.g + 0.0722 * sky_top.b;
  if (sky_top.n < w) fail("too few sky pixels in the top quarter");
  if (sky_luma < 0.15) fail("the sky above the horizon is (nearly) black");
  if (!(sky_top.b > sky_top.r + 0.05 && sky_top.b >= sky_top.g)) fail("the sky above the horizon is not blue-ish");
  if (columns < w / 4) fail("too few columns with a clean terrain horizon");
  if (near_terrain.n < w) fail("too few near-terrain pixels");
  if (!(d_far < 0.5 * d_near)) fail("far terrain is not nearer the horizon sky's colour than near terrain (x0.5)");
  if (!(d_far < 0.6 * d_far_plain)) fail("the haze did not move far terrain towards the horizon sky (x0.6)");
  std::printf("%s\n", failures ? "vtk_host_image_check: FAILED" : "vtk_host_image_check: passed");
  return failures ? 1 : 0;
}
