// fuzz_check.h — the one assertion the fuzz targets use: a broken contract
// (not only a crash) is a finding, so it aborts with the reason and libFuzzer
// keeps the input.
#pragma once

#include <cstdio>
#include <cstdlib>

#define FUZZ_CHECK(condition, what)                                                   \
  do {                                                                                \
    if (!(condition)) {                                                               \
      std::fprintf(stderr, "fuzz check failed at %s:%d: %s (%s)\n", __FILE__, __LINE__, \
                   what, #condition);                                                 \
      std::abort();                                                                   \
    }                                                                                 \
  } while (0)
