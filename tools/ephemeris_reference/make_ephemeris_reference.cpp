// make_ephemeris_reference: writes tests/data/ephemeris_reference.csv, a
// reference table of apparent places of the Sun, Moon and five planets over
// 1900-2100, computed with the Swiss Ephemeris (compressed JPL DE431 files
// sepl_18.se1 / semo_18.se1). The table is independent of ERFA and is used by
// the ephemeris accuracy tests. See docs/EPHEMERIS_REFERENCE.md.
//
// Not part of the default build (libswe is not a project dependency). Build:
//   g++ -std=c++17 -O2 -Wall -Wextra tools/ephemeris_reference/make_ephemeris_reference.cpp -Itools/support/include -lswe -lm -o make_ephemeris_reference
// or configure with -DATMO_BUILD_EPHEMERIS_REFERENCE=ON (needs libswe-dev).
// Run:
//   ./make_ephemeris_reference --out tests/data/ephemeris_reference.csv
//
// Options:
//   --ephe-path DIR   directory with sepl_18.se1 and semo_18.se1
//                     (default /usr/share/libswe/ephe, Debian swe-basic-data)
//   --out FILE        output CSV (default: standard output)
//   --strata N        number of stratified pseudo-random instants (default 36)
//   --seed S          seed of the pseudo-random offsets (default 20241215)
//   --self-check-only run the self-checks only, write no table
//
// Exit status: 0 on success; 1 if any Swiss Ephemeris call fails, reports a
// message, or does not use the .se1 files (e.g. a silent fallback to the
// Moshier analytic ephemeris), or if a self-check fails; 2 on a bad argument
// (CLI11's message names the option).
//
// Swiss Ephemeris is (c) Astrodienst AG, dual-licensed GPL-2.0-or-later or the
// Swiss Ephemeris Professional License. This generator links it only as a
// standalone tool; the numbers it writes are data for the project's tests.

#include <swephexp.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "atmo_support/cli.h"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kArcsec = kDeg / 3600.0;
constexpr double kAuM = 149597870700.0;         // IAU 2012 astronomical unit, m
constexpr double kCAuPerDay = 299792458.0 * 86400.0 / kAuM;
// Observer ellipsoid and rotation rate as used inside the Swiss Ephemeris
// (sweph.h: EARTH_RADIUS, EARTH_OBLATENESS, EARTH_ROT_SPEED).
constexpr double kSeEarthRadiusM = 6378136.6;
constexpr double kSeEarthFlattening = 1.0 / 298.25642;
constexpr double kSeEarthRotRadPerDay = 7.2921151467e-5 * 86400.0;

const int32 kFlagsGeo = SEFLG_SWIEPH | SEFLG_EQUATORIAL;
const int32 kFlagsTopo = SEFLG_SWIEPH | SEFLG_EQUATORIAL | SEFLG_TOPOCTR;
const int32 kFlagsPheno = SEFLG_SWIEPH | SEFLG_TOPOCTR;

struct Body {
  const char* name;
  int ipl;
};
const Body kBodies[] = {{"Sun", SE_SUN},         {"Moon", SE_MOON},       {"Mercury", SE_MERCURY},
                        {"Venus", SE_VENUS},     {"Mars", SE_MARS},       {"Jupiter", SE_JUPITER},
                        {"Saturn", SE_SATURN}};

struct Location {
  const char* name;
  double lat_deg, lon_deg, height_m;
};
const Location kLocations[] = {
    {"near North Pole", 89.9, 0.0, 0.0},
    {"near South Pole, polar plateau", -89.9, 139.27, 2835.0},
    {"date line, east (+180)", -16.5, 180.0, 0.0},
    {"date line, west (-180)", 65.0, -180.0, 0.0},
    {"Innsbruck", 47.26, 11.35, 620.0},
    {"stratospheric balloon, 30 km", 34.47, -104.24, 30000.0},
    {"equator, sea level", 0.0, 9.3, 0.0},
};

bool g_failed = false;

void fail(const std::string& what) {
  std::fprintf(stderr, "make_ephemeris_reference: ERROR: %s\n", what.c_str());
  g_failed = true;
}

