#include "core/astro/iso8601.h"

#include <cmath>
#include <cstdio>

namespace atmo::core::astro {

bool is_leap_year(std::int64_t y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

unsigned days_in_month(std::int64_t year, unsigned month) {
  static constexpr unsigned kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  if (month < 1 || month > 12) return 0;
  return month == 2 && is_leap_year(year) ? 29u : kDays[month - 1];
}

std::int64_t days_from_civil(std::int64_t y, unsigned m, unsigned d) {
  y -= m <= 2;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const std::int64_t yoe = y - era * 400;                                    // [0, 399]
  const std::int64_t doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;  // [0, 365]
  const std::int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;            // [0, 146096]
  return era * 146097 + doe - 719468;
}

void civil_from_days(std::int64_t z, std::int64_t* year, unsigned* month, unsigned* day) {
  z += 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const std::int64_t doe = z - era * 146097;
  const std::int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const std::int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const std::int64_t mp = (5 * doy + 2) / 153;
  *day = static_cast<unsigned>(doy - (153 * mp + 2) / 5 + 1);
  *month = static_cast<unsigned>(mp < 10 ? mp + 3 : mp - 9);
  *year = yoe + era * 400 + (*month <= 2);
}

namespace {

bool digits(const std::string& s, size_t pos, size_t n, int* out) {
  if (pos + n > s.size()) return false;
  int v = 0;
  for (size_t i = pos; i < pos + n; ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    v = v * 10 + (s[i] - '0');
  }
  *out = v;
  return true;
}

std::nullopt_t fail(std::string* error, const std::string& why) {
  if (error) *error = why;
  return std::nullopt;
}

}  // namespace

std::optional<CalendarTime> parse_iso8601(const std::string& s, std::string* error) {
  static const char* const kForm = "not of the form \"YYYY-MM-DDThh:mm:ss[.fff]Z\" (or \"+hh:mm\" in place of Z)";
  const std::string quoted = "'" + s + "'";
  int year, month, day, hour, minute, second;
  if (!(digits(s, 0, 4, &year) && s.size() > 4 && s[4] == '-' && digits(s, 5, 2, &month) && s.size() > 7 &&
        s[7] == '-' && digits(s, 8, 2, &day) && s.size() > 10 && s[10] == 'T' && digits(s, 11, 2, &hour) &&
        s.size() > 13 && s[13] == ':' && digits(s, 14, 2, &minute) && s.size() > 16 && s[16] == ':' &&
        digits(s, 17, 2, &second)))
    return fail(error, quoted + " is " + kForm);
  size_t pos = 19;
  double fraction = 0.0;
  if (pos < s.size() && s[pos] == '.') {
    ++pos;
    // Integer digits then one division: correctly rounded, locale-free.
    std::int64_t numerator = 0, denominator = 1;
    const size_t first = pos;
    while (pos < s.size() && s[pos] >= '0' && s[pos] <= '9') {
      if (denominator < 1000000000000000000) {
        numerator = numerator * 10 + (s[pos] - '0');
        denominator *= 10;
      }
      ++pos;
    }
    if (pos == first) return fail(error, quoted + ": no digits after the decimal point");
    fraction = static_cast<double>(numerator) / static_cast<double>(denominator);
  }
  int offset_min = 0;
  if (pos < s.size() && s[pos] == 'Z') {
    ++pos;
  } else if (pos < s.size() && (s[pos] == '+' || s[pos] == '-')) {
    int oh, om;
    if (!(digits(s, pos + 1, 2, &oh) && pos + 3 < s.size() && s[pos + 3] == ':' && digits(s, pos + 4, 2, &om)))
      return fail(error, quoted + " is " + kForm);
    if (oh > 23 || om > 59)
      return fail(error, quoted + ": offset " + s.substr(pos, 6) + " out of range (hours 00-23, minutes 00-59)");
    offset_min = (s[pos] == '-' ? -1 : 1) * (oh * 60 + om);
    pos += 6;
  } else {
    return fail(error, quoted + ": no time zone after the seconds: add Z for UTC or an offset \"+hh:mm\"");
  }
  if (pos != s.size()) return fail(error, quoted + ": characters after the time zone");
  if (month < 1 || month > 12) return fail(error, quoted + ": month " + std::to_string(month) + " is not in 01-12");
  const unsigned dim = days_in_month(year, static_cast<unsigned>(month));
  if (day < 1 || static_cast<unsigned>(day) > dim) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "day %02d does not exist in %04d-%02d (%04d-%02d has %u days)", day, year, month,
                  year, month, dim);
    return fail(error, quoted + ": " + buf);
  }
  if (hour > 23 || minute > 59) return fail(error, quoted + ": time of day out of range (hours 00-23, minutes 00-59)");
  if (second > 60) return fail(error, quoted + ": seconds out of range (00-59, or 60 in a leap second)");

