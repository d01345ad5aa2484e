// model_study — how far the ephemeris models of core/astro (solar_system.h)
// and ERFA's approximate routines are from JPL DE431, densely over 1900-2100:
// geocentric geometric positions (no light time, no aberration), ICRS, from
// the Swiss Ephemeris with its DE431 files (swe-basic-data). The angular
// separation of each model's geocentric position from DE431's is recorded.
// Standalone (needs libswe-dev, not in the build); docs/EPHEMERIS.md quotes it:
//
//   cmake --build build --target atmo_core
//   g++ -std=c++17 -O2 -Wall -Wextra -Iplugin tools/ephemeris_study/model_study.cpp
//       build/plugin/libatmo_core.a -lswe -lerfa -lnova -lGeographicLib -o model_study
//   (one command line)
//   ./model_study [step_days=0.737]
#include <erfa.h>
#include <erfam.h>
#include <swephexp.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/astro/solar_system.h"

namespace astro = atmo::core::astro;

namespace {
struct Stat {
  double max = 0, sum2 = 0, worst_jd = 0;
  long n = 0;
  void add(double x, double jd) {
    if (x > max) {
      max = x;
      worst_jd = jd;
    }
    sum2 += x * x;
    ++n;
  }
};
double sep_arcsec(const glm::dvec3& a, const double b[3]) {
  double p[3] = {a.x, a.y, a.z}, q[3] = {b[0], b[1], b[2]};
  return eraSepp(p, q) * ERFA_DR2AS;
}
}  // namespace

int main(int argc, char** argv) {
  const double step = argc > 1 ? std::atof(argv[1]) : 0.737;
  char path[] = "/usr/share/libswe/ephe";
  swe_set_ephe_path(path);
  const int32 flags = SEFLG_SWIEPH | SEFLG_J2000 | SEFLG_ICRS | SEFLG_TRUEPOS | SEFLG_NOABERR | SEFLG_NOGDEFL |
                      SEFLG_EQUATORIAL | SEFLG_XYZ;
  const astro::Body planets[] = {astro::Body::kMercury, astro::Body::kVenus, astro::Body::kMars,
                                 astro::Body::kJupiter, astro::Body::kSaturn};
  const int se_ids[] = {SE_MERCURY, SE_VENUS, SE_MARS, SE_JUPITER, SE_SATURN};
  Stat elp, moon98, vsop[5], plan94[5];
  char serr[256];
  for (double jd = 2415020.5; jd < 2488070.0; jd += step) {
    const astro::JulianDate tt{jd, 0.0};
    double x[6];
    int32 rc = swe_calc(jd, SE_MOON, flags, x, serr);
    if (rc < 0 || !(rc & SEFLG_SWIEPH)) {
      std::fprintf(stderr, "swe_calc: %s (no DE431 files?)\n", serr);
      return 1;
    }
    elp.add(sep_arcsec(astro::moon_geocentric_au(tt), x), jd);
    moon98.add(sep_arcsec(astro::moon_geocentric_moon98_au(tt), x), jd);
    const astro::EarthSun es = astro::earth_and_sun(tt);
    for (int p = 0; p < 5; ++p) {
      rc = swe_calc(jd, se_ids[p], flags, x, serr);
      if (rc < 0 || !(rc & SEFLG_SWIEPH)) {
        std::fprintf(stderr, "swe_calc: %s\n", serr);
        return 1;
      }
      vsop[p].add(sep_arcsec(astro::planet_heliocentric_au(planets[p], tt) - es.earth_heliocentric_au, x), jd);
      plan94[p].add(sep_arcsec(astro::planet_heliocentric_plan94_au(planets[p], tt) - es.earth_heliocentric_au, x),
                    jd);
    }
  }
  std::printf("geocentric geometric ICRS positions vs DE431 (Swiss Ephemeris), 1900-2100, every %.3f d, %ld epochs\n",
              step, elp.n);
  std::printf("%-8s %-28s %9s %8s %12s | %-10s %9s %8s %12s\n", "body", "used here", "worst\"", "rms\"", "at JD TT",
              "ERFA", "worst\"", "rms\"", "at JD TT");
  auto row = [](const char* body, const char* model, const Stat& a, const char* erfa, const Stat& b) {
    std::printf("%-8s %-28s %9.3f %8.3f %12.1f | %-10s %9.2f %8.2f %12.1f\n", body, model, a.max,
                std::sqrt(a.sum2 / a.n), a.worst_jd, erfa, b.max, std::sqrt(b.sum2 / b.n), b.worst_jd);
  };
  row("Moon", "ELP 2000-82B (libnova)", elp, "eraMoon98", moon98);
  for (int p = 0; p < 5; ++p) row(astro::to_string(planets[p]), "VSOP87 (libnova)", vsop[p], "eraPlan94", plan94[p]);
  return 0;
}
