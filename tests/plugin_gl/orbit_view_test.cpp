// Views from orbit through the ABI: an eye anywhere in the one documented
// range of heights (core/astro/observer.h: -1000 m to 10 000 km; atmo.h)
// renders every pass with clouds, fog and lights set, with no error, no
// warning logged and every pixel finite and non-negative; from 400 km to
// 10 000 km the Sun, the Moon, the planets and the stars are drawn where the
// ephemeris puts them for that height (the Moon's parallax there is up to
// 1.5°: in the 3° telephoto used here, the ground's ephemeris would put the
// Moon 6 px off from 5000 km and 12 px off from 10 000 km).
// Figures are printed with the prefix "[ orbit ]".
#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "core/astro/ephemeris.h"
#include "core/astro/star_catalog.h"
#include "core/astro/sky_bodies.h"
#include "plugin_gl_fixture.h"

using namespace plugin_gl;

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kLat = 47.26, kLon = 11.35;  // innsbruck_view's place
constexpr double kDayUtc = 1718964000.0;      // 2024-06-21T10:00Z: the Sun high over Innsbruck
constexpr double kNightUtc = 1734303600.0;    // 2024-12-15T23:00Z: the Sun 66° down, the full Moon high
const double kHeights[] = {-400.0, 400e3, 5.0e6, 1.0e7};

double luminance(const float* rgba) { return 0.2126 * rgba[0] + 0.7152 * rgba[1] + 0.0722 * rgba[2]; }

// Every warning or error the plugin logs.
struct LogCapture {
  std::vector<std::string> lines;
  static void log(void* user, int32_t severity, const char* message) {
    if (severity >= ATMO_LOG_WARNING) static_cast<LogCapture*>(user)->lines.push_back(message);
  }
};

void set_time(Fixture& f, double utc) {
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = utc;
  f.context->set_frame(frame);
}

// The pixel (x right, y down from the top row, as read_color returns it) where
// an ENU direction lands in innsbruck_view(heading, pitch, projection).
glm::dvec2 pixel_of(const glm::dvec3& enu, double heading, double pitch, const glm::dmat4& projection) {
  const glm::dvec4 clip = projection * look(heading, pitch) * glm::dvec4(enu, 0.0);
  const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
  return {(ndc.x + 1.0) * 0.5 * kWidth, (1.0 - ndc.y) * 0.5 * kHeight};
}

// Heading and pitch (degrees) of an ENU direction.
glm::dvec2 aim(const glm::dvec3& d) { return {std::atan2(d.x, d.y) / kDeg, std::asin(std::clamp(d.z, -1.0, 1.0)) / kDeg}; }

// The luminance-weighted centroid of the pixels above `fraction` of the peak,
// within `radius` pixels of `around`; the peak luminance in *peak.
glm::dvec2 bright_centroid(const atmo::support::Image& img, glm::dvec2 around, double radius, double fraction,
                           double* peak) {
  *peak = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      if (glm::length(glm::dvec2(x + 0.5, y + 0.5) - around) <= radius)
        *peak = std::max(*peak, luminance(&img.rgba[(size_t(y) * kWidth + x) * 4]));
  glm::dvec2 sum(0.0);
  double weight = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const double l = luminance(&img.rgba[(size_t(y) * kWidth + x) * 4]);
      if (glm::length(glm::dvec2(x + 0.5, y + 0.5) - around) <= radius && l > fraction * *peak) {
        sum += l * glm::dvec2(x + 0.5, y + 0.5);
        weight += l;
      }
    }
  return weight > 0.0 ? sum / weight : glm::dvec2(-1e9);
}

std::optional<atmo::core::astro::AstrometryFrame> astrometry(double utc, double height_m) {
  namespace astro = atmo::core::astro;
  std::string error;
  const auto t = astro::time_scales_from_posix(utc, {}, &error);
  EXPECT_TRUE(t) << error;
  const auto o = astro::observer_from_geodetic(kLat, kLon, height_m, &error);
  EXPECT_TRUE(o) << error;
  if (!t || !o) return std::nullopt;
  auto f = astro::AstrometryFrame::create(*t, *o, {}, &error);
  EXPECT_TRUE(f) << error;
  return f;
}

}  // namespace

