// ISO 8601 / RFC 3339 time stamps <-> POSIX seconds, without timegm (which
// depends on the C library and the TZ environment), through the plugin's
// parser and calendar (core/astro/iso8601.h).
#include "atmo_scenario/scenario.h"

#include "core/astro/iso8601.h"

namespace atmo::scenario {

// The one parser and calendar: core/astro/iso8601.h.
std::optional<double> parse_iso8601_utc(const std::string& s, std::string* error) {
  return core::astro::parse_iso8601_posix(s, error);
}

std::string format_iso8601_utc(double posix_s) { return core::astro::format_iso8601_posix(posix_s); }

}  // namespace atmo::scenario
