// point_sources.h — the stars and planets the night-sky pass draws as points
// this frame: their apparent (refracted) directions in east-north-up at the
// eye, their illuminance outside the atmosphere (linear sRGB, lux) and their
// V magnitude, cut at the horizon and at a limiting magnitude. Pure (no GL):
// the GL layer (plugin/gl/night_renderer.h) projects, dims by the
// atmosphere's transmittance and draws them. docs/NIGHT_SKY.md, "Rendering:
// point sources".
//
// Cost: a star's CIRS direction (ERFA's eraAtciq: proper motion, light
// deflection, aberration, precession-nutation; ~0.2 µs) is cached and
// recomputed only when Terrestrial Time moved by more than
// StarField::kMaxCacheAgeDays; every frame only rotates the cached vectors to
// ENU (the Earth's rotation), adds the diurnal aberration and the refraction,
// for the stars brighter than the limiting magnitude (the catalogue is sorted
// by V, so the cut is a prefix). The planets are cached for seconds. About
// 0.25 ms a frame for 5000 sources. Measured figures:
// tests/core/point_sources_test.cpp.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/astro/ephemeris.h"
#include "core/astro/star_catalog.h"

namespace atmo::core::night {

// One point of light. Laid out for a GL vertex buffer (28 bytes, no padding):
// the night renderer uploads an array of these as is.
struct PointSource {
  glm::vec3 direction_enu{0.0f, 0.0f, 1.0f};  // unit vector, ENU at the eye, as seen through the air (refracted)
  glm::vec3 illuminance_rgb_lux{0.0f};         // outside the atmosphere, linear sRGB, lux (E_v · colour)
  float v_mag = 0.0f;                          // V magnitude outside the atmosphere
};
static_assert(sizeof(PointSource) == 7 * sizeof(float), "PointSource is uploaded as 7 tightly packed floats");

// The colour of a planet: its mean B−V (reflected sunlight reddened by the
// planet's albedo spectrum), as tabulated in Allen's Astrophysical Quantities
// (4th ed., Cox 2000) — Mercury 0.93, Venus 0.82, Mars 1.36, Jupiter 0.83,
// Saturn 1.04 — turned into linear sRGB by the stars' own B−V → temperature →
// black-body chain (star_rgb_from_bv), normalised to luminance 1. NaN for a
// body that is not one of the five planets.
double planet_b_minus_v(astro::Body body);
glm::dvec3 planet_rgb(astro::Body body);

// The horizon cut: a source is kept when its refracted elevation exceeds
// -(dip + margin), dip = acos(R / (R + h)) the geometric dip of the horizon
// for an eye at height h (clamped to >= 0) above a sphere of radius R. The
// GL pass hides what is behind the Earth exactly (the transmittance is 0
// there); this cut only saves it the work, so it errs on the visible side.
struct PointSourceCut {
  double limiting_magnitude = 6.5;           // keep V <= this (display_limiting_magnitude gives it)
  double horizon_margin_rad = 0.5 * 3.14159265358979323846 / 180.0;  // 0.5°
  double earth_radius_m = 6371000.0;         // pass the atmosphere's bottom radius
  bool stars = true;
  bool planets = true;
};

// The horizon dip for an eye at height_m above a sphere of radius_m (0 at or below it).
double horizon_dip_rad(double height_m, double radius_m);

// Per-frame quantities the star directions need: the CIRS -> ENU rotation,
// the diurnal aberration (the observer's velocity from the Earth's rotation,
// due east in ENU) and the frame's refraction model.
struct StarFrameTransform {
  glm::dmat3 enu_from_cirs{1.0};
  glm::dvec3 diurnal_beta_enu{0.0};  // v / c, ENU
  bool refraction = true;
  astro::RefractionModel refraction_model;
};
StarFrameTransform star_frame_transform(const astro::AstrometryFrame& frame);

// Applies the refraction of `t` to an unrefracted unit ENU direction: exactly
// AstrometryFrame::direction_from_cirs's result, computed without
// trigonometry above 15° (ERFA's A tan z + B tan^3 z from the vector's
// components, then a small rotation toward the zenith).
glm::dvec3 refract_enu(const StarFrameTransform& t, const glm::dvec3& unrefracted);

// The catalogue prepared for drawing: per-star colour and illuminance
// computed once (95 exponentials a star), sorted by V (brightest first), and
// caches of the stars' and the planets' CIRS unit vectors. Keep one per
// context; not thread-safe (update() writes the caches).
class StarField {
 public:
  // The cached CIRS directions are recomputed when TT moved by more than this
  // (either way) since they were computed, and on first use. What changes in
  // a day: annual aberration (up to 0.35"), precession-nutation of the CIRS
  // (< 0.1"), proper motion (< 0.03" for Barnard's star); the diurnal
  // aberration (up to 0.32", which turns with the Earth) is taken out of the
  // cache and added every frame in ENU, where it is fixed. Measured worst
  // error over the catalogue at the threshold: printed by
  // PointSources.CachedDirectionsAgreeWithFreshOnes (< 1").
  static constexpr double kMaxCacheAgeDays = 1.0;

  StarField() = default;
  explicit StarField(const std::vector<astro::CatalogStar>& catalog);