// Every pass at every height, by day and by night, with clouds, fog, lights and
// host depth set: no error, no warning, every pixel finite and >= 0.
TEST(OrbitView, EveryPassAtEveryHeightWithCloudsFogAndLights) {
  Fixture f;
  LogCapture log;
  f.services.user = &log;
  f.services.log = &LogCapture::log;
  f.fresh_context();

  const AtmoCloudLayer layer = cumulus();
  ASSERT_EQ(f.context->set_clouds(clouds_at_innsbruck(&layer, 1)), ATMO_SUCCESS) << f.context->last_error();
  AtmoFogState fog = atmo::make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
  fog.visibility_m = 300.0;
  f.context->set_fog(fog);
  AtmoLightPoint light{};
  light.position_m[1] = 200.0;
  light.intensity_cd = 2.0e4;
  light.color[0] = light.color[1] = light.color[2] = 1.0;
  AtmoLightsState lights = atmo::make<AtmoLightsState>(ATMO_TYPE_LIGHTS_STATE);
  lights.world_frame = ATMO_WORLD_ENU;
  lights.light_size = sizeof(AtmoLightPoint);
  lights.world_origin_geodetic[0] = kLat;
  lights.world_origin_geodetic[1] = kLon;
  lights.lights = &light;
  lights.light_count = 1;
  f.context->set_lights(lights);

  const GLuint depth = atmo::support::make_split_depth_texture(kWidth, kHeight, 0.9999f);
  const glm::dmat4 projection = glm::perspective(glm::radians(60.0), double(kWidth) / kHeight, 1.0, 1.0e5);
  const AtmoPassKind passes[] = {ATMO_PASS_SKY, ATMO_PASS_NIGHT_SKY, ATMO_PASS_CLOUDS, ATMO_PASS_AERIAL_PERSPECTIVE,
                             ATMO_PASS_LIGHT_GLOWS};
  int renders = 0, drawn[ATMO_PASS_COUNT] = {};
  for (double utc : {kDayUtc, kNightUtc}) {
    set_time(f, utc);
    for (double h : kHeights) {
      for (double pitch : {-45.0, 45.0}) {
        AtmoViewState vs = innsbruck_view(h, 200.0, pitch, projection);
        vs.depth_texture = depth;
        vs.exposure_scale = utc == kDayUtc ? 1e-4 : 1.0;
        f.view->set(vs);
        f.target->bind();
        f.target->clear(0.0f, 0.0f, 0.0f, 1.0f);
        for (AtmoPassKind pass : passes) {
          const AtmoResult r = f.view->render(pass);
          ASSERT_TRUE(r == ATMO_SUCCESS || r == ATMO_STATUS_NOTHING_TO_DRAW)
              << "pass " << pass << " at " << h << " m, utc " << utc << ", pitch " << pitch << ": "
              << f.context->last_error();
          if (r == ATMO_SUCCESS) ++drawn[pass];
        }
        const auto img = f.target->read_color();
        size_t bad = 0;
        for (size_t i = 0; i < img.pixel_count() * 4; ++i)
          if (!std::isfinite(img.rgba[i]) || img.rgba[i] < 0.0f) ++bad;
        EXPECT_EQ(bad, 0u) << h << " m, utc " << utc << ", pitch " << pitch;
        ++renders;
      }
    }
  }
  glDeleteTextures(1, &depth);
  std::printf("[ orbit ] %d views, -400 m to 10 000 km, day and night, each of the 5 passes: drawn sky %d, night "
              "%d, clouds %d, aerial %d, glows %d times; %zu warnings or errors logged\n",
              renders, drawn[ATMO_PASS_SKY], drawn[ATMO_PASS_NIGHT_SKY], drawn[ATMO_PASS_CLOUDS],
              drawn[ATMO_PASS_AERIAL_PERSPECTIVE], drawn[ATMO_PASS_LIGHT_GLOWS], log.lines.size());
  for (const std::string& line : log.lines) ADD_FAILURE() << "logged: " << line;
  EXPECT_EQ(drawn[ATMO_PASS_SKY], renders);
  EXPECT_GT(drawn[ATMO_PASS_NIGHT_SKY], 0);
}

