// iso8601.h — UTC time stamps (ISO 8601 / RFC 3339) and the proleptic
// Gregorian calendar: the ONE parser of the plugin (time_scales), the
// scenario loader (tools/scenario) and the sample host. Pure C++, no library.
//
// The form: "YYYY-MM-DDThh:mm:ss[.f...]Z", or "+hh:mm" / "-hh:mm" in place of
// Z (the offset is removed: the result is UTC). Upper-case T and Z, as the
// scenario schema's pattern (config/scenario.schema.json); years
// 0000-9999; a leap second (ss = 60) is accepted as a calendar time (the
// ephemeris checks it against the leap-second table) but has no POSIX time.
// Fractions of any length are read exactly (integer digits, one division).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace atmo::core::astro {

// A UTC instant on the proleptic Gregorian calendar. second may be in
// [60, 61) inside a leap second (23:59:60).
struct CalendarTime {
  int year = 2000;
  int month = 1;
  int day = 1;
  int hour = 0;
  int minute = 0;
  double second = 0.0;
};

// On failure returns nullopt and, if error is not null, says why (quoting the text).
std::optional<CalendarTime> parse_iso8601(const std::string& text, std::string* error);

// POSIX seconds (days of exactly 86 400 s) of a calendar time; a leap second
// (second >= 60) has none: nullopt, and error says so.
std::optional<double> posix_from_calendar(const CalendarTime& time, std::string* error);
// Back: POSIX seconds (never a leap second) to UTC.
CalendarTime calendar_from_posix(double posix_s);
// parse_iso8601, then posix_from_calendar.
std::optional<double> parse_iso8601_posix(const std::string& text, std::string* error);
// POSIX seconds as "YYYY-MM-DDThh:mm:ss[.fff]Z" (milliseconds only when non-zero).
std::string format_iso8601_posix(double posix_s);

// The calendar (H. Hinnant's algorithms: eras of 400 years, years starting in
// March). Days since 1970-01-01, and back; any year.
bool is_leap_year(std::int64_t year);
unsigned days_in_month(std::int64_t year, unsigned month);  // 0 for a month outside 1-12
std::int64_t days_from_civil(std::int64_t year, unsigned month, unsigned day);
void civil_from_days(std::int64_t days, std::int64_t* year, unsigned* month, unsigned* day);

}  // namespace atmo::core::astro
