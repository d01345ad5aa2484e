#include "core/astro/time_scales.h"

#include <erfa.h>
#include <erfam.h>

#include <cmath>
#include <cstdio>

namespace atmo::core::astro {

namespace {

constexpr double kJdUtcStart = 2436934.5;        // 1960-01-01T00:00:00: UTC begins
constexpr double kMaxAbsDeltaTS = 1.0e5;         // a sanity bound on a user Delta T

bool fail(std::string* error, const std::string& why) {
  if (error) *error = why;
  return false;
}

// Difference a - b of two Julian dates in seconds, part by part.
double seconds_between(JulianDate a, JulianDate b) {
  return ((a.jd1 - b.jd1) + (a.jd2 - b.jd2)) * ERFA_DAYSEC;
}

JulianDate add_seconds(JulianDate jd, double seconds) { return {jd.jd1, jd.jd2 + seconds / ERFA_DAYSEC}; }

int calendar_year(JulianDate jd) {
  int y = 0, m = 0, d = 0;
  double fd = 0.0;
  if (eraJd2cal(jd.jd1, jd.jd2, &y, &m, &d, &fd) != 0) return jd.value() < 2451545.0 ? -4713 : 100000;
  return y;
}

bool validate_options(const TimeScaleOptions& options, std::string* error) {
  if (!std::isfinite(options.dut1_s) || std::fabs(options.dut1_s) > kMaxAbsDut1S) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "DUT1 = UT1 - UTC must be a number in [-0.9, 0.9] s, got %g", options.dut1_s);
    return fail(error, buf);
  }
  if (options.delta_t_s &&
      (!std::isfinite(*options.delta_t_s) || std::fabs(*options.delta_t_s) > kMaxAbsDeltaTS)) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "Delta T = TT - UT1 must be a finite number of seconds (|Delta T| <= 1e5), got %g",
                  *options.delta_t_s);
    return fail(error, buf);
  }
  return true;
}

// The validated range is in civil (UT) years: 1900-01-01T00:00Z is inside
// although its TT falls 2.7 s before 1900.
void flag_range(TimeScales* t) {
  const int year = calendar_year(t->ut1);
  t->in_validated_range = year >= kFirstValidatedYear && year <= kLastValidatedYear;
  if (!t->in_validated_range) {
    if (!t->note.empty()) t->note += "; ";
    t->note += "year " + std::to_string(year) + " is outside the validated 1900-2100: accuracy degrades";
  }
}

// TT and TAI from UT1 and Delta T.
void tt_from_ut1(TimeScales* t) {
  t->tt = add_seconds(t->ut1, t->delta_t_s);
  t->tai = add_seconds(t->tt, -ERFA_TTMTAI);
}

}  // namespace

const char* to_string(DeltaTSource source) {
  switch (source) {
    case DeltaTSource::kLeapSeconds: return "leap-second table + DUT1";
    case DeltaTSource::kLeapSecondsExtrapolated: return "leap-second table held at its last value + DUT1";
    case DeltaTSource::kEspenakMeeus2006: return "Espenak & Meeus 2006 model: no UTC before 1960";
    case DeltaTSource::kUser: return "user-supplied";
  }
  return "?";
}

double decimal_year(JulianDate jd) { return 2000.0 + ((jd.jd1 - 2451545.0) + jd.jd2) / 365.25; }

