// Time scales (core/astro/time_scales.h) against ERFA's own routines and
// published values: leap seconds, TT - TAI, DUT1, the Espenak & Meeus Delta T,
// the ISO 8601 parser (offsets, fractions, leap seconds) and its errors.
#include <erfa.h>
#include <erfam.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "core/astro/time_scales.h"

namespace astro = atmo::core::astro;

namespace {

astro::TimeScales from_iso(const std::string& text, astro::TimeScaleOptions options = {}) {
  std::string error;
  const auto c = astro::parse_iso8601(text, &error);
  EXPECT_TRUE(c) << text << ": " << error;
  if (!c) return {};
  const auto t = astro::time_scales_from_utc(*c, options, &error);
  EXPECT_TRUE(t) << text << ": " << error;
  return t ? *t : astro::TimeScales{};
}

std::string iso_error(const std::string& text) {
  std::string error;
  const auto c = astro::parse_iso8601(text, &error);
  EXPECT_FALSE(c) << text << " parsed";
  EXPECT_FALSE(error.empty()) << text;
  return error;
}

double seconds(astro::JulianDate a, astro::JulianDate b) { return ((a.jd1 - b.jd1) + (a.jd2 - b.jd2)) * 86400.0; }

}  // namespace

TEST(TimeScale, ModernDateFollowsLeapSecondsAndDut1) {
  astro::TimeScaleOptions o;
  o.dut1_s = 0.0123;
  const astro::TimeScales t = from_iso("2024-12-15T03:00:00Z", o);
  EXPECT_EQ(t.delta_t_source, astro::DeltaTSource::kLeapSeconds);
  EXPECT_TRUE(t.utc_defined);
  EXPECT_TRUE(t.in_validated_range);
  EXPECT_TRUE(t.note.empty()) << t.note;
  EXPECT_DOUBLE_EQ(t.tai_minus_utc_s, 37.0);
  EXPECT_NEAR(seconds(t.tai, t.utc), 37.0, 1e-5);
  EXPECT_NEAR(seconds(t.tt, t.tai), 32.184, 1e-5);
  EXPECT_NEAR(seconds(t.ut1, t.utc), 0.0123, 1e-5);
  EXPECT_NEAR(t.delta_t_s, 69.184 - 0.0123, 1e-5);
  EXPECT_NEAR(t.utc.value(), 2460659.625, 1e-9);  // 2024-12-15 03:00 UTC

  // The same instant from POSIX seconds, as in the frame state.
  std::string error;
  const auto p = astro::time_scales_from_posix(1734231600.0, o, &error);
  ASSERT_TRUE(p) << error;
  EXPECT_NEAR(seconds(p->tt, t.tt), 0.0, 1e-5);
  EXPECT_NEAR(seconds(p->ut1, t.ut1), 0.0, 1e-5);
}

TEST(TimeScale, MatchesErfaAcrossTheLeapSecondEra) {
  // Every 97 days from 1960 to 2026: our TAI, TT, UT1 equal ERFA's chain.
  for (double jd = 2436934.5; jd < 2461041.5; jd += 97.3) {
    int y, m, d;
    double fd;
    eraJd2cal(jd, 0.0, &y, &m, &d, &fd);
    const int hour = static_cast<int>(fd * 24.0);
    astro::CalendarTime c{y, m, d, hour, 17, 42.25};
    astro::TimeScaleOptions o;
    o.dut1_s = -0.4;
    std::string error;
    const auto t = astro::time_scales_from_utc(c, o, &error);
    ASSERT_TRUE(t) << error;
    double u1, u2, a1, a2, t1, t2, b1, b2;
    ASSERT_GE(eraDtf2d("UTC", y, m, d, hour, 17, 42.25, &u1, &u2), 0);
    eraUtctai(u1, u2, &a1, &a2);
    eraTaitt(a1, a2, &t1, &t2);
    eraUtcut1(u1, u2, -0.4, &b1, &b2);
    EXPECT_NEAR(seconds(t->tai, {a1, a2}), 0.0, 1e-5) << y << "-" << m << "-" << d;
    EXPECT_NEAR(seconds(t->tt, {t1, t2}), 0.0, 1e-5);
    EXPECT_NEAR(seconds(t->ut1, {b1, b2}), 0.0, 1e-5);
    EXPECT_EQ(t->delta_t_source, astro::DeltaTSource::kLeapSeconds);
  }
}

