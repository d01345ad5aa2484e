#include "core/night_sky/point_sources.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/astro/observer.h"
#include "core/night_sky/star_photometry.h"

namespace atmo::core::night {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kHalfPi = 0.5 * kPi;
// Above this unrefracted elevation the refraction model is ERFA's A tan z +
// B tan^3 z alone (core/astro/refraction.cpp blends below it).
const double kSinErfaOnly = std::sin(15.0 * kPi / 180.0);
// The Earth's rotation rate as ERFA's eraPvtob uses it (ERFA_OM, rad/s) and
// the speed of light (m/s).
constexpr double kEarthRotationRadPerS = 1.00273781191135448 * 2.0 * kPi / 86400.0;
constexpr double kSpeedOfLightMPerS = 299792458.0;

// First-order aberration of unit vector p by velocity beta (v/c), renormalised:
// p + beta - (p . beta) p, as eraAb to first order.
glm::dvec3 aberrate(const glm::dvec3& p, const glm::dvec3& beta) {
  return glm::normalize(p + beta - glm::dot(p, beta) * p);
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

double planet_b_minus_v(astro::Body body) {
  switch (body) {
    case astro::Body::kMercury: return 0.93;
    case astro::Body::kVenus: return 0.82;
    case astro::Body::kMars: return 1.36;
    case astro::Body::kJupiter: return 0.83;
    case astro::Body::kSaturn: return 1.04;
    default: return std::numeric_limits<double>::quiet_NaN();
  }
}

glm::dvec3 planet_rgb(astro::Body body) {
  const double bv = planet_b_minus_v(body);
  return std::isfinite(bv) ? star_rgb_from_bv(bv) : glm::dvec3(std::numeric_limits<double>::quiet_NaN());
}

double horizon_dip_rad(double height_m, double radius_m) {
  const double h = std::isfinite(height_m) ? std::max(height_m, 0.0) : 0.0;
  if (!(radius_m > 0.0)) return 0.0;
  return std::acos(std::clamp(radius_m / (radius_m + h), 0.0, 1.0));
}

// --- StarField -----------------------------------------------------------------

StarField::StarField(const std::vector<astro::CatalogStar>& catalog) {
  std::vector<std::size_t> order(catalog.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return catalog[a].v_mag < catalog[b].v_mag; });
  stars_.reserve(catalog.size());
  v_sorted_.reserve(catalog.size());
  for (std::size_t k : order) {
    const astro::CatalogStar& c = catalog[k];
    Star s;
    s.astrometry = astro::star_astrometry(c);
    s.v_mag = static_cast<float>(c.v_mag);
    s.illuminance_rgb_lux = glm::vec3(illuminance_from_magnitude(c.v_mag) * star_rgb_from_bv(c.b_minus_v));
    s.hd = c.hd;
    s.kstars_line = c.kstars_line;
    stars_.push_back(s);
    v_sorted_.push_back(s.v_mag);
  }
}

std::size_t StarField::count_brighter_than(double v_limit) const {
  if (std::isnan(v_limit)) return 0;
  if (v_limit >= static_cast<double>(std::numeric_limits<float>::max())) return v_sorted_.size();
  if (v_limit <= -static_cast<double>(std::numeric_limits<float>::max())) return 0;
  // V <= limit, compared as the stored floats are.
  const auto end = std::upper_bound(v_sorted_.begin(), v_sorted_.end(), static_cast<float>(v_limit));
  return static_cast<std::size_t>(end - v_sorted_.begin());
}

bool StarField::update(const astro::AstrometryFrame& frame, double max_age_days) {
  update_planets(frame);
  const double tt = frame.time().tt.value();
  if (cache_valid_ && std::abs(tt - cache_tt_jd_) <= max_age_days) return false;
  // The diurnal aberration of this frame, in CIRS, to take out of the cache.
  const StarFrameTransform t = star_frame_transform(frame);
  const glm::dvec3 beta_cirs = glm::transpose(t.enu_from_cirs) * t.diurnal_beta_enu;
  for (Star& s : stars_) {
    const glm::dvec3 c = frame.star_cirs(s.astrometry);
    const glm::dvec3 without = aberrate(c, -beta_cirs);
    s.cirs = finite(without) ? without : glm::dvec3(1.0, 0.0, 0.0);
  }
  cache_valid_ = true;
  cache_tt_jd_ = tt;
  ++cache_computations_;
  return true;
}

namespace {
constexpr astro::Body kPlanets[StarField::kPlanetCount] = {astro::Body::kMercury, astro::Body::kVenus,
                                                           astro::Body::kMars, astro::Body::kJupiter,
                                                           astro::Body::kSaturn};
constexpr double kSecondsPerDay = 86400.0;
}  // namespace

int StarField::update_planets(const astro::AstrometryFrame& frame) {
  const double tt = frame.time().tt.value();
  const glm::dvec3 eye = astro::observer_ecef(frame.observer());
  const bool moved = !planets_valid_ || !(glm::length(eye - planets_eye_ecef_m_) <= kPlanetMaxMoveM);
  // Ages in seconds; a planet is recomputed when stale, and at most one more when past half its life.
  bool refresh[kPlanetCount] = {};
  int stalest_half = -1;
  double stalest_age = 0.0;
  for (int k = 0; k < kPlanetCount; ++k) {
    const double age = std::abs(tt - planets_[k].tt_jd) * kSecondsPerDay;
    if (moved || !(age <= kPlanetMaxAgeS)) {
      refresh[k] = true;
    } else if (age > 0.5 * kPlanetMaxAgeS && age > stalest_age) {
      stalest_half = k;
      stalest_age = age;
    }
  }
  if (stalest_half >= 0) refresh[stalest_half] = true;
  int count = 0;
  StarFrameTransform t;
  bool have_transform = false;
  for (int k = 0; k < kPlanetCount; ++k) {
    if (!refresh[k]) continue;
    if (!have_transform) {
      t = star_frame_transform(frame);
      have_transform = true;
    }
    const astro::BodyEphemeris e = frame.body(kPlanets[k]);
    const double cd = std::cos(e.direction.dec_rad);
    const glm::dvec3 c(cd * std::cos(e.direction.ra_cirs_rad), cd * std::sin(e.direction.ra_cirs_rad),
                       std::sin(e.direction.dec_rad));
    const glm::dvec3 beta_cirs = glm::transpose(t.enu_from_cirs) * t.diurnal_beta_enu;
    const glm::dvec3 without = aberrate(c, -beta_cirs);
    Planet& p = planets_[k];
    p.cirs = finite(without) ? without : glm::dvec3(1.0, 0.0, 0.0);
    p.tt_jd = tt;
    p.v_mag = static_cast<float>(e.apparent_magnitude);
    p.illuminance_rgb_lux = glm::vec3(illuminance_from_magnitude(e.apparent_magnitude) * planet_rgb(kPlanets[k]));
    ++count;
  }
  if (moved) planets_eye_ecef_m_ = eye;
  planets_valid_ = true;
  planet_computations_ += static_cast<uint64_t>(count);
  return count;
}

bool StarField::cached_planet(const StarFrameTransform& t, int k, PointSource* out) const {
  if (!planets_valid_ || k < 0 || k >= kPlanetCount) return false;
  const Planet& p = planets_[k];
  const glm::dvec3 d = refract_enu(t, aberrate(t.enu_from_cirs * p.cirs, t.diurnal_beta_enu));
  out->direction_enu = glm::vec3(d);
  out->illuminance_rgb_lux = p.illuminance_rgb_lux;
  out->v_mag = p.v_mag;
  return true;
}

StarFrameTransform star_frame_transform(const astro::AstrometryFrame& frame) {
  StarFrameTransform t;
  t.enu_from_cirs = frame.enu_from_cirs();
  // eraPvtob: the observer moves at omega x r, due east, |v| = omega * distance from the axis.
  const glm::dvec3 ecef = astro::observer_ecef(frame.observer());
  const double axis_distance_m = std::sqrt(ecef.x * ecef.x + ecef.y * ecef.y);
  t.diurnal_beta_enu = glm::dvec3(kEarthRotationRadPerS * axis_distance_m / kSpeedOfLightMPerS, 0.0, 0.0);
  if (!finite(t.diurnal_beta_enu)) t.diurnal_beta_enu = glm::dvec3(0.0);
  t.refraction = frame.refraction_enabled();
  t.refraction_model = t.refraction ? astro::make_refraction_model(frame.conditions(), frame.observer().height_m)
                                    : astro::no_refraction();
  return t;
}

glm::dvec3 refract_enu(const StarFrameTransform& t, const glm::dvec3& d) {
  if (!t.refraction) return d;
  const double z = std::clamp(d.z, -1.0, 1.0);
  const double h = std::sqrt(d.x * d.x + d.y * d.y);
  double sin_r = 0.0, cos_r = 0.0;  // sine and cosine of the refracted elevation
  if (z >= kSinErfaOnly) {
    // astro::refraction_erfa_rad with sin e = z, cos e = h (no trigonometry),
    // then e + R by the angle-sum formulas (R < 4': the series are exact to 1e-16).
    const double sin_e = std::max(z, 0.05);
    const double cos_e = std::max(h, 1e-6);
    const double tz = cos_e / sin_e;
    const double w = t.refraction_model.refb * tz * tz;
    const double r = (t.refraction_model.refa + w) * tz / (1.0 + (t.refraction_model.refa + 3.0 * w) / (sin_e * sin_e));
    const double r2 = r * r;
    const double sr = r * (1.0 - r2 / 6.0);
    const double cr = 1.0 - 0.5 * r2 * (1.0 - r2 / 12.0);
    sin_r = z * cr + h * sr;
    cos_r = h * cr - z * sr;
    if (cos_r <= 0.0) return glm::dvec3(0.0, 0.0, 1.0);  // past the zenith: held there, as direction_from_cirs
  } else {
    const double e = std::asin(z);
    const double r = astro::refraction_rad(t.refraction_model, e);
    if (r == 0.0) return d;
    const double e_r = std::min(e + r, kHalfPi);
    sin_r = std::sin(e_r);
    cos_r = std::cos(e_r);
  }
  if (!(h > 0.0)) return d;
  const double scale = cos_r / h;
  return glm::dvec3(d.x * scale, d.y * scale, sin_r);
}

glm::dvec3 StarField::direction_enu(const StarFrameTransform& t, std::size_t i, glm::dvec3* refracted) const {
  const glm::dvec3 d = aberrate(t.enu_from_cirs * stars_[i].cirs, t.diurnal_beta_enu);
  if (refracted) *refracted = refract_enu(t, d);
  return d;
}

// --- The frame's list ------------------------------------------------------------

void visible_point_sources(const StarField& stars, const astro::AstrometryFrame& frame, const PointSourceCut& cut,
                           const std::array<astro::BodyEphemeris, astro::kBodyCount>* bodies,
                           std::vector<PointSource>* out) {
  out->clear();
  if (std::isnan(cut.limiting_magnitude)) return;
  const double dip = horizon_dip_rad(frame.observer().height_m, cut.earth_radius_m);
  const double min_elevation = -(dip + std::max(cut.horizon_margin_rad, 0.0));
  const double min_sin = std::sin(std::max(min_elevation, -kHalfPi));

  if (cut.stars && stars.cache_valid()) {
    const std::size_t n = stars.count_brighter_than(cut.limiting_magnitude);
    const StarFrameTransform t = star_frame_transform(frame);
    // Refraction only raises a source (by < 0.6° at the horizon, less from
    // altitude, and it is held finite below): a star whose unrefracted
    // elevation is more than 1° below the cut cannot pass it.
    const double reject_sin = std::sin(std::max(min_elevation - kPi / 180.0, -kHalfPi));
    for (std::size_t i = 0; i < n; ++i) {
      const glm::dvec3 d = stars.direction_enu(t, i);
      if (d.z < reject_sin) continue;
      const glm::dvec3 r = refract_enu(t, d);
      if (!(r.z > min_sin)) continue;
      PointSource p;
      p.direction_enu = glm::vec3(r);
      p.illuminance_rgb_lux = stars.illuminance_rgb_lux(i);
      p.v_mag = stars.v_mag(i);
      out->push_back(p);
    }
  }

  if (cut.planets) {
    const bool from_cache = bodies == nullptr && stars.planets_valid();
    const StarFrameTransform t = from_cache ? star_frame_transform(frame) : StarFrameTransform{};
    for (int k = 0; k < StarField::kPlanetCount; ++k) {
      PointSource p;
      if (from_cache) {
        stars.cached_planet(t, k, &p);
        if (!(p.v_mag <= cut.limiting_magnitude) || !(p.direction_enu.z > min_sin)) continue;
      } else {
        const astro::BodyEphemeris e = bodies ? (*bodies)[static_cast<int>(kPlanets[k])] : frame.body(kPlanets[k]);
        if (!std::isfinite(e.apparent_magnitude) || e.apparent_magnitude > cut.limiting_magnitude) continue;
        if (!finite(e.direction.enu) || !(e.direction.enu.z > min_sin)) continue;
        p.direction_enu = glm::vec3(glm::normalize(e.direction.enu));
        p.illuminance_rgb_lux =
            glm::vec3(illuminance_from_magnitude(e.apparent_magnitude) * planet_rgb(kPlanets[k]));
        p.v_mag = static_cast<float>(e.apparent_magnitude);
      }
      out->push_back(p);
    }
  }
}

void visible_point_sources(StarField& stars, const astro::AstrometryFrame& frame, const PointSourceCut& cut,
                           const std::array<astro::BodyEphemeris, astro::kBodyCount>* bodies,
                           std::vector<PointSource>* out) {
  if (cut.stars) stars.update(frame);
  else if (cut.planets && bodies == nullptr) stars.update_planets(frame);
  visible_point_sources(static_cast<const StarField&>(stars), frame, cut, bodies, out);
}

std::vector<PointSource> visible_point_sources(StarField& stars, const astro::AstrometryFrame& frame,
                                               const PointSourceCut& cut,
                                               const std::array<astro::BodyEphemeris, astro::kBodyCount>* bodies) {
  std::vector<PointSource> out;
  visible_point_sources(stars, frame, cut, bodies, &out);
  return out;
}

}  // namespace atmo::core::night