double delta_t_espenak_meeus_s(double y) {
  // F. Espenak and J. Meeus, "Five Millennium Canon of Solar Eclipses:
  // -1999 to +3000" (NASA/TP-2006-214141), section 2.6.
  double t, u;
  if (y < -500.0) {
    u = (y - 1820.0) / 100.0;
    return -20.0 + 32.0 * u * u;
  }
  if (y < 500.0) {
    u = y / 100.0;
    return 10583.6 + u * (-1014.41 + u * (33.78311 + u * (-5.952053 + u * (-0.1798452 + u * (0.022174192 +
                                                                                               u * 0.0090316521)))));
  }
  if (y < 1600.0) {
    u = (y - 1000.0) / 100.0;
    return 1574.2 + u * (-556.01 + u * (71.23472 + u * (0.319781 + u * (-0.8503463 + u * (-0.005050998 +
                                                                                         u * 0.0083572073)))));
  }
  if (y < 1700.0) {
    t = y - 1600.0;
    return 120.0 + t * (-0.9808 + t * (-0.01532 + t / 7129.0));
  }
  if (y < 1800.0) {
    t = y - 1700.0;
    return 8.83 + t * (0.1603 + t * (-0.0059285 + t * (0.00013336 - t / 1174000.0)));
  }
  if (y < 1860.0) {
    t = y - 1800.0;
    return 13.72 + t * (-0.332447 + t * (0.0068612 + t * (0.0041116 + t * (-0.00037436 + t * (0.0000121272 +
                                                                                             t * (-0.0000001699 +
                                                                                                  t * 0.000000000875))))));
  }
  if (y < 1900.0) {
    t = y - 1860.0;
    return 7.62 + t * (0.5737 + t * (-0.251754 + t * (0.01680668 + t * (-0.0004473624 + t / 233174.0))));
  }
  if (y < 1920.0) {
    t = y - 1900.0;
    return -2.79 + t * (1.494119 + t * (-0.0598939 + t * (0.0061966 - t * 0.000197)));
  }
  if (y < 1941.0) {
    t = y - 1920.0;
    return 21.20 + t * (0.84493 + t * (-0.076100 + t * 0.0020936));
  }
  if (y < 1961.0) {
    t = y - 1950.0;
    return 29.07 + t * (0.407 + t * (-1.0 / 233.0 + t / 2547.0));
  }
  if (y < 1986.0) {
    t = y - 1975.0;
    return 45.45 + t * (1.067 + t * (-1.0 / 260.0 - t / 718.0));
  }
  if (y < 2005.0) {
    t = y - 2000.0;
    return 63.86 + t * (0.3345 + t * (-0.060374 + t * (0.0017275 + t * (0.000651814 + t * 0.00002373599))));
  }
  if (y < 2050.0) {
    t = y - 2000.0;
    return 62.92 + t * (0.32217 + t * 0.005589);
  }
  u = (y - 1820.0) / 100.0;
  if (y < 2150.0) return -20.0 + 32.0 * u * u - 0.5628 * (2150.0 - y);
  return -20.0 + 32.0 * u * u;
}

std::string format_julian_date(JulianDate jd, bool utc) {
  int y = 0, m = 0, d = 0, hmsf[4] = {0, 0, 0, 0};
  if (eraD2dtf(utc ? "UTC" : "TT", 3, jd.jd1, jd.jd2, &y, &m, &d, hmsf) < 0) return "(out of range)";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d.%03d", y, m, d, hmsf[0], hmsf[1], hmsf[2], hmsf[3]);
  return buf;
}

std::optional<TimeScales> time_scales_from_utc(const CalendarTime& c, const TimeScaleOptions& options,
                                               std::string* error) {
  if (!validate_options(options, error)) return std::nullopt;
  if (!std::isfinite(c.second) || c.second < 0.0 || c.second >= 61.0 || c.hour < 0 || c.hour > 23 || c.minute < 0 ||
      c.minute > 59 || c.year < 1 || c.year > 9999) {
    fail(error, "UTC time out of range (years 0001-9999, hh 00-23, mm 00-59, ss 0-60.999)");
    return std::nullopt;
  }
  TimeScales t;
  t.dut1_s = options.dut1_s;
  const int status = eraDtf2d("UTC", c.year, c.month, c.day, c.hour, c.minute, c.second, &t.utc.jd1, &t.utc.jd2);
  if (status < 0) {
    fail(error, "invalid UTC calendar date");
    return std::nullopt;
  }
  if (status >= 2) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%04d-%02d-%02d %02d:%02d:%06.3f is after the end of the day: no leap second then",
                  c.year, c.month, c.day, c.hour, c.minute, c.second);
    fail(error, buf);
    return std::nullopt;
  }

  const bool before_utc = t.utc.value() < kJdUtcStart;
  t.utc_defined = !before_utc;
  double dat = 0.0;
  const double fd = (c.hour * 60.0 + c.minute) / 1440.0;
  const int dat_status = before_utc ? 1 : eraDat(c.year, c.month, c.day, fd, &dat);

  if (before_utc) {
    t.ut1 = add_seconds(t.utc, options.dut1_s);
    t.tai_minus_utc_s = 0.0;
    if (options.delta_t_s) {
      t.delta_t_source = DeltaTSource::kUser;
      t.delta_t_s = *options.delta_t_s;
    } else {
      t.delta_t_source = DeltaTSource::kEspenakMeeus2006;
      t.delta_t_s = delta_t_espenak_meeus_s(decimal_year(t.ut1));
    }
    t.note = "before 1960 there is no UTC: the time was read as UT (UT1 = given + DUT1)";
    tt_from_ut1(&t);
  } else if (options.delta_t_s) {
    eraUtcut1(t.utc.jd1, t.utc.jd2, options.dut1_s, &t.ut1.jd1, &t.ut1.jd2);
    t.delta_t_source = DeltaTSource::kUser;
    t.delta_t_s = *options.delta_t_s;
    tt_from_ut1(&t);
    t.tai_minus_utc_s = seconds_between(t.tai, t.utc);
  } else {
    eraUtctai(t.utc.jd1, t.utc.jd2, &t.tai.jd1, &t.tai.jd2);
    eraTaitt(t.tai.jd1, t.tai.jd2, &t.tt.jd1, &t.tt.jd2);
    eraUtcut1(t.utc.jd1, t.utc.jd2, options.dut1_s, &t.ut1.jd1, &t.ut1.jd2);
    t.tai_minus_utc_s = dat;
    t.delta_t_s = seconds_between(t.tt, t.ut1);
    if (dat_status == 1) {
      t.delta_t_source = DeltaTSource::kLeapSecondsExtrapolated;
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "beyond ERFA's leap-second table: TAI - UTC held at %.0f s (no further leap seconds assumed)", dat);
      t.note = buf;
    } else {
      t.delta_t_source = DeltaTSource::kLeapSeconds;
    }
  }
  flag_range(&t);
  return t;
}

