// CPU cost per frame of the night sky's ephemeris update (part of
// atmo_cpu_bench): at Innsbruck (47.26° N, 11.35° E, 620 m) from
// 2024-12-15T03:00:00Z (the moonlit night scenario), the time advancing
// 1/60 s per iteration, as a 60 Hz host's frames do:
//   BM_Ephemeris_Frame               AstrometryFrame for a new time (time scales + ERFA context)
//   BM_Ephemeris_SunMoon_Uncached    compute_sky_bodies: its own frame + Sun + Moon + the Moon's light
//   BM_Ephemeris_SunMoon_Cached      SkyBodiesCache::get steady state (recomputes every 0.1 s of time)
//   BM_Ephemeris_AllBodies_Uncached  frame.bodies(): Sun, Moon, five planets (frame given)
//   BM_Night_StarFieldUpdate         StarField::update steady state (star cache valid, planets refreshed
//                                    one at a time)
//   BM_Night_StarCacheRebuild        the once-a-day rebuild of the stars' CIRS cache (9931 stars)
//   BM_Night_VisiblePointSources/V   the visible list at V <= 6.5 / 4.0 (caches valid; argument 10 V)
//   BM_Night_EphemerisUpdatePerFrame/V  everything the plugin does per frame: time scales + frame +
//                                    cached Sun and Moon + StarField update (stars, cached planets) +
//                                    the visible list
// Where a benchmark is given a frame rather than building it, the frames are
// built in batches of 256 with the timer paused. Figures: docs/PERFORMANCE.md,
// "Night sky".
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/astro/ephemeris.h"
#include "core/astro/observer.h"
#include "core/astro/star_catalog.h"
#include "core/astro/time_scales.h"
#include "core/geo/geodesy.h"
#include "core/night_sky/point_sources.h"
#include "core/astro/sky_bodies.h"

namespace {

namespace astro = atmo::core::astro;
namespace night = atmo::core::night;

constexpr double kStartPosixS = 1734231600.0;  // 2024-12-15T03:00:00Z
constexpr double kFrameS = 1.0 / 60.0;
constexpr atmo::core::Geodetic kEye{47.26, 11.35, 620.0};

template <typename T>
T checked(std::optional<T> v, const std::string& error) {
  if (!v) throw std::runtime_error(error);
  return std::move(*v);
}

const astro::Observer& observer() {
  static const astro::Observer o = [] {
    std::string error;
    return checked(astro::observer_from_geodetic(kEye.latitude_deg, kEye.longitude_deg, kEye.height_m, &error),
                   error);
  }();
  return o;
}

astro::AstrometryFrame make_frame(double posix_s) {
  std::string error;
  const astro::TimeScales time = checked(astro::time_scales_from_posix(posix_s, {}, &error), error);
  return checked(astro::AstrometryFrame::create(time, observer(), {}, &error), error);
}

// The catalogue prepared once (colours, sorting); each benchmark copies it, so
// its caches start empty.
const night::StarField& star_field() {
  static const night::StarField f = [] {
    // ATMO_STAR_CATALOG overrides the build-tree path (e.g. a copy run on another machine).
    const char* override_path = std::getenv("ATMO_STAR_CATALOG");
    const astro::StarCatalogLoad c = astro::load_star_catalog(override_path ? override_path : ATMO_STAR_CATALOG_PATH);
    if (!c.error.empty()) throw std::runtime_error(c.error);
    return night::StarField(c.stars);
  }();
  return f;
}

// Frames 1/60 s apart, built ahead in batches with the timer paused.
class FrameStream {
 public:
  explicit FrameStream(double start_posix_s) : t_(start_posix_s) { refill(); }
  const astro::AstrometryFrame& next(benchmark::State& state) {
    if (i_ == frames_.size()) {
      state.PauseTiming();
      refill();
      state.ResumeTiming();
    }
    return frames_[i_++];
  }