// Checks the flag returned by swe_calc/swe_pheno: must be >= 0, must say
// SEFLG_SWIEPH (the .se1 files) and not SEFLG_MOSEPH (analytic fallback), and
// serr must be empty (SE reports a fallback there).
void check_ret(int32 ret, const char* serr, const char* what, double jd, bool allow_venus_mag_warning = false) {
  char buf[512];
  if (ret < 0) {
    std::snprintf(buf, sizeof buf, "%s at JD %.6f failed: %s", what, jd, serr);
    fail(buf);
    return;
  }
  if (!(ret & SEFLG_SWIEPH) || (ret & SEFLG_MOSEPH) || (ret & SEFLG_JPLEPH)) {
    std::snprintf(buf, sizeof buf, "%s at JD %.6f did not use the Swiss Ephemeris files (ret flag 0x%x): %s", what,
                  jd, static_cast<unsigned>(ret), serr);
    fail(buf);
  }
  if (serr[0] != '\0') {
    if (allow_venus_mag_warning && std::strstr(serr, "magnitude value for Venus") != nullptr) return;
    std::snprintf(buf, sizeof buf, "%s at JD %.6f: message from SE: %s", what, jd, serr);
    fail(buf);
  }
}

struct Vec3 {
  double x, y, z;
};
Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double norm(Vec3 a) { return std::sqrt(dot(a, a)); }
Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
// Angle between two directions, robust for small angles (radians).
double angle(Vec3 a, Vec3 b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }
Vec3 from_radec(double ra_deg, double dec_deg, double r) {
  return {r * std::cos(dec_deg * kDeg) * std::cos(ra_deg * kDeg), r * std::cos(dec_deg * kDeg) * std::sin(ra_deg * kDeg),
          r * std::sin(dec_deg * kDeg)};
}
Vec3 rot1(Vec3 v, double a) {  // rotation about x by angle a (frame rotation)
  const double c = std::cos(a), s = std::sin(a);
  return {v.x, c * v.y + s * v.z, -s * v.y + c * v.z};
}
Vec3 rot3(Vec3 v, double a) {  // rotation about z by angle a (frame rotation)
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x + s * v.y, -s * v.x + c * v.y, v.z};
}

// splitmix64: a fixed, portable pseudo-random sequence.
uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Rounds a JD to 1e-6 day through its printed form, so the value computed
// with is exactly the value written to the CSV.
double canonical_jd(double jd, std::string* text) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", jd);
  if (text) *text = buf;
  return std::strtod(buf, nullptr);
}

double norm360(double a) {
  a = std::fmod(a, 360.0);
  if (a < 0) a += 360.0;
  if (a >= 360.0) a -= 360.0;
  return a;
}

struct Place {
  double ra, dec, dist;
};

Place calc(double jd, int ipl, int32 flags, const char* what) {
  double x[6] = {0, 0, 0, 0, 0, 0};
  char serr[AS_MAXCH] = "";
  const int32 ret = swe_calc(jd, ipl, flags, x, serr);
  check_ret(ret, serr, what, jd);
  return {x[0], x[1], x[2]};
}

// Geocentric observer vector in AU, true equator and equinox of date.
// mean_pole = true reproduces SE's own model (swi_get_observer: the observer is
// placed with the MEAN sidereal time on the MEAN equator of date, then carried
// into the true frame by nutation); mean_pole = false places it on the true
// equator (CIP) with the apparent sidereal time, the physically correct model.
Vec3 observer_true_of_date(double jd_tt, const Location& loc, bool mean_pole, Vec3* velocity_au_per_day) {
  const double jd_ut = jd_tt - swe_deltat_ex(jd_tt, SEFLG_SWIEPH, nullptr);
  double nut[6];
  char serr[AS_MAXCH] = "";
  swe_calc(jd_tt, SE_ECL_NUT, 0, nut, serr);  // true eps, mean eps, dpsi, deps (deg)
  const double eps_true = nut[0] * kDeg, eps_mean = nut[1] * kDeg, dpsi = nut[2] * kDeg;
  const double st_deg = mean_pole ? swe_sidtime0(jd_ut, nut[1], 0.0) * 15.0 : swe_sidtime(jd_ut) * 15.0;
  const double f = kSeEarthFlattening;
  const double cf = std::cos(loc.lat_deg * kDeg), sf = std::sin(loc.lat_deg * kDeg);
  const double cc = 1.0 / std::sqrt(cf * cf + (1 - f) * (1 - f) * sf * sf);
  const double ss = (1 - f) * (1 - f) * cc;
  const double lst = (loc.lon_deg + st_deg) * kDeg;
  const double h = loc.height_m;
  Vec3 r = {(kSeEarthRadiusM * cc + h) * cf * std::cos(lst), (kSeEarthRadiusM * cc + h) * cf * std::sin(lst),
            (kSeEarthRadiusM * ss + h) * sf};
  r = (1.0 / kAuM) * r;
  Vec3 v = cross(Vec3{0, 0, kSeEarthRotRadPerDay}, r);
  if (mean_pole) {
    // mean of date -> true of date: N = R1(-eps_true) R3(-dpsi) R1(eps_mean)
    r = rot1(rot3(rot1(r, eps_mean), -dpsi), -eps_true);
    v = rot1(rot3(rot1(v, eps_mean), -dpsi), -eps_true);
  }
  if (velocity_au_per_day) *velocity_au_per_day = v;
  return r;
}

