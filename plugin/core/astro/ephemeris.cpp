#include "core/astro/ephemeris.h"

#include <erfa.h>
#include <erfam.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/astro/photometry.h"

namespace atmo::core::astro {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMaxPolarMotionRad = 1.0 * ERFA_DAS2R;  // IERS values stay below 1"

double wrap_2pi(double a) {
  a = std::fmod(a, 2.0 * kPi);
  return a < 0.0 ? a + 2.0 * kPi : a;
}
double wrap_pi(double a) {
  a = wrap_2pi(a);
  return a > kPi ? a - 2.0 * kPi : a;
}

glm::dvec3 to_glm(const double p[3]) { return {p[0], p[1], p[2]}; }
void to_c(const glm::dvec3& v, double p[3]) {
  p[0] = v.x;
  p[1] = v.y;
  p[2] = v.z;
}

// Position angle of direction b on the disc at m, from reference direction r,
// through "east" (counterclockwise as the observer sees the sky): the angle
// from r's component across the line of sight to b's, about -m.
double position_angle(const glm::dvec3& m, const glm::dvec3& r, const glm::dvec3& b) {
  const glm::dvec3 rxm = glm::cross(r, m);
  const double y = glm::dot(b, rxm);
  const double x = glm::dot(b, r) - glm::dot(r, m) * glm::dot(b, m);
  return (x == 0.0 && y == 0.0) ? 0.0 : std::atan2(y, x);
}

}  // namespace

struct AstrometryFrame::Impl {
  TimeScales time;
  Observer observer;
  RefractionConditions conditions;
  RefractionModel refraction;
  bool refraction_enabled = true;
  eraASTROM astrom{};
  double eo = 0.0;
  double era = 0.0;
  EarthSun earth_sun;
  glm::dmat3 enu_from_cirs{1.0};
  glm::dvec3 pole_enu{0.0, 0.0, 1.0};
  std::string notes;

  // Barycentric position (au) of a body at tt + dt_days.
  glm::dvec3 barycentric(Body b, double dt_days) const {
    const glm::dvec3 sun = earth_sun.sun_barycentric_au + earth_sun.sun_barycentric_velocity_au_d * dt_days;
    switch (b) {
      case Body::kSun: return sun;
      case Body::kMoon: return glm::dvec3(0.0);  // handled by the caller (needs the Moon's state)
      default: return sun + planet_heliocentric_au(b, JulianDate{time.tt.jd1, time.tt.jd2 + dt_days});
    }
  }
};