TEST(TimeScale, LeapSecondsAreExactAndCheckedAgainstTheTable) {
  // 2016-12-31 had a leap second: 23:59:60.5 exists and is 0.5 s after :60.0.
  const astro::TimeScales a = from_iso("2016-12-31T23:59:60.000Z");
  const astro::TimeScales b = from_iso("2016-12-31T23:59:60.500Z");
  const astro::TimeScales c = from_iso("2017-01-01T00:00:00Z");
  EXPECT_NEAR(seconds(b.tai, a.tai), 0.5, 1e-5);
  EXPECT_NEAR(seconds(c.tai, a.tai), 1.0, 1e-5);
  EXPECT_DOUBLE_EQ(c.tai_minus_utc_s, 37.0);
  EXPECT_NEAR(seconds(from_iso("2016-12-31T23:59:59Z").tai, c.tai), -2.0, 1e-5);  // 23:59:59 -> :60 -> 00:00

  // 2015-12-31 had none (the 2015 leap second was on June 30).
  std::string error;
  const auto cal = astro::parse_iso8601("2015-12-31T23:59:60Z", &error);
  ASSERT_TRUE(cal) << error;
  EXPECT_FALSE(astro::time_scales_from_utc(*cal, {}, &error));
  EXPECT_NE(error.find("no leap second"), std::string::npos) << error;
  EXPECT_TRUE(astro::time_scales_from_utc(*astro::parse_iso8601("2015-06-30T23:59:60.9Z", &error), {}, &error))
      << error;
}

TEST(TimeScale, Iso8601OffsetsAndFractions) {
  EXPECT_NEAR(seconds(from_iso("2024-12-15T04:00:00+01:00").tt, from_iso("2024-12-15T03:00:00Z").tt), 0.0, 1e-6);
  EXPECT_NEAR(seconds(from_iso("2024-12-14T21:30:00-05:30").tt, from_iso("2024-12-15T03:00:00Z").tt), 0.0, 1e-6);
  // Across a year boundary.
  EXPECT_NEAR(seconds(from_iso("2025-01-01T00:30:00+01:00").tt, from_iso("2024-12-31T23:30:00Z").tt), 0.0, 1e-6);
  EXPECT_NEAR(seconds(from_iso("2024-12-15T03:00:00.250Z").tt, from_iso("2024-12-15T03:00:00Z").tt), 0.25, 1e-6);
  EXPECT_NEAR(seconds(from_iso("2024-12-15T03:00:00.000001Z").tt, from_iso("2024-12-15T03:00:00Z").tt), 1e-6, 1e-7);
  std::string error;
  const auto c = astro::parse_iso8601("2000-02-29T12:00:00Z", &error);
  ASSERT_TRUE(c) << error;
  EXPECT_EQ(c->year, 2000);
  EXPECT_EQ(c->month, 2);
  EXPECT_EQ(c->day, 29);
}

TEST(TimeScale, Iso8601ErrorsAreClear) {
  EXPECT_NE(iso_error("2024-12-15 03:00:00Z").find("not of the form"), std::string::npos);
  EXPECT_NE(iso_error("2024-12-15T03:00:00").find("no time zone"), std::string::npos);
  EXPECT_NE(iso_error("2024-13-15T03:00:00Z").find("month 13"), std::string::npos);
  EXPECT_NE(iso_error("2023-02-29T03:00:00Z").find("day 29 does not exist in 2023-02"), std::string::npos);
  EXPECT_NE(iso_error("2024-12-15T24:00:00Z").find("time of day"), std::string::npos);
  EXPECT_NE(iso_error("2024-12-15T03:00:61Z").find("seconds"), std::string::npos);
  EXPECT_NE(iso_error("2024-12-15T03:00:00+24:00").find("offset"), std::string::npos);
  EXPECT_NE(iso_error("2024-12-15T03:00:00.Z").find("no digits"), std::string::npos);
  EXPECT_NE(iso_error("2024-12-15T03:00:00Zjunk").find("after the time zone"), std::string::npos);
  EXPECT_NE(iso_error("").find("not of the form"), std::string::npos);
}