// ------------------------------------------------------------------ self-checks

struct CheckLog {
  std::vector<std::string> lines;
  bool ok = true;
  void add(bool pass, const char* fmt, ...) __attribute__((format(printf, 3, 4)));
};
void CheckLog::add(bool pass, const char* fmt, ...) {
  char buf[1024];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  lines.push_back(std::string(pass ? "PASS " : "FAIL ") + buf);
  if (!pass) ok = false;
}

double hms(double h, double m, double s) { return (h + m / 60.0 + s / 3600.0) * 15.0; }
double dms(double sign, double d, double m, double s) { return sign * (d + m / 60.0 + s / 3600.0); }

// Published almanac-style values (J. Meeus, Astronomical Algorithms, 2nd ed.).
void check_meeus(CheckLog& log) {
  struct Ref {
    const char* label;
    int ipl;
    double jd_tt, ra_deg, dec_deg, tol_arcsec;
  };
  // Ex. 25.b (Sun from full VSOP87, FK5), Ex. 33.a (Venus, full VSOP87),
  // Ex. 47.a (Moon from a truncated ELP-2000/82: good to ~10" in longitude).
  const Ref refs[] = {
      {"Meeus ex. 25.b Sun 1992-10-13 0h TD", SE_SUN, 2448908.5, hms(13, 13, 30.749), dms(-1, 7, 47, 1.74), 1.0},
      {"Meeus ex. 33.a Venus 1992-12-20 0h TD", SE_VENUS, 2448976.5, hms(21, 4, 41.454), dms(-1, 18, 53, 16.84), 1.0},
      {"Meeus ex. 47.a Moon 1992-04-12 0h TD", SE_MOON, 2448724.5, 134.688470, 13.768368, 20.0},
  };
  for (const Ref& r : refs) {
    const Place p = calc(r.jd_tt, r.ipl, kFlagsGeo, r.label);
    const double sep = angle(from_radec(p.ra, p.dec, 1), from_radec(r.ra_deg, r.dec_deg, 1)) / kArcsec;
    log.add(sep <= r.tol_arcsec, "%s: SE RA %.6f Dec %.6f vs published RA %.6f Dec %.6f: %.3f\" (tolerance %.0f\")",
            r.label, p.ra, p.dec, r.ra_deg, r.dec_deg, sep, r.tol_arcsec);
  }
  // Illuminated fractions: Ex. 48.a Moon 1992-04-12 0h TD i = 69.0756 deg,
  // k = 0.6786 (low-precision lunar theory); Ex. 41.a Venus 1992-12-20 k = 0.647.
  struct Phase {
    const char* label;
    int ipl;
    double jd_tt, k, tol;
  };
  const Phase phases[] = {{"Meeus ex. 48.a Moon illuminated fraction", SE_MOON, 2448724.5, 0.6786, 0.002},
                          {"Meeus ex. 41.a Venus illuminated fraction", SE_VENUS, 2448976.5, 0.647, 0.002}};
  for (const Phase& ph : phases) {
    double attr[20];
    char serr[AS_MAXCH] = "";
    const int32 ret = swe_pheno(ph.jd_tt, ph.ipl, SEFLG_SWIEPH, attr, serr);
    check_ret(ret, serr, ph.label, ph.jd_tt);
    log.add(std::fabs(attr[1] - ph.k) <= ph.tol, "%s: SE k %.5f (phase angle %.4f deg) vs published %.4f", ph.label,
            attr[1], attr[0], ph.k);
  }
}