std::optional<AstrometryFrame> AstrometryFrame::create(const TimeScales& time, const Observer& observer,
                                                       const EphemerisOptions& options, std::string* error) {
  if (!std::isfinite(options.polar_motion_x_rad) || !std::isfinite(options.polar_motion_y_rad) ||
      std::fabs(options.polar_motion_x_rad) > kMaxPolarMotionRad ||
      std::fabs(options.polar_motion_y_rad) > kMaxPolarMotionRad) {
    if (error) *error = "polar motion must be finite and within 1 arcsecond";
    return std::nullopt;
  }
  if (!std::isfinite(observer.latitude_rad) || !std::isfinite(observer.longitude_rad) ||
      !std::isfinite(observer.height_m) || std::fabs(observer.latitude_rad) > 0.5 * kPi + 1e-12) {
    if (error) *error = "observer position is not finite";
    return std::nullopt;
  }
  if (!std::isfinite(time.tt.value()) || !std::isfinite(time.ut1.value())) {
    if (error) *error = "time scales are not finite";
    return std::nullopt;
  }
  auto impl = std::make_shared<Impl>();
  impl->time = time;
  impl->observer = observer;
  impl->conditions = options.conditions ? *options.conditions : standard_refraction_conditions(observer.height_m);
  if (auto why = validate(impl->conditions)) {
    if (error) *error = "refraction conditions: " + *why;
    return std::nullopt;
  }
  impl->refraction_enabled = options.refraction;
  impl->refraction = options.refraction ? make_refraction_model(impl->conditions, observer.height_m) : no_refraction();

  // The astrometry context, as eraApco13 builds it but from our TT and UT1
  // (so dates before UTC and a user Delta T work), refraction left out (ours
  // is applied after).
  const double tt1 = time.tt.jd1, tt2 = time.tt.jd2;
  double ehpv[2][3], ebpv[2][3], rnpb[3][3];
  const bool epv_in_range = eraEpv00(tt1, tt2, ehpv, ebpv) == 0;
  eraPnm06a(tt1, tt2, rnpb);
  double x = 0.0, y = 0.0;
  eraBpn2xy(rnpb, &x, &y);
  const double s = eraS06(tt1, tt2, x, y);
  impl->era = eraEra00(time.ut1.jd1, time.ut1.jd2);
  const double sp = eraSp00(tt1, tt2);
  eraApco(tt1, tt2, ebpv, ehpv[0], x, y, s, impl->era, observer.longitude_rad, observer.latitude_rad,
          observer.height_m, options.polar_motion_x_rad, options.polar_motion_y_rad, sp, 0.0, 0.0, &impl->astrom);
  impl->eo = eraEors(rnpb, s);
  impl->earth_sun = earth_and_sun(time.tt);

  // CIRS -> ENU: the images of the three CIRS axes through eraAtioq (no
  // refraction in the context, and no separate diurnal aberration: eraApco
  // puts it in the observer's velocity), so the rotation is exactly ERFA's.
  const double axes[3][2] = {{0.0, 0.0}, {0.5 * kPi, 0.0}, {0.0, 0.5 * kPi}};
  for (int i = 0; i < 3; ++i) {
    double aob, zob, hob, dob, rob;
    eraAtioq(axes[i][0], axes[i][1], &impl->astrom, &aob, &zob, &hob, &dob, &rob);
    impl->enu_from_cirs[i] = glm::dvec3(std::sin(zob) * std::sin(aob), std::sin(zob) * std::cos(aob), std::cos(zob));
  }
  impl->pole_enu = impl->enu_from_cirs[2];

  impl->notes = time.note;
  if (!epv_in_range) {
    if (!impl->notes.empty()) impl->notes += "; ";
    impl->notes += "eraEpv00 outside 1900-2100: Earth's position degrades";
  }
  return AstrometryFrame(std::move(impl));
}

const TimeScales& AstrometryFrame::time() const { return impl_->time; }
const Observer& AstrometryFrame::observer() const { return impl_->observer; }
const RefractionConditions& AstrometryFrame::conditions() const { return impl_->conditions; }
bool AstrometryFrame::refraction_enabled() const { return impl_->refraction_enabled; }
double AstrometryFrame::equation_of_origins_rad() const { return impl_->eo; }
double AstrometryFrame::earth_rotation_angle_rad() const { return impl_->era; }
const std::string& AstrometryFrame::notes() const { return impl_->notes; }
glm::dmat3 AstrometryFrame::enu_from_cirs() const { return impl_->enu_from_cirs; }

double AstrometryFrame::refraction_rad(double e) const {
  return impl_->refraction_enabled ? astro::refraction_rad(impl_->refraction, e) : 0.0;
}

