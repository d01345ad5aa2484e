/* atmo_geodetic.h — WGS84 for hosts: geodetic <-> ECEF and the east-north-up
 * frame of ATMO_WORLD_ENU, so that a host whose world is a local tangent plane
 * can hand the plugin its eye (AtmoFrameState wants ECEF or geodetic) without
 * writing its own geodesy. Header-only C99, no allocation, thread-safe (pure
 * functions). Degrees at this edge for latitude and longitude, metres for
 * everything else; ECEF axes: X to 0°N 0°E, Z to the North Pole.
 *
 * The ENU frame of ATMO_WORLD_ENU, exactly: its origin is the ECEF point of
 * world_origin_geodetic (latitude, longitude AND height: the tangent plane at
 * the origin's height, not at the ellipsoid); x points east, y north, z up
 * along the ellipsoid's normal at the origin (geodetic, not geocentric, up).
 * The frame is a plane: a point 10 km east at z = 0 lies ~7.8 m above the
 * ellipsoid's surface at the origin's height — use atmo_ecef_from_enu, never
 * add heights to z.
 *
 * Accuracy (tests/abi/geodetic_test.cpp, against GeographicLib):
 * from 10 km below the ellipsoid to 100 000 km up, poles included, both ways
 * agree to < 1e-7 m (measured 3e-8 and 5e-8 m: round-off at 1e8 m); the
 * Earth's centre maps to latitude 0, height -a. */
#ifndef ATMO_GEODETIC_H
#define ATMO_GEODETIC_H

#include <math.h>

#ifdef __cplusplus
extern "C" {
#endif

#define ATMO_WGS84_A_M 6378137.0                  /* semi-major axis, metres */
#define ATMO_WGS84_F (1.0 / 298.257223563)        /* flattening */
#define ATMO_DEG_PER_RAD 57.295779513082320876798
#define ATMO_RAD_PER_DEG 0.017453292519943295769237

/* (latitude deg, longitude deg, height m above the ellipsoid) -> ECEF metres. */
static inline void atmo_ecef_from_geodetic(const double geodetic[3], double ecef_m[3]) {
  const double e2 = ATMO_WGS84_F * (2.0 - ATMO_WGS84_F);
  const double lat = geodetic[0] * ATMO_RAD_PER_DEG, lon = geodetic[1] * ATMO_RAD_PER_DEG;
  const double sl = sin(lat), cl = cos(lat);
  const double n = ATMO_WGS84_A_M / sqrt(1.0 - e2 * sl * sl); /* prime-vertical radius */
  ecef_m[0] = (n + geodetic[2]) * cl * cos(lon);
  ecef_m[1] = (n + geodetic[2]) * cl * sin(lon);
  ecef_m[2] = (n * (1.0 - e2) + geodetic[2]) * sl;
}

/* ECEF metres -> (latitude deg, longitude deg, height m). Latitude by Newton's
 * method on the parametric form (converges in 2-3 steps everywhere; 6 are run,
 * no data-dependent loop), so the call is bounded. */
static inline void atmo_geodetic_from_ecef(const double ecef_m[3], double geodetic[3]) {
  const double a = ATMO_WGS84_A_M, f = ATMO_WGS84_F;
  const double b = a * (1.0 - f), e2 = f * (2.0 - f), half_pi = 1.5707963267948966192313;
  const double x = ecef_m[0], y = ecef_m[1], z = ecef_m[2];
  const double p = hypot(x, y);
  double lat, h;
  if (p < 1e-9 * a) { /* on the polar axis: latitude +-90 (or 0 at the centre) */
    lat = z > 0.0 ? half_pi : (z < 0.0 ? -half_pi : 0.0);
    h = z == 0.0 ? -a : fabs(z) - b;
  } else {
    /* Bowring's start, then Newton on the reduced latitude u of the foot point. */
    double u = atan2(z * a, p * b);
    for (int i = 0; i < 6; ++i) {
      const double su = sin(u), cu = cos(u);
      /* g: half the derivative of the squared distance to (a cos u, b sin u); dg: its derivative. */
      const double g = a * su * p - b * cu * z - (a * a - b * b) * su * cu;
      const double dg = a * cu * p + b * su * z - (a * a - b * b) * (cu * cu - su * su);
      if (dg == 0.0) break;
      u -= g / dg;
    }
    lat = atan2(a * sin(u), b * cos(u));
    const double sl = sin(lat), cl = cos(lat);
    const double n = a / sqrt(1.0 - e2 * sl * sl);
    /* The better-conditioned of the two height formulas for this latitude. */
    h = fabs(cl) > 0.5 ? p / cl - n : z / sl - n * (1.0 - e2);
  }
  geodetic[0] = lat * ATMO_DEG_PER_RAD;
  geodetic[1] = atan2(y, x) * ATMO_DEG_PER_RAD;
  geodetic[2] = h;
}

/* The ENU axes at an origin as unit vectors in ECEF (rows of ENU-from-ECEF). */
static inline void atmo_enu_axes(const double origin_geodetic[3], double east[3], double north[3],
                                 double up[3]) {
  const double lat = origin_geodetic[0] * ATMO_RAD_PER_DEG, lon = origin_geodetic[1] * ATMO_RAD_PER_DEG;
  const double sl = sin(lat), cl = cos(lat), so = sin(lon), co = cos(lon);
  east[0] = -so;       east[1] = co;        east[2] = 0.0;
  north[0] = -sl * co; north[1] = -sl * so; north[2] = cl;
  up[0] = cl * co;     up[1] = cl * so;     up[2] = sl;
}

/* A point in the ENU frame of ATMO_WORLD_ENU (metres) -> ECEF metres. */
static inline void atmo_ecef_from_enu(const double origin_geodetic[3], const double enu_m[3], double ecef_m[3]) {
  double e[3], n[3], u[3], o[3];
  atmo_enu_axes(origin_geodetic, e, n, u);
  atmo_ecef_from_geodetic(origin_geodetic, o);
  for (int i = 0; i < 3; ++i) ecef_m[i] = o[i] + e[i] * enu_m[0] + n[i] * enu_m[1] + u[i] * enu_m[2];
}

/* ECEF metres -> the ENU frame at the origin (metres). */
static inline void atmo_enu_from_ecef(const double origin_geodetic[3], const double ecef_m[3], double enu_m[3]) {
  double e[3], n[3], u[3], o[3], d[3];
  atmo_enu_axes(origin_geodetic, e, n, u);
  atmo_ecef_from_geodetic(origin_geodetic, o);
  for (int i = 0; i < 3; ++i) d[i] = ecef_m[i] - o[i];
  enu_m[0] = e[0] * d[0] + e[1] * d[1] + e[2] * d[2];
  enu_m[1] = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
  enu_m[2] = u[0] * d[0] + u[1] * d[1] + u[2] * d[2];
}

/* A point in the ENU frame -> (latitude deg, longitude deg, height m): what
 * AtmoFrameState.eye_geodetic takes for a host whose camera lives in ENU. */
static inline void atmo_geodetic_from_enu(const double origin_geodetic[3], const double enu_m[3],
                                          double geodetic[3]) {
  double ecef[3];
  atmo_ecef_from_enu(origin_geodetic, enu_m, ecef);
  atmo_geodetic_from_ecef(ecef, geodetic);
}

#ifdef __cplusplus
}
#endif

#endif /* ATMO_GEODETIC_H */