// The Sun by day and the Moon by night, from orbit: a telephoto aimed where the
// ephemeris says for that height puts the disc at the image centre.
TEST(OrbitView, SunAndMoonAreWhereTheEphemerisSaysForTheHeight) {
  Fixture f;
  const double fov_deg = 3.0;
  const double pixel_deg = fov_deg / kHeight;
  const glm::dmat4 projection = glm::perspective(glm::radians(fov_deg), double(kWidth) / kHeight, 1.0, 1.0e5);
  for (double h : {400e3, 5.0e6, 1.0e7}) {
    for (bool moon : {false, true}) {
      const double utc = moon ? kNightUtc : kDayUtc;
      std::string error;
      const auto here = atmo::core::compute_sky_bodies(utc, 0.0, atmo::core::Geodetic{kLat, kLon, h}, &error);
      const auto ground = atmo::core::compute_sky_bodies(utc, 0.0, atmo::core::Geodetic{kLat, kLon, 0.0}, &error);
      ASSERT_TRUE(here && ground) << error;
      const glm::dvec3 d = moon ? here->moon_enu : here->sun_enu;
      const glm::dvec3 d_ground = moon ? ground->moon_enu : ground->sun_enu;
      const glm::dvec2 a = aim(d);
      set_time(f, utc);
      AtmoViewState vs = innsbruck_view(h, a.x, a.y, projection);
      vs.exposure_scale = 1.0;
      f.view->set(vs);
      f.target->bind();
      f.target->clear(0.0f, 0.0f, 0.0f, 1.0f);
      ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS) << f.context->last_error();
      const auto img = f.target->read_color();
      const glm::dvec2 centre(0.5 * kWidth, 0.5 * kHeight);
      double peak = 0.0;
      const glm::dvec2 c = bright_centroid(img, centre, 0.5 * kHeight, 0.5, &peak);
      const double off_px = glm::length(c - centre);
      const double parallax_px = std::acos(std::clamp(glm::dot(d, d_ground), -1.0, 1.0)) / kDeg / pixel_deg;
      std::printf("[ orbit ] %-4s from %8.0f m: disc centroid %.2f px from where the ephemeris puts it (the "
                  "ground's ephemeris: %.1f px away), peak %.3g cd/m^2\n",
                  moon ? "Moon" : "Sun", h, off_px, parallax_px, peak);
      EXPECT_GT(peak, moon ? 1.0e3 : 1.0e8) << "no disc drawn";
      EXPECT_LT(off_px, 1.0) << (moon ? "Moon" : "Sun") << " from " << h << " m";
    }
  }
}