SkyDirection AstrometryFrame::direction_from_cirs(const glm::dvec3& c_in) const {
  const double len = glm::length(c_in);
  const glm::dvec3 c = len > 0.0 && std::isfinite(len) ? c_in / len : glm::dvec3(1.0, 0.0, 0.0);
  SkyDirection d;
  d.ra_cirs_rad = wrap_2pi(std::atan2(c.y, c.x));
  d.dec_rad = std::asin(std::clamp(c.z, -1.0, 1.0));
  d.ra_equinox_rad = wrap_2pi(d.ra_cirs_rad - impl_->eo);
  d.hour_angle_rad = wrap_pi(impl_->astrom.eral - d.ra_cirs_rad);

  glm::dvec3 enu = impl_->enu_from_cirs * c;
  enu /= glm::length(enu);
  d.enu_unrefracted = enu;
  d.elevation_rad = std::asin(std::clamp(enu.z, -1.0, 1.0));
  d.azimuth_rad = (enu.x == 0.0 && enu.y == 0.0) ? 0.0 : wrap_2pi(std::atan2(enu.x, enu.y));
  d.elevation_refracted_rad = std::min(d.elevation_rad + refraction_rad(d.elevation_rad), 0.5 * kPi);
  if (d.elevation_refracted_rad == d.elevation_rad) {
    d.enu = enu;
  } else {
    const double ce = std::cos(d.elevation_refracted_rad);
    d.enu = glm::dvec3(ce * std::sin(d.azimuth_rad), ce * std::cos(d.azimuth_rad), std::sin(d.elevation_refracted_rad));
  }
  return d;
}

glm::dvec3 AstrometryFrame::star_cirs(const StarAstrometry& s) const {
  eraASTROM astrom = impl_->astrom;
  double ri = 0.0, di = 0.0, c[3];
  eraAtciq(s.ra_rad, s.dec_rad, s.pm_ra_rad_per_year, s.pm_dec_rad_per_year, s.parallax_arcsec,
           s.radial_velocity_km_s, &astrom, &ri, &di);
  eraS2c(ri, di, c);
  return to_glm(c);
}

SkyDirection AstrometryFrame::star(const StarAstrometry& s) const { return direction_from_cirs(star_cirs(s)); }

void AstrometryFrame::stars(const StarAstrometry* s, std::size_t n, SkyDirection* out) const {
  eraASTROM astrom = impl_->astrom;
  for (std::size_t i = 0; i < n; ++i) {
    double ri = 0.0, di = 0.0, c[3];
    eraAtciq(s[i].ra_rad, s[i].dec_rad, s[i].pm_ra_rad_per_year, s[i].pm_dec_rad_per_year, s[i].parallax_arcsec,
             s[i].radial_velocity_km_s, &astrom, &ri, &di);
    eraS2c(ri, di, c);
    out[i] = direction_from_cirs(to_glm(c));
  }
}