TEST(TimeScale, BadOptionsAndTimesAreRejected) {
  std::string error;
  astro::TimeScaleOptions o;
  o.dut1_s = 0.95;
  EXPECT_FALSE(astro::time_scales_from_posix(0.0, o, &error));
  EXPECT_NE(error.find("DUT1"), std::string::npos) << error;
  o.dut1_s = std::nan("");
  EXPECT_FALSE(astro::time_scales_from_posix(0.0, o, &error));
  o = {};
  o.delta_t_s = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(astro::time_scales_from_posix(0.0, o, &error));
  EXPECT_NE(error.find("Delta T"), std::string::npos) << error;
  EXPECT_FALSE(astro::time_scales_from_posix(std::nan(""), {}, &error));
  EXPECT_NE(error.find("POSIX"), std::string::npos) << error;
  EXPECT_FALSE(astro::time_scales_from_posix(1e300, {}, &error));
  EXPECT_FALSE(astro::time_scales_from_tt({std::nan(""), 0.0}, {}, &error));
}

TEST(TimeScale, BeforeUtcDeltaTComesFromEspenakMeeus) {
  const astro::TimeScales t = from_iso("1900-01-01T00:00:00Z");
  EXPECT_FALSE(t.utc_defined);
  EXPECT_EQ(t.delta_t_source, astro::DeltaTSource::kEspenakMeeus2006);
  EXPECT_FALSE(t.note.empty());
  EXPECT_TRUE(t.in_validated_range);
  // Published Delta T at 1900.0 is -2.7 s (Morrison & Stephenson; EM2006 -2.7).
  EXPECT_NEAR(t.delta_t_s, -2.7, 0.15);
  EXPECT_NEAR(seconds(t.tt, t.ut1), t.delta_t_s, 1e-5);
  EXPECT_NEAR(seconds(t.tt, t.tai), 32.184, 1e-5);
  // Tabulated values (NASA's Delta T table, seconds): 1920 21.2, 1950 29.1, 2000 63.9.
  EXPECT_NEAR(astro::delta_t_espenak_meeus_s(1920.0), 21.2, 0.1);
  EXPECT_NEAR(astro::delta_t_espenak_meeus_s(1950.0), 29.07, 0.01);
  EXPECT_NEAR(astro::delta_t_espenak_meeus_s(2000.0), 63.86, 0.01);
  // The published polynomial pieces join within 0.1 s from 1800 on (0.25 s
  // at 1600 and 1700).
  for (double y : {1800.0, 1860.0, 1900.0, 1920.0, 1941.0, 1961.0, 1986.0, 2005.0, 2050.0, 2150.0}) {
    EXPECT_NEAR(astro::delta_t_espenak_meeus_s(y - 1e-9), astro::delta_t_espenak_meeus_s(y), 0.1) << y;
  }
  for (double y : {1600.0, 1700.0}) {
    EXPECT_NEAR(astro::delta_t_espenak_meeus_s(y - 1e-9), astro::delta_t_espenak_meeus_s(y), 0.3) << y;
  }
  // A user Delta T replaces the model.
  astro::TimeScaleOptions o;
  o.delta_t_s = 1.5;
  const astro::TimeScales u = from_iso("1900-01-01T00:00:00Z", o);
  EXPECT_EQ(u.delta_t_source, astro::DeltaTSource::kUser);
  EXPECT_NEAR(seconds(u.tt, u.ut1), 1.5, 1e-5);
}

TEST(TimeScale, AfterTheLeapSecondTableTaiMinusUtcIsHeld) {
  const astro::TimeScales t = from_iso("2100-12-31T23:59:59Z");
  EXPECT_EQ(t.delta_t_source, astro::DeltaTSource::kLeapSecondsExtrapolated);
  EXPECT_TRUE(t.in_validated_range);
  EXPECT_DOUBLE_EQ(t.tai_minus_utc_s, 37.0);
  EXPECT_NEAR(t.delta_t_s, 69.184, 1e-5);
  EXPECT_NE(t.note.find("no further leap seconds"), std::string::npos) << t.note;
  // Past 2100: flagged, still computed, continuous.
  const astro::TimeScales later = from_iso("2101-01-01T00:00:01Z");
  EXPECT_FALSE(later.in_validated_range);
  EXPECT_NE(later.note.find("outside the validated 1900-2100"), std::string::npos) << later.note;
  EXPECT_NEAR(seconds(later.tt, t.tt), 2.0, 1e-5);
}