// From 5000 km at night, looking up: the night pass draws the stars and the
// planets at the pixels the ephemeris gives for that height.
TEST(OrbitView, FromFiveThousandKmStarsAndPlanetsAreWhereTheEphemerisSays) {
  namespace astro = atmo::core::astro;
  const double h = 5.0e6;
  Fixture f;
  const auto frame = astrometry(kNightUtc, h);
  ASSERT_TRUE(frame);
  const astro::StarCatalogLoad cat =
      astro::load_star_catalog(std::string(ATMO_SOURCE_DIR) + "/data/stars/hipparcos_v6_6.tsv");
  ASSERT_TRUE(cat.error.empty()) << cat.error;

  struct Target {
    std::string name;
    glm::dvec3 enu;
    double v_mag;
  };
  std::vector<Target> targets;
  for (astro::Body b : {astro::Body::kMars, astro::Body::kJupiter}) {
    const astro::BodyEphemeris e = frame->body(b);
    targets.push_back({astro::to_string(b), e.direction.enu, e.apparent_magnitude});
  }
  std::vector<astro::StarAstrometry> stars;
  for (const astro::CatalogStar& s : cat.stars) stars.push_back(astro::star_astrometry(s));
  std::vector<astro::SkyDirection> star_dirs(stars.size());
  frame->stars(stars.data(), stars.size(), star_dirs.data());

  const double fov_deg = 30.0;
  const glm::dmat4 projection = glm::perspective(glm::radians(fov_deg), double(kWidth) / kHeight, 1.0, 1.0e5);
  set_time(f, kNightUtc);
  int checked = 0;
  double worst_px = 0.0;
  for (const Target& planet : targets) {
    ASSERT_GT(planet.enu.z, 0.1) << planet.name << " must be up";
    const glm::dvec2 a = aim(planet.enu);
    AtmoViewState vs = innsbruck_view(h, a.x, a.y, projection);
    vs.exposure_scale = 1.0 / (1.2 * 0.25);  // EV100 -2
    vs.output_encoding = ATMO_OUTPUT_LINEAR_HDR;
    f.view->set(vs);
    f.target->bind();
    f.target->clear(0.0f, 0.0f, 0.0f, 1.0f);
    ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS) << f.context->last_error();
    const auto sky = f.target->read_color();
    ASSERT_EQ(f.view->render(ATMO_PASS_NIGHT_SKY), ATMO_SUCCESS) << f.context->last_error();
    auto img = f.target->read_color();
    for (size_t i = 0; i < img.pixel_count() * 4; ++i) img.rgba[i] -= sky.rgba[i];  // the points alone

    // The planet at the centre, then the bright stars in the field (V < 3), each alone within 3 px.
    std::vector<Target> in_view = {planet};
    for (size_t i = 0; i < stars.size(); ++i) {
      if (cat.stars[i].v_mag > 3.0) continue;
      const glm::dvec2 p = pixel_of(star_dirs[i].enu, a.x, a.y, projection);
      if (p.x < 4 || p.y < 4 || p.x > kWidth - 4 || p.y > kHeight - 4) continue;
      if (glm::dot(star_dirs[i].enu, planet.enu) < 0.0) continue;
      const std::string name = cat.stars[i].name.empty() ? cat.stars[i].bayer : cat.stars[i].name;
      in_view.push_back({name, star_dirs[i].enu, cat.stars[i].v_mag});
    }
    for (const Target& t : in_view) {
      const glm::dvec2 p = pixel_of(t.enu, a.x, a.y, projection);
      bool alone = true;
      for (size_t i = 0; i < stars.size(); ++i) {
        const glm::dvec2 q = pixel_of(star_dirs[i].enu, a.x, a.y, projection);
        if (glm::dot(star_dirs[i].enu, planet.enu) > 0.0 && cat.stars[i].v_mag < t.v_mag + 2.5 &&
            glm::length(q - p) < 3.0 && glm::length(q - p) > 1e-6)
          alone = false;
      }
      if (!alone) continue;
      double peak = 0.0;
      const glm::dvec2 c = bright_centroid(img, p, 2.5, 0.2, &peak);
      const double off = glm::length(c - p);
      std::printf("[ orbit ] 5000 km, night: %-10s V %5.2f drawn %.2f px from its ephemeris pixel (%.1f, %.1f), "
                  "peak %.3g\n",
                  t.name.c_str(), t.v_mag, off, p.x, p.y, peak);
      EXPECT_GT(peak, 0.0) << t.name << " not drawn";
      EXPECT_LT(off, 1.0) << t.name;
      worst_px = std::max(worst_px, off);
      ++checked;
    }
  }
  std::printf("[ orbit ] 5000 km, night: %d points checked, worst %.2f px\n", checked, worst_px);
  EXPECT_GE(checked, 4);
}