 private:
  void refill() {
    frames_.clear();
    for (int k = 0; k < 256; ++k) {
      frames_.push_back(make_frame(t_));
      t_ += kFrameS;
    }
    i_ = 0;
  }
  double t_;
  std::vector<astro::AstrometryFrame> frames_;
  std::size_t i_ = 0;
};

night::PointSourceCut cut_at(const benchmark::State& state) {
  night::PointSourceCut cut;
  cut.limiting_magnitude = 0.1 * double(state.range(0));
  cut.earth_radius_m = atmo::core::local_earth_radius_m(kEye.latitude_deg);
  return cut;
}

void BM_Ephemeris_Frame(benchmark::State& state) {
  double t = kStartPosixS;
  std::string error;
  for (auto _ : state) {
    t += kFrameS;
    std::optional<astro::TimeScales> time = astro::time_scales_from_posix(t, {}, &error);
    std::optional<astro::AstrometryFrame> frame = astro::AstrometryFrame::create(*time, observer(), {}, &error);
    benchmark::DoNotOptimize(frame->earth_rotation_angle_rad());
  }
}
BENCHMARK(BM_Ephemeris_Frame)->Unit(benchmark::kMicrosecond);

void BM_Ephemeris_SunMoon_Uncached(benchmark::State& state) {
  double t = kStartPosixS;
  std::string error;
  for (auto _ : state) {
    t += kFrameS;
    std::optional<atmo::core::SkyBodies> b = atmo::core::compute_sky_bodies(t, 0.0, kEye, &error);
    benchmark::DoNotOptimize(b->moon_enu);
  }
}
BENCHMARK(BM_Ephemeris_SunMoon_Uncached)->Unit(benchmark::kMicrosecond);

void BM_Ephemeris_SunMoon_Cached(benchmark::State& state) {
  atmo::core::SkyBodiesCache cache;
  const glm::dvec3 eye_ecef = atmo::core::ecef_from_geodetic(kEye);
  double t = kStartPosixS;
  std::string error;
  cache.get(t, 0.0, kEye, eye_ecef, &error);
  const uint64_t before = cache.computations();
  for (auto _ : state) {
    t += kFrameS;
    std::optional<atmo::core::SkyBodies> b = cache.get(t, 0.0, kEye, eye_ecef, &error);
    benchmark::DoNotOptimize(b->moon_enu);
  }
  state.counters["computed_fraction"] = double(cache.computations() - before) / double(state.iterations());
}
BENCHMARK(BM_Ephemeris_SunMoon_Cached)->Unit(benchmark::kMicrosecond);

void BM_Ephemeris_AllBodies_Uncached(benchmark::State& state) {
  FrameStream frames(kStartPosixS);
  for (auto _ : state) {
    const auto bodies = frames.next(state).bodies();
    benchmark::DoNotOptimize(bodies.data());
  }
}
BENCHMARK(BM_Ephemeris_AllBodies_Uncached)->Unit(benchmark::kMicrosecond);

void BM_Night_StarFieldUpdate(benchmark::State& state) {
  night::StarField field = star_field();
  field.update(make_frame(kStartPosixS - kFrameS));  // the star cache, and every planet, once
  const uint64_t planets_before = field.planet_computations();
  FrameStream frames(kStartPosixS);
  for (auto _ : state) benchmark::DoNotOptimize(field.update(frames.next(state)));
  if (field.cache_computations() != 1) state.SkipWithError("the star cache was rebuilt");
  state.counters["planets_per_frame"] =
      double(field.planet_computations() - planets_before) / double(state.iterations());
}
BENCHMARK(BM_Night_StarFieldUpdate)->Unit(benchmark::kMicrosecond);

void BM_Night_StarCacheRebuild(benchmark::State& state) {
  night::StarField field = star_field();
  field.update(make_frame(kStartPosixS - kFrameS));
  FrameStream frames(kStartPosixS);
  // A negative age limit rebuilds the star cache on every call (planets as in the steady state).
  for (auto _ : state) benchmark::DoNotOptimize(field.update(frames.next(state), -1.0));
  state.counters["stars"] = double(field.size());
}
BENCHMARK(BM_Night_StarCacheRebuild)->Unit(benchmark::kMillisecond);

// Argument: 10 x the limiting magnitude.
void BM_Night_VisiblePointSources(benchmark::State& state) {
  night::StarField field = star_field();
  field.update(make_frame(kStartPosixS - kFrameS));
  const night::PointSourceCut cut = cut_at(state);
  std::vector<night::PointSource> out;
  FrameStream frames(kStartPosixS);
  for (auto _ : state) {
    const night::StarField& cached = field;  // the list only: caches valid
    night::visible_point_sources(cached, frames.next(state), cut, nullptr, &out);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["sources"] = double(out.size());
  state.counters["catalogue_stars"] = double(field.count_brighter_than(cut.limiting_magnitude));
}
BENCHMARK(BM_Night_VisiblePointSources)->Arg(65)->Arg(40)->Unit(benchmark::kMicrosecond);

// The whole per-frame ephemeris update as the plugin does it, per view: the
// frame for the new time, the Sun and Moon from the view's cache (which builds
// its own frame when it recomputes), the star field's caches (stars valid for
// a day, planets refreshed one at a time) and the visible list. Argument: 10 x
// the limiting magnitude.
void BM_Night_EphemerisUpdatePerFrame(benchmark::State& state) {
  night::StarField field = star_field();
  atmo::core::SkyBodiesCache sky_bodies;
  const glm::dvec3 eye_ecef = atmo::core::ecef_from_geodetic(kEye);
  const night::PointSourceCut cut = cut_at(state);
  std::vector<night::PointSource> out;
  std::string error;
  double t = kStartPosixS - kFrameS;
  // Warm-up frame: every cache filled, the list's capacity reached.
  sky_bodies.get(t, 0.0, kEye, eye_ecef, &error);
  night::visible_point_sources(field, make_frame(t), cut, nullptr, &out);
  for (auto _ : state) {
    t += kFrameS;
    std::optional<astro::TimeScales> time = astro::time_scales_from_posix(t, {}, &error);
    std::optional<astro::AstrometryFrame> frame = astro::AstrometryFrame::create(*time, observer(), {}, &error);
    std::optional<atmo::core::SkyBodies> bodies = sky_bodies.get(t, 0.0, kEye, eye_ecef, &error);
    benchmark::DoNotOptimize(bodies->moon_enu);
    night::visible_point_sources(field, *frame, cut, nullptr, &out);
    benchmark::DoNotOptimize(out.data());
  }
  if (field.cache_computations() != 1) state.SkipWithError("the star cache was rebuilt");
  state.counters["sources"] = double(out.size());
}
BENCHMARK(BM_Night_EphemerisUpdatePerFrame)->Arg(65)->Arg(40)->Unit(benchmark::kMicrosecond);

}  // namespace