TEST(TimeScale, FromTtRoundTrips) {
  for (const char* iso : {"1905-03-01T12:00:00Z", "1975-07-01T06:30:00Z", "2024-12-15T03:00:00Z",
                          "2077-02-02T02:02:02Z"}) {
    astro::TimeScaleOptions o;
    o.dut1_s = 0.3;
    const astro::TimeScales a = from_iso(iso, o);
    std::string error;
    const auto b = astro::time_scales_from_tt(a.tt, o, &error);
    ASSERT_TRUE(b) << error;
    EXPECT_NEAR(seconds(b->ut1, a.ut1), 0.0, 1e-4) << iso;
    EXPECT_NEAR(seconds(b->utc, a.utc), 0.0, 1e-4) << iso;
    EXPECT_EQ(b->delta_t_source, a.delta_t_source) << iso;
  }
  // With a given Delta T, UT1 = TT - Delta T exactly.
  astro::TimeScaleOptions o;
  o.delta_t_s = 93.6;
  std::string error;
  const auto t = astro::time_scales_from_tt({2488069.0, 0.0}, o, &error);
  ASSERT_TRUE(t) << error;
  EXPECT_NEAR(seconds(t->tt, t->ut1), 93.6, 1e-5);
}

TEST(TimeScale, FormatsJulianDates) {
  const astro::TimeScales t = from_iso("2016-12-31T23:59:60.250Z");
  EXPECT_EQ(astro::format_julian_date(t.utc, true), "2016-12-31T23:59:60.250");
  EXPECT_EQ(astro::format_julian_date(from_iso("2024-12-15T03:00:00Z").tt, false), "2024-12-15T03:01:09.184");
}

// The calendar of the one ISO 8601 parser (core/astro/iso8601.h; moved from tools/scenario, whose copy and the
// sample host's were two of them).
TEST(Iso8601Calendar, RoundTrip) {
  for (std::int64_t days = -800000; days <= 3000000; ++days) {  // years ~-220 to ~10183
    std::int64_t y;
    unsigned m, d;
    astro::civil_from_days(days, &y, &m, &d);
    ASSERT_GE(m, 1u);
    ASSERT_LE(m, 12u);
    ASSERT_GE(d, 1u);
    ASSERT_LE(d, astro::days_in_month(y, m));
    ASSERT_EQ(astro::days_from_civil(y, m, d), days) << y << "-" << m << "-" << d;
  }
  EXPECT_EQ(astro::days_from_civil(1970, 1, 1), 0);
  EXPECT_EQ(astro::days_from_civil(2000, 3, 1), 11017);
  EXPECT_TRUE(astro::is_leap_year(2000));
  EXPECT_FALSE(astro::is_leap_year(1900));
  EXPECT_TRUE(astro::is_leap_year(2024));
  EXPECT_FALSE(astro::is_leap_year(2023));
  EXPECT_EQ(astro::days_in_month(2023, 2), 28u);
  EXPECT_EQ(astro::days_in_month(2024, 2), 29u);
  EXPECT_EQ(astro::days_in_month(2024, 13), 0u);
}