// Parallax and diurnal-aberration consistency over the table's instants.
void check_geometry(CheckLog& log, const std::vector<double>& jds) {
  double max_resid_mean_pole = 0, max_resid_true_pole = 0, max_ratio = 0, max_excess = -1e9, max_sep_moon = 0;
  double max_diurnal_resid = 0, max_diurnal = 0;
  for (double jd : jds) {
    for (const Location& loc : kLocations) {
      swe_set_topo(loc.lon_deg, loc.lat_deg, loc.height_m);
      for (int ipl : {SE_MOON, SE_SUN}) {
        // 1. Geometry without light-time/aberration (SEFLG_TRUEPOS): the
        //    topocentric vector must equal geocentric minus observer.
        const Place g = calc(jd, ipl, kFlagsGeo | SEFLG_TRUEPOS, "geometry check (geo)");
        const Place t = calc(jd, ipl, kFlagsTopo | SEFLG_TRUEPOS, "geometry check (topo)");
        const Vec3 gv = from_radec(g.ra, g.dec, g.dist), tv = from_radec(t.ra, t.dec, t.dist);
        const Vec3 obs_mean = observer_true_of_date(jd, loc, true, nullptr);
        const Vec3 obs_true = observer_true_of_date(jd, loc, false, nullptr);
        const double r_mean = angle(tv, gv - obs_mean) / kArcsec;
        const double r_true = angle(tv, gv - obs_true) / kArcsec;
        if (r_mean > max_resid_mean_pole) max_resid_mean_pole = r_mean;
        if (r_true > max_resid_true_pole) max_resid_true_pole = r_true;
        if (ipl == SE_MOON) {
          // Apparent places: topo-geo separation vs horizontal parallax.
          const Place ga = calc(jd, ipl, kFlagsGeo, "parallax check (geo)");
          const Place ta = calc(jd, ipl, kFlagsTopo, "parallax check (topo)");
          const double sep = angle(from_radec(ga.ra, ga.dec, 1), from_radec(ta.ra, ta.dec, 1));
          const double rho = norm(obs_true) * kAuM;
          const double hp = std::asin(rho / (ga.dist * kAuM));  // parallax for this observer's geocentric distance
          if (sep / hp > max_ratio) max_ratio = sep / hp;
          if ((sep - hp) / kArcsec > max_excess) max_excess = (sep - hp) / kArcsec;
          if (sep > max_sep_moon) max_sep_moon = sep;
        } else {
          // 2. Diurnal aberration (Sun): (topo app - topo no-aberr) - (geo app -
          //    geo no-aberr) must equal v_obs/c projected perpendicular to the line of sight.
          const Place ga = calc(jd, ipl, kFlagsGeo, "aberration check");
          const Place gn = calc(jd, ipl, kFlagsGeo | SEFLG_NOABERR, "aberration check");
          const Place ta = calc(jd, ipl, kFlagsTopo, "aberration check");
          const Place tn = calc(jd, ipl, kFlagsTopo | SEFLG_NOABERR, "aberration check");
          const Vec3 uga = from_radec(ga.ra, ga.dec, 1), ugn = from_radec(gn.ra, gn.dec, 1);
          const Vec3 uta = from_radec(ta.ra, ta.dec, 1), utn = from_radec(tn.ra, tn.dec, 1);
          const Vec3 measured = (uta - utn) - (uga - ugn);
          Vec3 vobs;
          observer_true_of_date(jd, loc, true, &vobs);
          const Vec3 b = (1.0 / kCAuPerDay) * vobs;
          const Vec3 predicted = b - dot(b, utn) * utn;
          const double resid = norm(measured - predicted) / kArcsec;
          if (resid > max_diurnal_resid) max_diurnal_resid = resid;
          if (norm(predicted) / kArcsec > max_diurnal) max_diurnal = norm(predicted) / kArcsec;
        }
      }
    }
  }
  log.add(max_resid_mean_pole < 0.005,
          "geometry: topocentric = geocentric - observer (SE's model: mean pole, mean sidereal time), "
          "Sun and Moon, all instants x locations: max residual %.5f\"",
          max_resid_mean_pole);
  log.add(max_resid_true_pole < 0.5,
          "geometry: same with the observer on the true pole (CIP) and apparent sidereal time: max %.4f\" "
          "(SE neglects nutation for the observer's position; bounded by R_earth*|nutation| ~ 0.35 km)",
          max_resid_true_pole);
  // The apparent topo-geo separation of the Moon can exceed asin(rho/d) only by
  // the aberration/light-time differences (< 0.5").
  log.add(max_excess <= 0.5 && max_sep_moon / kArcsec > 0.9 * 3400.0,
          "parallax: Moon apparent |topo - geo| vs asin(rho/d) (rho = observer's distance from the geocentre): "
          "max ratio %.6f, max excess %.3f\"; largest topo-geo separation in the sample %.1f\" = %.2f'",
          max_ratio, max_excess, max_sep_moon / kArcsec, max_sep_moon / kArcsec / 60.0);
  log.add(max_diurnal_resid < 0.002,
          "diurnal aberration is included by SE: measured topo-minus-geo aberration vs v_obs/c: max residual "
          "%.5f\" (largest diurnal aberration in the sample %.3f\")",
          max_diurnal_resid, max_diurnal);
}