  std::size_t size() const { return stars_.size(); }
  // The number of stars with V <= v_limit (the prefix the cut keeps).
  std::size_t count_brighter_than(double v_limit) const;
  // Star i in V order: its catalogue entry's identifiers and photometry.
  uint32_t hd(std::size_t i) const { return stars_[i].hd; }
  uint32_t kstars_line(std::size_t i) const { return stars_[i].kstars_line; }
  float v_mag(std::size_t i) const { return stars_[i].v_mag; }
  const glm::vec3& illuminance_rgb_lux(std::size_t i) const { return stars_[i].illuminance_rgb_lux; }
  const astro::StarAstrometry& astrometry(std::size_t i) const { return stars_[i].astrometry; }

  // Makes the caches valid for the frame: the stars' CIRS vectors are
  // recomputed (all stars, ~2 ms) on first use or when TT moved by more than
  // max_age_days, and the planets as below. Returns true when the stars were
  // recomputed.
  bool update(const astro::AstrometryFrame& frame, double max_age_days = kMaxCacheAgeDays);
  bool cache_valid() const { return cache_valid_; }
  uint64_t cache_computations() const { return cache_computations_; }
  double cache_tt_jd() const { return cache_tt_jd_; }

  // The planets are cached too, for visible_point_sources without the
  // caller's bodies (one AstrometryFrame::body costs ~0.3 ms): each planet's
  // CIRS direction (light time, deflection, aberration, parallax) and
  // magnitude are kept while TT moved by less than kPlanetMaxAgeS and the
  // eye by less than kPlanetMaxMoveM (Mercury, the fastest, moves < 0.1"/s
  // against the stars; 10 km shift Venus's parallax by < 0.06"); an update
  // recomputes every planet older than that, plus at most one older than
  // half of it, so in real time the planets are refreshed one per frame
  // rather than all five at once. Measured error: printed by
  // PointSources.CachedPlanetsAgreeWithFreshOnes.
  static constexpr double kPlanetMaxAgeS = 5.0;
  static constexpr double kPlanetMaxMoveM = 10000.0;
  static constexpr int kPlanetCount = 5;  // Mercury, Venus, Mars, Jupiter, Saturn
  // Updates only the planets' cache (update() calls it); returns how many were recomputed.
  int update_planets(const astro::AstrometryFrame& frame);
  bool planets_valid() const { return planets_valid_; }
  uint64_t planet_computations() const { return planet_computations_; }
  // Planet k (0 = Mercury .. 4 = Saturn) from the cache, as a PointSource
  // (refracted direction); false when the cache is not valid.
  bool cached_planet(const StarFrameTransform& t, int k, PointSource* out) const;

  // The apparent direction of star i from the cache (update() must have been
  // called for a frame within the cache's age), `t` from
  // star_frame_transform(frame): unrefracted (geometric + aberration +
  // deflection) and, in *refracted, as seen through the air. Unit vectors,
  // ENU at the eye.
  glm::dvec3 direction_enu(const StarFrameTransform& t, std::size_t i, glm::dvec3* refracted = nullptr) const;

 private:
  struct Star {
    astro::StarAstrometry astrometry;
    glm::dvec3 cirs{1.0, 0.0, 0.0};  // cached: CIRS unit vector without the diurnal aberration
    glm::vec3 illuminance_rgb_lux{0.0f};
    float v_mag = 0.0f;
    uint32_t hd = 0, kstars_line = 0;
  };
  std::vector<Star> stars_;
  std::vector<float> v_sorted_;  // stars_[i].v_mag, for the binary search
  bool cache_valid_ = false;
  double cache_tt_jd_ = 0.0;
  uint64_t cache_computations_ = 0;

  struct Planet {
    glm::dvec3 cirs{1.0, 0.0, 0.0};  // without the diurnal aberration, as the stars
    double tt_jd = 0.0;
    glm::vec3 illuminance_rgb_lux{0.0f};
    float v_mag = 0.0f;
  };
  Planet planets_[kPlanetCount];
  glm::dvec3 planets_eye_ecef_m_{0.0};
  bool planets_valid_ = false;
  uint64_t planet_computations_ = 0;
};

// Everything to draw this frame, brightest stars first then the planets
// (Mercury .. Saturn), above the horizon cut and with V <= the limiting
// magnitude. Stars from the field's cache (call stars.update(frame) first, or
// use the non-const overload, which does); planets from `bodies` if given
// (e.g. the frame's bodies() the caller already has), else from the field's
// planet cache if valid, else computed here (~0.3 ms each). *out is cleared
// and refilled: once its capacity has grown, a frame allocates nothing.
void visible_point_sources(const StarField& stars, const astro::AstrometryFrame& frame, const PointSourceCut& cut,
                           const std::array<astro::BodyEphemeris, astro::kBodyCount>* bodies,
                           std::vector<PointSource>* out);
// The same, updating the field's caches first.
void visible_point_sources(StarField& stars, const astro::AstrometryFrame& frame, const PointSourceCut& cut,
                           const std::array<astro::BodyEphemeris, astro::kBodyCount>* bodies,
                           std::vector<PointSource>* out);
// Convenience: returns a new vector (allocates).
std::vector<PointSource> visible_point_sources(StarField& stars, const astro::AstrometryFrame& frame,
                                               const PointSourceCut& cut,
                                               const std::array<astro::BodyEphemeris, astro::kBodyCount>* bodies =
                                                   nullptr);

}  // namespace atmo::core::night
