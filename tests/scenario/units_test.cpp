// Unit conversions and the automatic exposure curve.
#include <cmath>

#include <gtest/gtest.h>

#include "atmo_scenario/scenario.h"
#include "atmo_scenario/units.h"

namespace u = atmo::scenario::units;
using atmo::scenario::auto_exposure_ev100;

TEST(Units, KnownValues) {
  EXPECT_DOUBLE_EQ(u::feet_to_metres(1000.0), 304.8);
  EXPECT_DOUBLE_EQ(u::metres_to_feet(0.3048), 1.0);
  EXPECT_DOUBLE_EQ(u::celsius_to_kelvin(15.0), 288.15);
  EXPECT_DOUBLE_EQ(u::kelvin_to_celsius(0.0), -273.15);
  EXPECT_DOUBLE_EQ(u::hpa_to_pa(1013.25), 101325.0);
  EXPECT_DOUBLE_EQ(u::pa_to_hpa(101325.0), 1013.25);
  EXPECT_DOUBLE_EQ(u::oktas_to_fraction(4), 0.5);
  EXPECT_DOUBLE_EQ(u::fraction_to_oktas(0.25), 2.0);
  EXPECT_DOUBLE_EQ(u::degrees_to_radians(180.0), u::kPi);
  EXPECT_DOUBLE_EQ(u::radians_to_degrees(u::kPi / 2), 90.0);
}

TEST(Units, RoundTrips) {
  for (double x : {-1234.5, -1.0, 0.0, 0.001, 1.0, 42.0, 12000.0, 1e6}) {
    EXPECT_NEAR(u::metres_to_feet(u::feet_to_metres(x)), x, 1e-9 * (1 + std::abs(x)));
    EXPECT_NEAR(u::kelvin_to_celsius(u::celsius_to_kelvin(x)), x, 1e-9 * (1 + std::abs(x)));
    EXPECT_NEAR(u::pa_to_hpa(u::hpa_to_pa(x)), x, 1e-9 * (1 + std::abs(x)));
    EXPECT_NEAR(u::fraction_to_oktas(u::oktas_to_fraction(x)), x, 1e-12 * (1 + std::abs(x)));
    EXPECT_NEAR(u::radians_to_degrees(u::degrees_to_radians(x)), x, 1e-9 * (1 + std::abs(x)));
  }
  for (double mor : {50.0, 400.0, 8000.0, 40000.0, 500000.0}) {
    EXPECT_NEAR(u::extinction_to_mor(u::mor_to_extinction(mor)), mor, 1e-9 * mor);
  }
  for (double ev : {-6.0, 0.0, 8.0, 12.0, 15.0, 20.5}) {
    EXPECT_NEAR(u::exposure_scale_to_ev100(u::ev100_to_exposure_scale(ev)), ev, 1e-12);
  }
}

// MOR is where a black object's contrast has fallen to 5 %.
TEST(Units, KoschmiederFivePercent) {
  EXPECT_NEAR(u::kKoschmiederConstant, -std::log(0.05), 1e-15);
  EXPECT_NEAR(u::mor_to_extinction(1000.0), 2.9957e-3, 1e-7);
  for (double mor : {100.0, 8000.0, 40000.0}) {
    EXPECT_NEAR(std::exp(-u::mor_to_extinction(mor) * mor), u::kMorContrastThreshold, 1e-12);
  }
}

TEST(Units, OktaCodeFollowsWmo) {
  EXPECT_EQ(u::fraction_to_okta_code(0.0), 0);
  EXPECT_EQ(u::fraction_to_okta_code(-0.1), 0);
  EXPECT_EQ(u::fraction_to_okta_code(0.01), 1);   // a trace of cloud is not clear
  EXPECT_EQ(u::fraction_to_okta_code(0.5), 4);
  EXPECT_EQ(u::fraction_to_okta_code(0.99), 7);   // a gap is not overcast
  EXPECT_EQ(u::fraction_to_okta_code(1.0), 8);
  for (int o = 1; o <= 7; ++o) EXPECT_EQ(u::fraction_to_okta_code(u::oktas_to_fraction(o)), o);
}

TEST(Units, Ev100MatchesTheAbiDefault) {
  // atmo.h: exposure_scale 0 means 1 / (1.2 * 2^15), EV100 = 15.
  EXPECT_DOUBLE_EQ(u::ev100_to_exposure_scale(15.0), 1.0 / (1.2 * 32768.0));
  EXPECT_DOUBLE_EQ(u::ev100_to_exposure_scale(0.0), 1.0 / 1.2);
  EXPECT_DOUBLE_EQ(u::ev100_to_exposure_scale(16.0) * 2.0, u::ev100_to_exposure_scale(15.0));
}

TEST(AutoExposure, KnownPoints) {
  EXPECT_DOUBLE_EQ(auto_exposure_ev100(90.0), 15.0);
  EXPECT_DOUBLE_EQ(auto_exposure_ev100(25.0), 15.0);
  EXPECT_NEAR(auto_exposure_ev100(60.0), 15.0, 1e-12);
  EXPECT_DOUBLE_EQ(auto_exposure_ev100(0.0), 12.0);   // sunset
  EXPECT_DOUBLE_EQ(auto_exposure_ev100(-4.0), 8.0);   // civil twilight
  EXPECT_DOUBLE_EQ(auto_exposure_ev100(-10.0), 2.0);  // night
  EXPECT_DOUBLE_EQ(auto_exposure_ev100(-90.0), 2.0);
  EXPECT_GT(auto_exposure_ev100(-3.0), 8.0);
  EXPECT_LT(auto_exposure_ev100(-6.0), 8.0);
  EXPECT_TRUE(std::isfinite(auto_exposure_ev100(std::nan(""))));
}

TEST(AutoExposure, MonotoneAndSmooth) {
  const double step = 0.001;
  double prev = auto_exposure_ev100(-20.0);
  double prev_slope = 0.0;
  for (double e = -20.0 + step; e <= 40.0; e += step) {
    const double v = auto_exposure_ev100(e);
    ASSERT_GE(v, prev - 1e-12) << "decreases at " << e;
    const double slope = (v - prev) / step;
    ASSERT_LE(slope, 2.0) << "too steep at " << e;  // no jumps
    ASSERT_NEAR(slope, prev_slope, 0.01) << "kink at " << e;  // C1: slope is continuous
    prev = v;
    prev_slope = slope;
  }
}