  // Remove the offset: shift the minutes, carry whole days through the
  // calendar; the seconds (possibly a leap second's 60.x) stay as written.
  const int total_min = hour * 60 + minute - offset_min;
  const int day_shift = total_min < 0 ? -1 : total_min >= 1440 ? 1 : 0;  // |offset| < 24 h
  std::int64_t y = 0;
  unsigned m = 0, d = 0;
  civil_from_days(days_from_civil(year, static_cast<unsigned>(month), static_cast<unsigned>(day)) + day_shift, &y,
                  &m, &d);
  CalendarTime t;
  t.year = static_cast<int>(y);
  t.month = static_cast<int>(m);
  t.day = static_cast<int>(d);
  t.hour = (total_min - day_shift * 1440) / 60;
  t.minute = (total_min - day_shift * 1440) % 60;
  t.second = second + fraction;
  return t;
}

std::optional<double> posix_from_calendar(const CalendarTime& t, std::string* error) {
  if (!(t.second >= 0.0 && t.second < 60.0)) {
    if (t.second >= 60.0 && t.second < 61.0)
      return fail(error, "leap second :60 has no POSIX time; use :59.999 or the next minute");
    return fail(error, "seconds out of range (00-59)");
  }
  const double whole_second = std::floor(t.second);
  const std::int64_t whole =
      days_from_civil(t.year, static_cast<unsigned>(t.month), static_cast<unsigned>(t.day)) * 86400 +
      t.hour * 3600 + t.minute * 60 + static_cast<std::int64_t>(whole_second);
  return static_cast<double>(whole) + (t.second - whole_second);
}

std::optional<double> parse_iso8601_posix(const std::string& text, std::string* error) {
  const auto calendar = parse_iso8601(text, error);
  if (!calendar) return std::nullopt;
  return posix_from_calendar(*calendar, error);
}

std::string format_iso8601_posix(double posix_s) {
  // Round to milliseconds first so 59.9996 carries into the next minute.
  const double ms_total = std::round(posix_s * 1000.0);
  std::int64_t ms = static_cast<std::int64_t>(ms_total);
  std::int64_t secs = ms >= 0 ? ms / 1000 : -((-ms + 999) / 1000);
  ms -= secs * 1000;
  std::int64_t days = secs >= 0 ? secs / 86400 : -((-secs + 86399) / 86400);
  const std::int64_t sod = secs - days * 86400;
  std::int64_t y;
  unsigned m, d;
  civil_from_days(days, &y, &m, &d);
  char buf[64];
  const int h = static_cast<int>(sod / 3600), mi = static_cast<int>(sod / 60 % 60),
            s = static_cast<int>(sod % 60);
  if (ms != 0) {
    std::snprintf(buf, sizeof buf, "%04lld-%02u-%02uT%02d:%02d:%02d.%03dZ",
                  static_cast<long long>(y), m, d, h, mi, s, static_cast<int>(ms));
  } else {
    std::snprintf(buf, sizeof buf, "%04lld-%02u-%02uT%02d:%02d:%02dZ", static_cast<long long>(y),
                  m, d, h, mi, s);
  }
  return buf;
}

CalendarTime calendar_from_posix(double posix_s) {
  const double days = std::floor(posix_s / 86400.0);
  double sod = posix_s - days * 86400.0;
  if (sod < 0.0) sod = 0.0;
  if (sod >= 86400.0) sod = std::nextafter(86400.0, 0.0);
  std::int64_t y = 0;
  unsigned m = 0, d = 0;
  civil_from_days(static_cast<std::int64_t>(days), &y, &m, &d);
  CalendarTime t;
  t.year = static_cast<int>(y);
  t.month = static_cast<int>(m);
  t.day = static_cast<int>(d);
  t.hour = static_cast<int>(sod / 3600.0);
  t.minute = static_cast<int>((sod - t.hour * 3600.0) / 60.0);
  t.second = sod - t.hour * 3600.0 - t.minute * 60.0;
  return t;
}

}  // namespace atmo::core::astro