std::optional<TimeScales> time_scales_from_posix(double posix_s, const TimeScaleOptions& options,
                                                 std::string* error) {
  if (!std::isfinite(posix_s) || posix_s < kMinPosixUtcS || posix_s > kMaxPosixUtcS) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "POSIX UTC time %g s is not a finite time in the years 0001-9999", posix_s);
    fail(error, buf);
    return std::nullopt;
  }
  return time_scales_from_utc(calendar_from_posix(posix_s), options, error);
}

std::optional<TimeScales> time_scales_from_tt(JulianDate tt, const TimeScaleOptions& options, std::string* error) {
  if (!validate_options(options, error)) return std::nullopt;
  if (!std::isfinite(tt.jd1) || !std::isfinite(tt.jd2) || tt.value() < 1721425.5 || tt.value() >= 5373484.5) {
    fail(error, "TT Julian date is not finite or outside the years 0001-9999");
    return std::nullopt;
  }
  TimeScales t;
  t.tt = tt;
  t.tai = add_seconds(tt, -ERFA_TTMTAI);
  t.dut1_s = options.dut1_s;
  const bool before_utc = tt.value() < kJdUtcStart;
  t.utc_defined = !before_utc;
  if (before_utc) {
    if (options.delta_t_s) {
      t.delta_t_source = DeltaTSource::kUser;
      t.delta_t_s = *options.delta_t_s;
    } else {
      t.delta_t_source = DeltaTSource::kEspenakMeeus2006;
      t.delta_t_s = delta_t_espenak_meeus_s(decimal_year(tt));
    }
    t.ut1 = add_seconds(tt, -t.delta_t_s);
    t.utc = add_seconds(t.ut1, -options.dut1_s);
    t.tai_minus_utc_s = 0.0;
    t.note = "before 1960 there is no UTC: 'UTC' is UT (UT1 - DUT1)";
  } else {
    const int status = eraTaiutc(t.tai.jd1, t.tai.jd2, &t.utc.jd1, &t.utc.jd2);
    if (status < 0) {
      fail(error, "TT outside the range of the leap-second table");
      return std::nullopt;
    }
    t.tai_minus_utc_s = seconds_between(t.tai, t.utc);
    if (options.delta_t_s) {
      t.delta_t_source = DeltaTSource::kUser;
      t.delta_t_s = *options.delta_t_s;
      t.ut1 = add_seconds(tt, -t.delta_t_s);
      t.dut1_s = seconds_between(t.ut1, t.utc);
    } else {
      eraUtcut1(t.utc.jd1, t.utc.jd2, options.dut1_s, &t.ut1.jd1, &t.ut1.jd2);
      t.delta_t_s = seconds_between(t.tt, t.ut1);
      t.delta_t_source = status == 1 ? DeltaTSource::kLeapSecondsExtrapolated : DeltaTSource::kLeapSeconds;
      if (status == 1) t.note = "beyond ERFA's leap-second table: TAI - UTC held (no further leap seconds assumed)";
    }
  }
  flag_range(&t);
  return t;
}

}  // namespace atmo::core::astro
