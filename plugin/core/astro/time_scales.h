// time_scales.h — civil time (UTC) to the astronomical time scales: TAI, TT
// and UT1, as two-part Julian dates (ERFA convention: jd1 + jd2, days).
//
//   UTC --leap seconds (eraUtctai)--> TAI --+32.184 s (eraTaitt)--> TT
//   UTC --DUT1 = UT1 - UTC (eraUtcut1)--> UT1          Delta T = TT - UT1
//
// UTC only exists from 1960; before that the given time is taken as UT
// (UT1 = given + DUT1) and TT = UT1 + Delta T from the Espenak & Meeus (2006)
// polynomials. After the last year ERFA's leap-second table vouches for
// (eraDat's "dubious year"), TAI - UTC is held at its last value: no further
// leap seconds are assumed (the CGPM decided in 2022 to stop them by 2035).
// A user-supplied Delta T replaces both rules: TT = UT1 + Delta T.
// docs/EPHEMERIS.md lists the rules and their errors.
#pragma once

#include <optional>
#include <string>

#include "core/astro/iso8601.h"

namespace atmo::core::astro {

// A Julian date in two parts for precision; value() is the sum.
struct JulianDate {
  double jd1 = 0.0;
  double jd2 = 0.0;
  double value() const { return jd1 + jd2; }
};

// CalendarTime, parse_iso8601 (the one ISO 8601 parser) and
// calendar_from_posix: core/astro/iso8601.h.

// "YYYY-MM-DDThh:mm:ss.sss" of a Julian date on a time scale (milliseconds,
// rounded by eraD2dtf). utc: the date is ERFA's UTC quasi Julian date, whose
// leap-second days read 23:59:60.
std::string format_julian_date(JulianDate jd, bool utc);

// How TT - UT1 was obtained.
enum class DeltaTSource {
  kLeapSeconds,              // leap-second table (eraDat) and DUT1
  kLeapSecondsExtrapolated,  // beyond the table's last year: TAI - UTC held
  kEspenakMeeus2006,         // before 1960 (no UTC): polynomial model
  kUser,                     // given by the caller
};
const char* to_string(DeltaTSource source);

// The validated range of the whole ephemeris; outside it results degrade
// (flagged), they do not fail.
constexpr int kFirstValidatedYear = 1900;
constexpr int kLastValidatedYear = 2100;
// The one range of each input (the ABI checks AtmoFrameState against them):
// |DUT1| <= 0.9 s (the IERS keeps UT1 - UTC within it by leap seconds), and
// UTC in the years 0001-9999, as POSIX seconds [kMinPosixUtcS, kMaxPosixUtcS]
// (0001-01-01T00:00:00Z to 9999-12-31T23:59:59Z).
constexpr double kMaxAbsDut1S = 0.9;
constexpr double kMinPosixUtcS = -62135596800.0;
constexpr double kMaxPosixUtcS = 253402300799.0;

struct TimeScaleOptions {
  double dut1_s = 0.0;              // UT1 - UTC in seconds, |DUT1| <= 0.9
  std::optional<double> delta_t_s;  // TT - UT1 in seconds, replaces the rules above
};

struct TimeScales {
  JulianDate utc;  // ERFA's quasi Julian date (eraDtf2d), or UT before 1960
  JulianDate tai;
  JulianDate tt;
  JulianDate ut1;
  double dut1_s = 0.0;           // UT1 - UTC used
  double delta_t_s = 0.0;        // TT - UT1
  double tai_minus_utc_s = 0.0;  // leap seconds (+ the 1960-71 drift); 0 before 1960
  DeltaTSource delta_t_source = DeltaTSource::kLeapSeconds;
  bool utc_defined = true;       // false before 1960: the input was read as UT
  bool in_validated_range = true;  // 1900..2100
  std::string note;              // empty, or what was modelled / extrapolated
};

// From a UTC calendar instant. Errors (nullopt + message): a non-finite or
// out-of-range field, |DUT1| > 0.9 s, a non-finite Delta T, a second 60 on a
// day without a leap second.
std::optional<TimeScales> time_scales_from_utc(const CalendarTime& utc, const TimeScaleOptions& options,
                                               std::string* error);

// From POSIX UTC seconds, as in the ABI's frame state (utc + dut1_s).
std::optional<TimeScales> time_scales_from_posix(double posix_s, const TimeScaleOptions& options,
                                                 std::string* error);

// From Terrestrial Time (e.g. an ephemeris reference given in TT): UT1 = TT -
// Delta T with Delta T from options.delta_t_s, or else from the rules above
// (UTC recovered with eraTttai/eraTaiutc).
std::optional<TimeScales> time_scales_from_tt(JulianDate tt, const TimeScaleOptions& options, std::string* error);

// The Espenak & Meeus (2006) Delta T polynomials (seconds) at a decimal year
// (NASA's "Polynomial expressions for Delta T"; valid -1999..3000, the
// long-term parabola beyond).
double delta_t_espenak_meeus_s(double decimal_year);

// Decimal year (Julian years of 365.25 d from J2000.0) of a Julian date.
double decimal_year(JulianDate jd);

}  // namespace atmo::core::astro