BodyEphemeris AstrometryFrame::body(Body b) const {
  const Impl& f = *impl_;
  const glm::dvec3 observer = to_glm(f.astrom.eb);
  const EarthSun& es = f.earth_sun;

  // Moon: ELP at t, moved back over the light time with its velocity (and the
  // Earth's), so one ELP evaluation serves.
  glm::dvec3 moon_geo(0.0), moon_vel(0.0);
  if (b == Body::kMoon) {
    moon_geo = moon_geocentric_au(f.time.tt);
    moon_vel = moon_geocentric_velocity_au_d(f.time.tt);
  }
  auto position_at = [&](double dt_days) -> glm::dvec3 {
    if (b == Body::kMoon) {
      return es.earth_barycentric_au + es.earth_barycentric_velocity_au_d * dt_days + moon_geo + moon_vel * dt_days;
    }
    return f.barycentric(b, dt_days);
  };

  // Light time from the observer: two passes reach ~1e-4 s for the planets.
  glm::dvec3 body_bary = position_at(0.0);
  double tau_days = glm::length(body_bary - observer) * ERFA_AULT / ERFA_DAYSEC;
  const int passes = b == Body::kMoon || b == Body::kSun ? 3 : 2;
  for (int i = 0; i < passes; ++i) {
    body_bary = position_at(-tau_days);
    tau_days = glm::length(body_bary - observer) * ERFA_AULT / ERFA_DAYSEC;
  }
  const glm::dvec3 sun_bary =
      es.sun_barycentric_au - es.sun_barycentric_velocity_au_d * tau_days;  // the Sun at emission
  const glm::dvec3 q = body_bary - observer;
  const double distance_au = glm::length(q);

  // Deflection by the Sun (not for the Sun itself), aberration, BPN.
  double p[3], p1[3], p2[3], c[3];
  to_c(q / distance_au, p);
  if (b != Body::kSun) {
    double qs[3], e[3];
    to_c(glm::normalize(body_bary - sun_bary), qs);
    for (int i = 0; i < 3; ++i) e[i] = f.astrom.eh[i];
    const double em2 = std::max(f.astrom.em * f.astrom.em, 1.0);
    eraLd(1.0, p, qs, e, f.astrom.em, 1e-6 / em2, p1);
  } else {
    for (int i = 0; i < 3; ++i) p1[i] = p[i];
  }
  double v[3], bpn[3][3];
  for (int i = 0; i < 3; ++i) v[i] = f.astrom.v[i];
  eraAb(p1, v, f.astrom.em, f.astrom.bm1, p2);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) bpn[i][j] = f.astrom.bpn[i][j];
  eraRxp(bpn, p2, c);

  BodyEphemeris out;
  out.body = b;
  out.direction = direction_from_cirs(to_glm(c));
  out.distance_m = distance_au * ERFA_DAU;
  out.light_time_s = tau_days * ERFA_DAYSEC;
  out.angular_radius_rad = std::asin(std::min(1.0, body_radius_m(b) / std::max(out.distance_m, 1.0)));

  if (b == Body::kSun) {
    out.sun_distance_m = 0.0;
    out.phase_angle_rad = 0.0;
    out.illuminated_fraction = 1.0;
    out.apparent_magnitude = apparent_magnitude(b, 0.0, distance_au, 0.0);
    out.bright_limb_enu = glm::dvec3(0.0, 0.0, 1.0);
    return out;
  }

  const glm::dvec3 to_sun = sun_bary - body_bary;
  const double r_au = glm::length(to_sun);
  double a[3], bb[3];
  to_c(to_sun, a);
  to_c(-q, bb);
  out.sun_distance_m = r_au * ERFA_DAU;
  out.phase_angle_rad = eraSepp(a, bb);
  out.illuminated_fraction = illuminated_fraction(out.phase_angle_rad);
  if (b == Body::kSaturn) {
    const glm::dvec3 pole = saturn_pole_icrs(f.time.tt);
    out.saturn_ring_tilt_rad = std::asin(std::clamp(-glm::dot(q / distance_au, pole), -1.0, 1.0));
  }
  out.apparent_magnitude =
      apparent_magnitude(b, r_au, distance_au, out.phase_angle_rad, out.saturn_ring_tilt_rad);

  // Orientation: vectors in ENU (unrefracted) — body m, Sun s, celestial pole
  // n, zenith u. chi and q as position angles from north; chi - q from up.
  const glm::dvec3 m = out.direction.enu_unrefracted;
  const glm::dvec3 sdir = body(Body::kSun).direction.enu_unrefracted;
  const glm::dvec3 n = f.pole_enu;
  const glm::dvec3 up(0.0, 0.0, 1.0);
  out.bright_limb_position_angle_rad = wrap_2pi(position_angle(m, n, sdir));
  out.parallactic_angle_rad = position_angle(m, n, up);
  out.bright_limb_zenith_angle_rad = wrap_2pi(out.bright_limb_position_angle_rad - out.parallactic_angle_rad);
  glm::dvec3 across = sdir - glm::dot(sdir, m) * m;
  if (glm::length(across) < 1e-12) across = up - glm::dot(up, m) * m;  // exactly full or new: any
  if (glm::length(across) < 1e-12) across = glm::dvec3(0.0, 1.0, 0.0);  // and at the zenith
  out.bright_limb_enu = glm::normalize(across);
  return out;
}

std::array<BodyEphemeris, kBodyCount> AstrometryFrame::bodies() const {
  std::array<BodyEphemeris, kBodyCount> out;
  for (int i = 0; i < kBodyCount; ++i) out[i] = body(static_cast<Body>(i));
  return out;
}

}  // namespace atmo::core::astro