// Where the three parsers (core/astro/time_scales, tools/scenario/iso8601 and the sample host's
// scene_settings) disagreed, the one parser gives one answer, as a calendar time and as POSIX seconds (the
// scenario loader and the sample host read it so). Before: the core summed the fraction's digits times 0.1^k
// (".3" came out 0.30000000000000004 s) and accepted "t" and "z", which the scenario loader and its schema refuse; the sample host accepted 2024-02-30 (as
// March 1), "2024-06-21 15:00:00" and 23:59:60.5 as POSIX time, and refused any offset; the scenario's
// day error named no date in the core's words.
TEST(Iso8601Calendar, OneParserForTheCasesThatDisagreed) {
  struct Case {
    const char* text;
    bool calendar_ok, posix_ok;
    double posix_s;  // expected POSIX seconds (Python's datetime), when posix_ok
    const char* error;  // part of the message, when rejected
  };
  const Case cases[] = {
      {"2024-06-21T11:00:00.1234567890123Z", true, true, 1718967600.1234567890123, ""},
      {"2024-06-21T11:00:00.5Z", true, true, 1718967600.5, ""},
      {"2024-06-21T13:00:00+02:00", true, true, 1718967600.0, ""},
      {"2025-01-01T01:00:00+02:00", true, true, 1735686000.0, ""},  // back across a year
      {"2024-12-31T23:30:00-01:00", true, true, 1735691400.0, ""},  // forward across a year
      {"2016-12-31T23:59:60Z", true, false, 0.0, "leap second"},
      {"2016-12-31T23:59:60.5Z", true, false, 0.0, "leap second"},
      {"2017-01-01T00:59:60+01:00", true, false, 0.0, "leap second"},
      {"1900-01-01T00:00:00Z", true, true, -2208988800.0, ""},
      {"0001-01-01T00:00:00Z", true, true, -62135596800.0, ""},
      {"2100-03-01T00:00:00Z", true, true, 4107542400.0, ""},
      {"2040-02-29T12:00:00Z", true, true, 2214129600.0, ""},  // past 2038 (32-bit time_t)
      {"9999-12-31T23:59:59Z", true, true, 253402300799.0, ""},
      {"2024-02-30T00:00:00Z", false, false, 0.0, "day 30 does not exist in 2024-02 (2024-02 has 29 days)"},
      {"2100-02-29T00:00:00Z", false, false, 0.0, "day 29 does not exist in 2100-02"},
      {"2024-06-21 15:00:00Z", false, false, 0.0, "not of the form"},
      {"2024-06-21T15:00Z", false, false, 0.0, "not of the form"},
      {"2024-06-21t15:00:00Z", false, false, 0.0, "not of the form"},  // as the scenario schema
      {"2024-06-21T15:00:00z", false, false, 0.0, "no time zone"},
      {"2024-06-21T15:00:00", false, false, 0.0, "no time zone"},
      {"12024-06-21T15:00:00Z", false, false, 0.0, "not of the form"},
  };
  for (const Case& c : cases) {
    std::string calendar_error, posix_error;
    const auto calendar = astro::parse_iso8601(c.text, &calendar_error);
    const auto posix = astro::parse_iso8601_posix(c.text, &posix_error);
    std::printf("[ iso8601 ] %-36s calendar %s, POSIX %s\n", c.text,
                calendar ? "ok" : calendar_error.c_str(),
                posix ? std::to_string(*posix).c_str() : posix_error.c_str());
    EXPECT_EQ(calendar.has_value(), c.calendar_ok) << c.text << ": " << calendar_error;
    EXPECT_EQ(posix.has_value(), c.posix_ok) << c.text << ": " << posix_error;
    if (c.posix_ok && posix) {
      EXPECT_NEAR(*posix, c.posix_s, 1e-6) << c.text;
    }
    if (!c.posix_ok) {
      EXPECT_NE(posix_error.find(c.error), std::string::npos) << c.text << ": " << posix_error;
    }
    if (!c.calendar_ok) {
      EXPECT_EQ(calendar_error, posix_error) << c.text;
    }
  }
  // The fraction is read exactly (one division), whatever its length.
  EXPECT_EQ(astro::parse_iso8601("2024-06-21T11:00:00.3Z", nullptr)->second, 0.3);
  EXPECT_EQ(astro::parse_iso8601("2024-06-21T11:00:00.1234567890123Z", nullptr)->second, 0.1234567890123);
  // The leap second stays a calendar time, for the leap-second table.
  EXPECT_EQ(astro::parse_iso8601("2017-01-01T00:59:60.25+01:00", nullptr)->second, 60.25);
  EXPECT_EQ(astro::parse_iso8601("2017-01-01T00:59:60.25+01:00", nullptr)->day, 31);
}
