// The low-precision solar position against ERFA (IAU SOFA): geocentric Sun
// from eraEpv00, IAU 2006/2000A precession-nutation, Greenwich apparent
// sidereal time. The formula claims ~0.01° over 1950–2050; we require 0.02°.
#include <erfa.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/astro/solar_position.h"

namespace {

glm::dvec3 erfa_sun_ecef(double posix_s) {
  const double utc1 = 2440587.5, utc2 = posix_s / 86400.0;
  double tai1, tai2, tt1, tt2, ut11, ut12;
  eraUtctai(utc1, utc2, &tai1, &tai2);
  eraTaitt(tai1, tai2, &tt1, &tt2);
  eraUtcut1(utc1, utc2, 0.0, &ut11, &ut12);
  double pvh[2][3], pvb[2][3];
  eraEpv00(tt1, tt2, pvh, pvb);
  double sun_gcrs[3] = {-pvh[0][0], -pvh[0][1], -pvh[0][2]};
  double rnpb[3][3];
  eraPnm06a(tt1, tt2, rnpb);
  double tod[3];
  eraRxp(rnpb, sun_gcrs, tod);
  double gast = eraGst06a(ut11, ut12, tt1, tt2);
  glm::dvec3 ecef(std::cos(gast) * tod[0] + std::sin(gast) * tod[1], -std::sin(gast) * tod[0] + std::cos(gast) * tod[1],
                  tod[2]);
  return glm::normalize(ecef);
}

}  // namespace

TEST(SolarPosition, WithinTwoHundredthsOfADegreeOfErfa1950To2050) {
  double worst_deg = 0.0, worst_at = 0.0;
  const double start = -631152000.0;  // 1950-01-01
  const double end = 2524608000.0;    // 2050-01-01
  const int samples = 4000;
  for (int i = 0; i <= samples; ++i) {
    double t = start + (end - start) * i / samples + 3600.0 * 7.3 * i;  // vary the hour too
    glm::dvec3 ours = atmo::core::solar_position(t, 0.0).direction_ecef;
    double angle = std::acos(std::min(1.0, glm::dot(ours, erfa_sun_ecef(t)))) * 180.0 / M_PI;
    if (angle > worst_deg) {
      worst_deg = angle;
      worst_at = t;
    }
  }
  std::printf("[ sun ] worst angular error vs ERFA over 1950-2050 (%d samples): %.4f deg (%.1f arcsec) at POSIX %.0f\n",
              samples + 1, worst_deg, worst_deg * 3600.0, worst_at);
  EXPECT_LT(worst_deg, 0.02);
}

TEST(SolarPosition, DistanceWithinPerihelionAphelion) {
  for (double t = 1.7e9; t < 1.7e9 + 3.2e7; t += 86400.0 * 5) {
    double d = atmo::core::solar_position(t, 0.0).distance_au;
    EXPECT_GT(d, 0.9832);
    EXPECT_LT(d, 1.0168);
  }
}