// One range per quantity, enforced at the ABI edge: the eye's height, UTC and
// DUT1 just outside the ranges the ephemeris serves are refused with the
// function, the field, the value and the range, and change nothing; just
// inside, every pass draws.
TEST(OrbitView, RangesAreTheEphemerisRangesAndRefusalsNameThem) {
  Fixture f;
  const AtmoPluginApi& api = f.plugin->api();
  const glm::dmat4 projection = glm::perspective(glm::radians(60.0), double(kWidth) / kHeight, 1.0, 1.0e5);
  set_time(f, kNightUtc);
  f.view->set(innsbruck_view(1.0e7, 0.0, 30.0, projection));
  f.target->bind();
  ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS) << f.context->last_error();
  const auto before = f.target->read_color();

  struct FrameCase {
    double utc, dut1;
    const char* field;
    const char* value;
  } frames[] = {{kNightUtc, 0.95, "AtmoFrameState.dut1_s", "0.95"},
                {kNightUtc, -0.91, "AtmoFrameState.dut1_s", "-0.91"},
                {-62135596801.0, 0.0, "AtmoFrameState.utc_posix_s", "-62135596801"},
                {253402300800.0, 0.0, "AtmoFrameState.utc_posix_s", "253402300800"},
                {-1.0e11, 0.0, "AtmoFrameState.utc_posix_s", "-100000000000"}};
  for (const FrameCase& c : frames) {
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = c.utc;
    frame.dut1_s = c.dut1;
    EXPECT_EQ(api.set_frame(f.context->handle(), &frame), ATMO_ERROR_OUT_OF_RANGE) << c.field << " = " << c.value;
    const std::string e = f.context->last_error();
    std::printf("[ orbit ] refused: %s\n", e.c_str());
    for (const char* part : {"set_frame", c.field, c.value, "["})
      EXPECT_NE(e.find(part), std::string::npos) << "'" << part << "' missing in: " << e;
  }
  struct ViewCase {
    double height_m;
    const char* value;
  } views[] = {{1.0001e7, "10001000"}, {-1000.5, "-1000.5"}, {-12000.0, "-12000"}};
  for (const ViewCase& c : views) {
    const AtmoViewState vs = innsbruck_view(c.height_m, 0.0, 30.0, projection);
    EXPECT_EQ(api.set_view(f.view->handle(), &vs), ATMO_ERROR_OUT_OF_RANGE) << c.height_m;
    const std::string e = f.context->last_error();
    std::printf("[ orbit ] refused: %s\n", e.c_str());
    for (const char* part : {"set_view", "AtmoViewState.eye_geodetic[2]", c.value, "[-1000, 10000000] m"})
      EXPECT_NE(e.find(part), std::string::npos) << "'" << part << "' missing in: " << e;
  }
  {
    // An ECEF eye 20 000 km from the centre over the equator: 13 622 km up.
    AtmoViewState vs = innsbruck_view(0.0, 0.0, 30.0, projection);
    vs.eye_kind = ATMO_POSITION_ECEF;
    vs.eye_ecef_m[0] = 2.0e7;
    EXPECT_EQ(api.set_view(f.view->handle(), &vs), ATMO_ERROR_OUT_OF_RANGE);
    const std::string e = f.context->last_error();
    std::printf("[ orbit ] refused: %s\n", e.c_str());
    for (const char* part : {"set_view", "AtmoViewState.eye_ecef_m", "13621863", "[-1000, 10000000] m"})
      EXPECT_NE(e.find(part), std::string::npos) << "'" << part << "' missing in: " << e;
  }
  // Refused input changed nothing: the same frame is drawn.
  ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS) << f.context->last_error();
  const auto after = f.target->read_color();
  EXPECT_EQ(before.rgba, after.rgba);

  // The ends of the ranges are served.
  for (double utc : {-62135596800.0, 253402300799.0}) {
    for (double dut1 : {-0.9, 0.9}) {
      auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
      frame.utc_posix_s = utc;
      frame.dut1_s = dut1;
      f.context->set_frame(frame);
      for (double h : {-1000.0, 1.0e7}) {
        f.view->set(innsbruck_view(h, 0.0, 30.0, projection));
        for (AtmoPassKind pass : {ATMO_PASS_SKY, ATMO_PASS_NIGHT_SKY}) {
          const AtmoResult r = f.view->render(pass);
          EXPECT_TRUE(r == ATMO_SUCCESS || r == ATMO_STATUS_NOTHING_TO_DRAW)
              << "utc " << utc << ", dut1 " << dut1 << ", " << h << " m, pass " << pass << ": "
              << f.context->last_error();
        }
      }
    }
  }
}
