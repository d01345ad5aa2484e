// scenario_fuzz.cpp — the scenario loader (tools/scenario) on any bytes as
// JSON text, and its ISO 8601 parser on the same bytes. Contract: no crash,
// a result is either a scenario or a non-empty error, and a time the parser
// read is written back as text that it reads again.
#include <cstddef>
#include <cstdint>
#include <string>

#include "atmo_scenario/scenario.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const atmo::scenario::LoadResult r = atmo::scenario::parse_scenario(text, "fuzz/scenario.json");
  FUZZ_CHECK(r.scenario.has_value() == r.error.empty(), "a scenario xor an error");
  if (r.scenario) {
    for (const atmo::scenario::CloudLayer& layer : r.scenario->clouds)
      (void)atmo::scenario::cloud_layer_area_m(*r.scenario, layer);
  }
  std::string error;
  const std::optional<double> t = atmo::scenario::parse_iso8601_utc(text, &error);
  FUZZ_CHECK(t.has_value() == error.empty(), "a time xor an error");
  if (t) {  // what the formatter writes, the parser reads
    const std::string again = atmo::scenario::format_iso8601_utc(*t);
    FUZZ_CHECK(atmo::scenario::parse_iso8601_utc(again, &error).has_value(), again.c_str());
  }
  return 0;
}
