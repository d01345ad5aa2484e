// ISO 8601 / RFC 3339 time stamps <-> POSIX seconds, without timegm (which
// depends on the C library and the TZ environment).
#include "atmo_scenario/scenario.h"

#include <cmath>
#include <cstdio>

namespace atmo::scenario {

bool is_leap_year(std::int64_t y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

unsigned days_in_month(std::int64_t year, unsigned month) {
  static constexpr unsigned kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  if (month < 1 || month > 12) return 0;
  return month == 2 && is_leap_year(year) ? 29u : kDays[month - 1];
}

// H. Hinnant's algorithm: eras of 400 years (146 097 days), years starting in
// March so the leap day is the last day of the year.
std::int64_t days_from_civil(std::int64_t y, unsigned m, unsigned d) {
  y -= m <= 2;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const std::int64_t yoe = y - era * 400;                            // [0, 399]
  const std::int64_t doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;  // [0, 365]
  const std::int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;    // [0, 146096]
  return era * 146097 + doe - 719468;
}

void civil_from_days(std::int64_t z, std::int64_t* year, unsigned* month, unsigned* day) {
  z += 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const std::int64_t doe = z - era * 146097;
  const std::int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const std::int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const std::int64_t mp = (5 * doy + 2) / 153;
  const unsigned d = static_cast<unsigned>(doy - (153 * mp + 2) / 5 + 1);
  const unsigned m = static_cast<unsigned>(mp < 10 ? mp + 3 : mp - 9);
  *year = yoe + era * 400 + (m <= 2);
  *month = m;
  *day = d;
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

bool fail(std::string* error, const std::string& why) {
  if (error) *error = why;
  return false;
}

}  // namespace

std::optional<double> parse_iso8601_utc(const std::string& s, std::string* error) {
  // Messages that start with kForm are about the shape; the others say more.
  static const char* const kForm =
      "not of the form \"YYYY-MM-DDThh:mm:ss[.fff]Z\" (or \"+hh:mm\" in place of Z)";
  int year, month, day, hour, minute, second;
  if (!(digits(s, 0, 4, &year) && s.size() > 4 && s[4] == '-' && digits(s, 5, 2, &month) &&
        s.size() > 7 && s[7] == '-' && digits(s, 8, 2, &day) && s.size() > 10 && s[10] == 'T' &&
        digits(s, 11, 2, &hour) && s.size() > 13 && s[13] == ':' && digits(s, 14, 2, &minute) &&
        s.size() > 16 && s[16] == ':' && digits(s, 17, 2, &second))) {
    fail(error, kForm);
    return std::nullopt;
  }
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
    fraction = static_cast<double>(numerator) / static_cast<double>(denominator);
    if (pos == first) {
      fail(error, "no digits after '.'");
      return std::nullopt;
    }
  }
  int offset_s = 0;
  if (pos < s.size() && s[pos] == 'Z') {
    ++pos;
  } else if (pos < s.size() && (s[pos] == '+' || s[pos] == '-')) {
    int oh, om;
    if (!(digits(s, pos + 1, 2, &oh) && pos + 3 < s.size() && s[pos + 3] == ':' &&
          digits(s, pos + 4, 2, &om))) {
      fail(error, kForm);
      return std::nullopt;
    }
    if (oh > 23 || om > 59) {
      fail(error, "offset " + s.substr(pos, 6) + " out of range (hours 00-23, minutes 00-59)");
      return std::nullopt;
    }
    offset_s = (s[pos] == '-' ? -1 : 1) * (oh * 3600 + om * 60);
    pos += 6;
  } else {
    fail(error, "no time zone after the seconds: add Z for UTC or an offset \"+hh:mm\"");
    return std::nullopt;
  }
  if (pos != s.size()) {
    fail(error, "characters after the time zone");
    return std::nullopt;
  }

  if (month < 1 || month > 12) {
    fail(error, "month " + std::to_string(month) + " is not in 01-12");
    return std::nullopt;
  }
  const unsigned dim = days_in_month(year, static_cast<unsigned>(month));
  if (day < 1 || static_cast<unsigned>(day) > dim) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "day %02d does not exist: %04d-%02d has %u days", day, year,
                  month, dim);
    fail(error, buf);
    return std::nullopt;
  }
  if (hour > 23 || minute > 59) {
    fail(error, "time of day out of range (hours 00-23, minutes 00-59)");
    return std::nullopt;
  }
  if (second > 59) {
    fail(error, second == 60 ? "leap second :60 has no POSIX time; use :59.999 or the next minute"
                             : "seconds out of range (00-59)");
    return std::nullopt;
  }

  const std::int64_t days = days_from_civil(year, static_cast<unsigned>(month),
                                            static_cast<unsigned>(day));
  const std::int64_t whole = days * 86400 + hour * 3600 + minute * 60 + second - offset_s;
  return static_cast<double>(whole) + fraction;
}

std::string format_iso8601_utc(double posix_s) {
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

}  // namespace atmo::scenario
