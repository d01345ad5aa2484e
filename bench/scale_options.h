// scale_options.h — the options the scale benches share: --frames N (timed
// frames a case), --only SUBSTRING (the cases whose name holds it), --csv FILE.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <string>

namespace bench_scale {

struct CommonOptions {
  int frames = 5;
  std::string only, csv_path;

  // Takes argv[*i] (and its value argv[*i + 1], "" past the end) when it is
  // one of these options; advances *i past the value. False: not ours.
  bool take(int argc, char** argv, int* i) {
    const std::string a = argv[*i];
    const char* v = *i + 1 < argc ? argv[*i + 1] : "";
    if (a == "--frames") {
      frames = std::max(1, std::atoi(v));
    } else if (a == "--only") {
      only = v;
    } else if (a == "--csv") {
      csv_path = v;
    } else {
      return false;
    }
    ++*i;
    return true;
  }

  bool skips(const std::string& case_name) const {
    return !only.empty() && case_name.find(only) == std::string::npos;
  }
};

}  // namespace bench_scale
