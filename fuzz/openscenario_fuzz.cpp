// openscenario_fuzz.cpp — the OpenSCENARIO import (tools/scenario
// openscenario.h) on any bytes as XML text. Contract: no crash, no hang, and a
// result is either a scenario with one camera or a non-empty error.
#include <cstddef>
#include <cstdint>
#include <string>

#include "atmo_scenario/openscenario.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const atmo::scenario::LoadResult r = atmo::scenario::parse_openscenario(text, "fuzz/scenario.xosc");
  FUZZ_CHECK(r.scenario.has_value() == r.error.empty(), "a scenario xor an error");
  if (r.scenario) FUZZ_CHECK(r.scenario->cameras.size() == 1, "one camera");
  return 0;
}
