// ISO 8601 -> POSIX seconds against values computed independently (Python's
// datetime), and the calendar helpers against each other.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "atmo_scenario/scenario.h"

namespace sc = atmo::scenario;

namespace {

double parse_ok(const std::string& s) {
  std::string error;
  const auto t = sc::parse_iso8601_utc(s, &error);
  EXPECT_TRUE(t) << s << ": " << error;
  return t ? *t : std::nan("");
}

std::string parse_error(const std::string& s) {
  std::string error;
  const auto t = sc::parse_iso8601_utc(s, &error);
  EXPECT_FALSE(t) << s << " parsed as " << (t ? *t : 0.0);
  EXPECT_FALSE(error.empty()) << s;
  return error;
}

}  // namespace

TEST(Iso8601, KnownPosixValues) {
  EXPECT_EQ(parse_ok("1970-01-01T00:00:00Z"), 0.0);
  EXPECT_EQ(parse_ok("2000-01-01T12:00:00Z"), 946728000.0);  // J2000.0 in UTC
  EXPECT_EQ(parse_ok("2024-06-21T11:00:00Z"), 1718967600.0);
  EXPECT_EQ(parse_ok("1969-12-31T23:59:59Z"), -1.0);
  EXPECT_EQ(parse_ok("1900-01-01T00:00:00Z"), -2208988800.0);  // not a leap year
  EXPECT_EQ(parse_ok("0001-01-01T00:00:00Z"), -62135596800.0);
  EXPECT_EQ(parse_ok("9999-12-31T23:59:59Z"), 253402300799.0);
}

TEST(Iso8601, LeapDays) {
  EXPECT_EQ(parse_ok("2024-02-29T00:00:00Z"), 1709164800.0);
  EXPECT_EQ(parse_ok("2000-02-29T00:00:00Z"), 951782400.0);  // divisible by 400
  EXPECT_NE(parse_error("2023-02-29T00:00:00Z").find("2023-02 has 28 days"), std::string::npos);
  parse_error("2100-02-29T00:00:00Z");  // divisible by 100, not by 400
  parse_error("2024-02-30T00:00:00Z");
  parse_error("2024-04-31T00:00:00Z");
  parse_error("2024-01-00T00:00:00Z");
  EXPECT_EQ(parse_ok("2024-12-31T00:00:00Z") - parse_ok("2024-01-01T00:00:00Z"), 365 * 86400.0);
}

TEST(Iso8601, Offsets) {
  EXPECT_EQ(parse_ok("2024-06-21T13:00:00+02:00"), 1718967600.0);
  EXPECT_EQ(parse_ok("2024-03-10T05:30:00-05:30"), 1710068400.0);
  EXPECT_EQ(parse_ok("2024-06-21T11:00:00+00:00"), parse_ok("2024-06-21T11:00:00Z"));
  EXPECT_EQ(parse_ok("2024-06-21T11:00:00-00:00"), parse_ok("2024-06-21T11:00:00Z"));
  // An offset can move the instant across a day, month and year boundary.
  EXPECT_EQ(parse_ok("2025-01-01T01:00:00+02:00"), parse_ok("2024-12-31T23:00:00Z"));
  parse_error("2024-06-21T11:00:00+24:00");
  parse_error("2024-06-21T11:00:00+02:60");
  parse_error("2024-06-21T11:00:00+2:00");
  parse_error("2024-06-21T11:00:00+0200");
}

TEST(Iso8601, FractionalSeconds) {
  EXPECT_EQ(parse_ok("2024-06-21T11:00:00.5Z"), 1718967600.5);
  EXPECT_EQ(parse_ok("2024-06-21T11:00:00.250Z"), 1718967600.25);
  EXPECT_NEAR(parse_ok("2024-06-21T11:00:00.123456789Z") - 1718967600.0, 0.123456789, 1e-6);
  EXPECT_EQ(parse_ok("2024-01-15T08:30:00.250+10:00"), 1705271400.25);
  parse_error("2024-06-21T11:00:00.Z");
}

TEST(Iso8601, RejectsWhatIsNotTheFormat) {
  for (const char* s :
       {"", "2024-06-21", "2024-06-21T11:00Z", "2024-06-21T11:00:00", "2024-06-21 11:00:00Z",
        "2024-06-21t11:00:00Z", "2024-06-21T11:00:00z", "24-06-21T11:00:00Z", "2024-6-21T11:00:00Z",
        "2024-06-21T11:00:00Z ", " 2024-06-21T11:00:00Z", "2024-06-21T11:00:00ZZ", "+2024-06-21T11:00:00Z",
        "2024-13-01T00:00:00Z", "2024-00-01T00:00:00Z", "2024-06-21T24:00:00Z",
        "2024-06-21T23:60:00Z", "2024-06-21T23:59:61Z"}) {
    parse_error(s);
  }
  EXPECT_NE(parse_error("2016-12-31T23:59:60Z").find("leap second"), std::string::npos);
  EXPECT_FALSE(sc::parse_iso8601_utc("garbage", nullptr));  // error may be null
}

TEST(Iso8601, FormatRoundTrip) {
  for (const char* s : {"1970-01-01T00:00:00Z", "2024-02-29T23:59:59Z", "1969-12-31T23:59:59.500Z",
                        "1900-03-01T12:34:56.789Z", "9999-12-31T23:59:59Z"}) {
    EXPECT_EQ(sc::format_iso8601_utc(parse_ok(s)), s);
  }
  EXPECT_EQ(sc::format_iso8601_utc(1718967600.0), "2024-06-21T11:00:00Z");
  EXPECT_EQ(sc::format_iso8601_utc(59.9996), "1970-01-01T00:01:00Z");  // rounds to ms
}
