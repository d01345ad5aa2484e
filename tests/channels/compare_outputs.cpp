// channels_compare DIR_A DIR_B [--max-levels L]: the channel images two runs of atmo-channels wrote
// (channel<i>_frame<k>.exr, linear float) and their panoramas (panorama_frame<k>.png), file by file.
// Without --max-levels every float must be bitwise equal and every PNG byte too; with it, the 8-bit display
// levels (the runs' PNGs) may differ by at most L and the linear EXRs by 1e-3 relative (floor 1e-3 cd/m^2). Fails on a file missing on either side, and
// when there is nothing to compare.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>

#include "atmo_support/image.h"

namespace fs = std::filesystem;
namespace su = atmo::support;

namespace {

std::set<std::string> outputs(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    const bool channel = name.rfind("channel", 0) == 0 && (e.path().extension() == ".exr" || e.path().extension() == ".png");
    const bool panorama = name.rfind("panorama_", 0) == 0 && e.path().extension() == ".png";
    if (channel || panorama) out.insert(name);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && !(argc == 5 && std::strcmp(argv[3], "--max-levels") == 0)) {
    std::fprintf(stderr, "usage: channels_compare DIR_A DIR_B [--max-levels L]\n");
    return 2;
  }
  const fs::path a = argv[1], b = argv[2];
  const int max_levels = argc == 5 ? std::atoi(argv[4]) : -1;  // -1: bitwise
  const std::set<std::string> in_a = outputs(a), in_b = outputs(b);
  int failures = 0, compared = 0;
  for (const std::string& n : in_a)
    if (!in_b.count(n)) std::printf("FAIL %s: in %s only\n", n.c_str(), a.c_str()), ++failures;
  for (const std::string& n : in_b)
    if (!in_a.count(n)) std::printf("FAIL %s: in %s only\n", n.c_str(), b.c_str()), ++failures;
  for (const std::string& n : in_a) {
    if (!in_b.count(n)) continue;
    su::Image ia, ib;
    std::string error;
    const bool exr = fs::path(n).extension() == ".exr";
    const bool read = exr ? su::read_exr((a / n).string(), &ia, &error) && su::read_exr((b / n).string(), &ib, &error)
                          : su::read_png((a / n).string(), &ia, &error) && su::read_png((b / n).string(), &ib, &error);
    if (!read || ia.width != ib.width || ia.height != ib.height) {
      std::printf("FAIL %s: %s\n", n.c_str(), read ? "sizes differ" : error.c_str());
      ++failures;
      continue;
    }
    ++compared;
    long differing = 0;
    double max_rel = 0.0;
    int levels = 0;
    for (size_t i = 0; i < ia.rgba.size(); ++i) {
      if (std::memcmp(&ia.rgba[i], &ib.rgba[i], sizeof(float)) != 0) ++differing;
      const double x = ia.rgba[i], y = ib.rgba[i];
      max_rel = std::max(max_rel, std::fabs(x - y) / std::max({std::fabs(x), std::fabs(y), 1e-3}));
      if (!exr) levels = std::max(levels, static_cast<int>(std::lround(std::fabs(x - y) * 255.0)));
    }
    const bool ok = max_levels < 0 ? differing == 0 : (exr ? max_rel <= 1e-3 : levels <= max_levels);
    if (!ok) ++failures;
    std::printf("%s %s: %ld of %zu values differ, max relative %.3g%s\n", ok ? "ok  " : "FAIL", n.c_str(), differing,
                ia.rgba.size(), max_rel, exr ? "" : (", max " + std::to_string(levels) + " levels").c_str());
  }
  if (compared == 0) {
    std::printf("FAIL: no channel images or panoramas in both %s and %s\n", a.c_str(), b.c_str());
    return 1;
  }
  std::printf("%s: %d files compared (%s), %d failed\n", failures == 0 ? "PASS" : "FAIL", compared,
              max_levels < 0 ? "bitwise" : ("8-bit PNGs within " + std::to_string(max_levels) + " levels").c_str(),
              failures);
  return failures == 0 ? 0 : 1;
}