// ------------------------------------------------------------------ main

}  // namespace

int main(int argc, char** argv) {
  std::string ephe_path = "/usr/share/libswe/ephe";
  std::string out_path;
  int strata = 36;
  uint64_t seed = 20241215;
  bool self_check_only = false;
  CLI::App app{"make_ephemeris_reference: the Swiss Ephemeris reference table (docs/EPHEMERIS_REFERENCE.md)"};
  app.add_option("--ephe-path", ephe_path, "Directory with sepl_18.se1 and semo_18.se1")->check(CLI::ExistingDirectory);
  app.add_option("--out", out_path, "Output CSV (default: standard output)");
  app.add_option("--strata", strata, "Number of stratified pseudo-random instants")->check(CLI::Range(1, 1000000));
  app.add_option("--seed", seed, "Seed of the pseudo-random offsets");
  app.add_flag("--self-check-only", self_check_only, "Run the self-checks only, write no table");
  if (const auto exit_code = atmo::support::parse_command_line(app, argc, argv)) return *exit_code;

  swe_set_ephe_path(ephe_path.c_str());
  char version[AS_MAXCH];
  swe_version(version);

  // --- instants (TT)
  std::vector<double> jds;
  std::vector<std::string> jd_texts;
  const double jd_start = swe_julday(1900, 1, 1, 0.0, SE_GREG_CAL);
  const double jd_end = swe_julday(2101, 1, 1, 0.0, SE_GREG_CAL);  // exclusive: through 2100-12-31
  const double fixed[] = {
      swe_julday(1900, 1, 1, 0.0, SE_GREG_CAL),    // start of range
      2451545.0,                                   // J2000.0 = 2000-01-01T12:00 TT
      swe_julday(2024, 12, 15, 3.0, SE_GREG_CAL),  // 2024-12-15T03:00 TT
      swe_julday(2100, 12, 31, 12.0, SE_GREG_CAL), // end of range
  };
  for (double jd : fixed) jds.push_back(jd);
  uint64_t state = seed;
  const double width = (jd_end - jd_start) / strata;
  for (int k = 0; k < strata; ++k) {
    const double u = static_cast<double>(splitmix64(state) >> 11) * (1.0 / 9007199254740992.0);
    jds.push_back(jd_start + (k + u) * width);
  }
  std::vector<std::pair<double, std::string>> sorted;
  for (double jd : jds) {
    std::string text;
    const double c = canonical_jd(jd, &text);
    sorted.push_back({c, text});
  }
  std::sort(sorted.begin(), sorted.end());
  jds.clear();
  for (auto& p : sorted) {
    jds.push_back(p.first);
    jd_texts.push_back(p.second);
  }

  // --- self-checks
  CheckLog log;
  check_meeus(log);
  check_geometry(log, jds);

  // --- make sure the .se1 files were really used
  {
    double a, b;
    int de_pl = 0, de_mo = 0;
    const char* fpl = swe_get_current_file_data(0, &a, &b, &de_pl);
    const char* fmo = swe_get_current_file_data(1, &a, &b, &de_mo);
    const bool pl_ok = fpl && std::strstr(fpl, "sepl_18.se1") && de_pl == 431;
    const bool mo_ok = fmo && std::strstr(fmo, "semo_18.se1") && de_mo == 431;
    log.add(pl_ok && mo_ok, "ephemeris files in use: planets %s (DE%d), Moon %s (DE%d)", fpl ? fpl : "(none)", de_pl,
            fmo ? fmo : "(none)", de_mo);
  }
  for (const std::string& l : log.lines) std::fprintf(stderr, "self-check: %s\n", l.c_str());
  if (!log.ok) fail("a self-check failed");
  if (g_failed) return 1;
  if (self_check_only) return 0;

  // --- table
  FILE* out = stdout;
  if (!out_path.empty()) {
    out = std::fopen(out_path.c_str(), "w");
    if (!out) {
      fail("cannot open " + out_path);
      return 1;
    }
  }
  char models_short[AS_MAXCH * 4] = "", models[AS_MAXCH * 10] = "";
  swe_get_astro_models(models_short, models, SEFLG_SWIEPH);

  std::fprintf(out,
               "# Atmo ephemeris reference table: apparent places of Sun, Moon, Mercury, Venus, Mars, Jupiter, Saturn\n"
               "# generator: tools/ephemeris_reference/make_ephemeris_reference.cpp "
               "(--strata %d --seed %llu); see docs/EPHEMERIS_REFERENCE.md\n"
               "# Swiss Ephemeris version: %s (Debian libswe), data files: sepl_18.se1 and semo_18.se1 "
               "(Swiss Ephemeris compression of JPL DE431, 1800-2400), Debian swe-basic-data\n",
               strata, static_cast<unsigned long long>(seed), version);
  // SE's own model summary, one comment line per line.
  {
    std::string m = models;
    size_t pos = 0;
    while (pos < m.size()) {
      size_t nl = m.find('\n', pos);
      if (nl == std::string::npos) nl = m.size();
      std::string line = m.substr(pos, nl - pos);
      if (!line.empty() && line.rfind("swetest", 0) != 0 && line.find("-amod") == std::string::npos &&
          line.rfind("For list", 0) != 0)
        std::fprintf(out, "# SE model: %s\n", line.c_str());
      pos = nl + 1;
    }
  }
  std::fprintf(
      out,
      "# flags: geocentric = SEFLG_SWIEPH|SEFLG_EQUATORIAL; topocentric = SEFLG_SWIEPH|SEFLG_EQUATORIAL|"
      "SEFLG_TOPOCTR (swe_set_topo(lon, lat, height)); phenomena = swe_pheno(jd_tt, body, "
      "SEFLG_SWIEPH|SEFLG_TOPOCTR); every call's returned flag checked for SEFLG_SWIEPH (no Moshier fallback) and an "
      "empty error string\n"
      "# positions: APPARENT right ascension and declination referred to the TRUE EQUATOR AND EQUINOX OF DATE "
      "(equinox-based RA, not CIO-based): light-time, gravitational deflection by the Sun (planets), annual "
      "aberration (relativistic), frame bias, precession (Vondrak 2011), nutation (IAU 2000B). No refraction, no "
      "polar motion.\n"
      "# ERFA users: RA_equinox = RA_CIRS - eo, with eo (equation of the origins) from eraApco13/eraApci13/"
      "eraAtci13/eraEors\n"
      "# topocentric (ra_app_deg, dec_app_deg, distance_au): observer on SE's ellipsoid a = 6378136.6 m, "
      "f = 1/298.25642, height above the ellipsoid, geodetic latitude, east longitude; light-time from the observer; "
      "DIURNAL ABERRATION IS INCLUDED (SE aberrates with the observer's barycentric velocity, Earth's orbital plus "
      "rotational velocity; verified below). SE neglects polar motion and places the observer on the MEAN equator "
      "of date with the MEAN sidereal time (nutation neglected for the observer only): differs from a CIP-based "
      "observer by <= ~0.35 km, i.e. <= ~0.2\" for the Moon (measured below)\n"
      "# geocentric (geo_*): same apparent place seen from the geocentre; Moon without deflection (as SE does)\n"
      "# time: jd_tt is the input, Terrestrial Time Julian date (SE treats TT = TDB, < 2 ms). UT1 enters only "
      "through the topocentric observer's sidereal time: SE derives it as UT1 = jd_tt - delta_t_s/86400 with its OWN "
      "Delta T (Stephenson/Morrison/Hohenkerk 2016 + observed table + extrapolation; the value used is in the last "
      "column delta_t_s). A Delta T difference of 1 s rotates the observer by 15.04\" about the pole, i.e. moves it "
      "by 0.465 km*cos(lat); this moves the topocentric Moon by at most 0.465/356500 rad = 0.27\" (perigee, "
      "equator) per second of Delta T, the Sun by 0.0006\"/s, the planets less. Tests must use delta_t_s (or accept "
      "0.27\"/s times their own Delta T difference: predicted Delta T near 2100 differs between models by ~100 s, "
      "i.e. up to ~30\" for the topocentric Moon)\n"
      "# phenomena (topocentric, swe_pheno): phase_angle_deg = Sun-body-observer angle; illuminated_fraction = "
      "(1+cos(phase))/2; magnitude = SE's visual magnitude (planets: Mallama & Hilton 2018; Moon: Vreijs; Sun: "
      "-26.86 at 1 au in SE, scaled with distance); apparent_diameter_deg = SE's disc diameter from its equatorial "
      "radii (no oblateness, Saturn without rings). For the Sun the generator writes phase angle 0 and "
      "illuminated fraction 1 (SE leaves both 0)\n"
      "# units: degrees for angles, au (149597870700 m) for distances, metres for height, seconds for delta_t_s; "
      "ra in [0, 360)\n"
      "# locations: ");
  for (size_t i = 0; i < sizeof kLocations / sizeof kLocations[0]; ++i)
    std::fprintf(out, "%s%s (%.4f, %.4f, %.0f m)", i ? "; " : "", kLocations[i].name, kLocations[i].lat_deg,
                 kLocations[i].lon_deg, kLocations[i].height_m);
  std::fprintf(out,
               "\n# instants: %zu = 4 fixed (1900-01-01T00 TT, J2000.0, 2024-12-15T03:00 TT, 2100-12-31T12 TT) + %d "
               "stratified pseudo-random over 1900-01-01..2100-12-31 (one per %.1f-day stratum, splitmix64 seed "
               "%llu), rounded to 1e-6 day\n",
               jds.size(), strata, width, static_cast<unsigned long long>(seed));
  for (const std::string& l : log.lines) std::fprintf(out, "# self-check: %s\n", l.c_str());
  std::fprintf(out,
               "# license: computed with the Swiss Ephemeris (c) Astrodienst AG, Zurich, used under the GNU GPL "
               "version 2 or later (alternative: Swiss Ephemeris Professional License); JPL DE431 by NASA/JPL. The "
               "generated numbers are data for the Atmo tests; the generator is a standalone tool, not part of Atmo's "
               "build\n");
  std::fprintf(out,
               "body,jd_tt,latitude_deg,longitude_deg,height_m,ra_app_deg,dec_app_deg,distance_au,geo_ra_app_deg,"
               "geo_dec_app_deg,geo_distance_au,phase_angle_deg,illuminated_fraction,magnitude,apparent_diameter_deg,"
               "delta_t_s\n");

  size_t rows = 0;
  for (size_t k = 0; k < jds.size(); ++k) {
    const double jd = jds[k];
    const double delta_t_s = swe_deltat_ex(jd, SEFLG_SWIEPH, nullptr) * 86400.0;
    for (const Location& loc : kLocations) {
      swe_set_topo(loc.lon_deg, loc.lat_deg, loc.height_m);
      for (const Body& b : kBodies) {
        const Place topo = calc(jd, b.ipl, kFlagsTopo, b.name);
        const Place geo = calc(jd, b.ipl, kFlagsGeo, b.name);
        double attr[20];
        char serr[AS_MAXCH] = "";
        const int32 ret = swe_pheno(jd, b.ipl, kFlagsPheno, attr, serr);
        check_ret(ret, serr, "swe_pheno", jd, /*allow_venus_mag_warning=*/true);
        if (b.ipl == SE_SUN) {  // SE leaves phase angle and fraction 0 for the Sun
          attr[0] = 0.0;
          attr[1] = 1.0;
        }
        std::fprintf(out, "%s,%s,%.4f,%.4f,%.1f,%.9f,%.9f,%.12f,%.9f,%.9f,%.12f,%.6f,%.8f,%.4f,%.9f,%.4f\n", b.name,
                     jd_texts[k].c_str(), loc.lat_deg, loc.lon_deg, loc.height_m, norm360(topo.ra), topo.dec, topo.dist,
                     norm360(geo.ra), geo.dec, geo.dist, attr[0], attr[1], attr[4], attr[3], delta_t_s);
        ++rows;
      }
    }
  }
  if (out != stdout) std::fclose(out);
  std::fprintf(stderr, "make_ephemeris_reference: %zu rows (%zu instants x %zu locations x %zu bodies), SE %s%s\n", rows,
               jds.size(), sizeof kLocations / sizeof kLocations[0], sizeof kBodies / sizeof kBodies[0], version,
               g_failed ? " -- FAILED" : "");
  return g_failed ? 1 : 0;
}
