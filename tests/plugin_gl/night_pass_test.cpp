// The night sky through the ABI, drawn on llvmpipe: the Moon's phase and the
// orientation of its lit side in the image against the ephemeris (ERFA +
// ELP 2000-82B, Meeus's bright-limb angle), the night pass drawing stars at
// night and nothing in daylight. Figures are printed with the prefix
// "[ night pass ]" and quoted in docs/NIGHT_SKY.md.
#include <algorithm>
#include <vector>

#include "core/astro/sky_bodies.h"
#include "plugin_gl_fixture.h"

using namespace plugin_gl;

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kInnsbruck[3] = {47.26, 11.35, 620.0};

AtmoViewState geodetic_view(double heading_deg, double pitch_deg, const glm::dmat4& projection) {
  AtmoViewState vs = innsbruck_view(0.0, heading_deg, pitch_deg, projection);
  vs.eye_kind = ATMO_POSITION_GEODETIC;
  vs.world_frame = ATMO_WORLD_ENU;
  for (int i = 0; i < 3; ++i) vs.eye_geodetic[i] = vs.world_origin_geodetic[i] = kInnsbruck[i];
  return vs;
}

struct MoonCase {
  const char* name;
  double utc_posix_s;
};

double luminance(const float* rgba) { return 0.2126 * rgba[0] + 0.7152 * rgba[1] + 0.0722 * rgba[2]; }

}  // namespace

// A telephoto (1.2° vertical field, the Moon ~28 px across) pointed at the
// Moon: the lit part of the disc covers the illuminated fraction of it, and
// its centroid lies from the disc's centre in the direction of the bright limb.
TEST(NightPass, MoonPhaseAndOrientationMatchTheEphemeris) {
  const MoonCase cases[] = {
      {"waxing gibbous, 2024-12-10T19:00Z", 1733857200.0},
      {"waxing crescent at dusk, 2025-01-03T16:05Z", 1735920300.0},
      {"waning crescent before dawn, 2025-01-25T06:00Z", 1737784800.0},
      {"waning gibbous, 2024-12-19T03:00Z", 1734577200.0},
  };
  for (const MoonCase& c : cases) {
    Fixture f;
    std::string error;
    const auto bodies = atmo::core::compute_sky_bodies(
        c.utc_posix_s, 0.0, atmo::core::Geodetic{kInnsbruck[0], kInnsbruck[1], kInnsbruck[2]}, &error);
    ASSERT_TRUE(bodies) << error;
    const glm::dvec3 m = bodies->moon_enu;
    ASSERT_GT(m.z, 0.1) << c.name << ": the Moon must be up";
    const double heading = std::atan2(m.x, m.y) / kDeg, pitch = std::asin(m.z) / kDeg;
    const double fov_deg = 1.2;
    const glm::dmat4 projection = glm::perspective(glm::radians(fov_deg), double(kWidth) / kHeight, 1.0, 1.0e5);
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = c.utc_posix_s;
    f.context->set_frame(frame);
    f.view->set(geodetic_view(heading, pitch, projection));
    f.target->bind();
    ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS) << f.plugin->api().last_error(f.context->handle());
    const auto img = f.target->read_color();

    // The disc: pixels whose centre is within the Moon's angular radius of the image centre (the Moon's direction).
    const double pixel_rad = 2.0 * std::tan(0.5 * fov_deg * kDeg) / kHeight;
    const double radius_px = bodies->moon_angular_radius_rad / pixel_rad;
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    double peak = 0.0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) peak = std::max(peak, luminance(&img.rgba[(size_t(y) * kWidth + x) * 4]));
    int disc = 0, lit = 0;
    double sx = 0.0, sy = 0.0;
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        const double dx = x + 0.5 - cx, dy = cy - (y + 0.5);  // read_color's row 0 is the top: dy > 0 is up
        if (std::hypot(dx, dy) > radius_px - 0.5) continue;  // whole pixels inside the limb
        ++disc;
        if (luminance(&img.rgba[(size_t(y) * kWidth + x) * 4]) > 0.1 * peak) {
          ++lit;
          sx += dx;
          sy += dy;
        }
      }
    }
    ASSERT_GT(disc, 100) << c.name;
    ASSERT_GT(lit, 0) << c.name << ": no lit pixel";
    const double lit_fraction = double(lit) / disc;
    // Counter-clockwise from the image's up (the zenith side: the camera is not rolled), as the ephemeris states it.
    double angle = std::atan2(-sx, sy);
    if (angle < 0.0) angle += 2.0 * M_PI;
    double difference = std::remainder(angle - bodies->moon_bright_limb_zenith_angle_rad, 2.0 * M_PI);
    std::printf("[ night pass ] %-44s illuminated %.3f, drawn %.3f (%d of %d disc pixels); bright limb %.1f° from "
                "up, drawn %.1f° (difference %+.1f°); peak %.0f cd/m^2\n",
                c.name, bodies->moon_illuminated_fraction, lit_fraction, lit, disc,
                bodies->moon_bright_limb_zenith_angle_rad / kDeg, angle / kDeg, difference / kDeg, peak);
    EXPECT_NEAR(lit_fraction, bodies->moon_illuminated_fraction, 0.06) << c.name;
    EXPECT_LT(std::abs(difference), 6.0 * kDeg) << c.name;
  }
}

// Noon: the night pass does nothing and says so; a night: it draws stars.
TEST(NightPass, NothingInDaylightStarsAtNight) {
  Fixture f;
  const glm::dmat4 projection = glm::perspective(glm::radians(60.0), double(kWidth) / kHeight, 1.0, 1.0e5);
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  AtmoViewState vs = geodetic_view(0.0, 45.0, projection);
  vs.output_encoding = ATMO_OUTPUT_DISPLAY_SRGB;

  frame.utc_posix_s = 1718964000.0;  // 2024-06-21T10:00Z
  vs.exposure_scale = 1.0 / (1.2 * 32768.0);  // EV100 15
  f.context->set_frame(frame);
  f.view->set(vs);
  f.target->bind();
  f.target->clear(0.25f, 0.5f, 0.75f, 1.0f);
  EXPECT_EQ(f.view->render(ATMO_PASS_NIGHT_SKY), ATMO_STATUS_NOTHING_TO_DRAW);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(f.view->render(ATMO_PASS_NIGHT_SKY), ATMO_STATUS_NOTHING_TO_DRAW);
  const auto day = f.target->read_color();
  for (size_t i = 0; i < day.pixel_count(); ++i) ASSERT_EQ(day.rgba[i * 4 + 2], 0.75f) << "the day pass wrote a pixel";

  frame.utc_posix_s = 1734231600.0;  // 2024-12-15T03:00Z, the Moon in the west; the camera looks north
  vs.exposure_scale = 1.0 / (1.2 * 0.25);  // EV100 -2
  f.context->set_frame(frame);
  f.view->set(vs);
  ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS);
  const auto sky = f.target->read_color();
  ASSERT_EQ(f.view->render(ATMO_PASS_NIGHT_SKY), ATMO_SUCCESS) << f.plugin->api().last_error(f.context->handle());
  const auto stars = f.target->read_color();
  int brighter = 0, darker = 0;
  for (size_t i = 0; i < sky.pixel_count(); ++i) {
    const double before = luminance(&sky.rgba[i * 4]), after = luminance(&stars.rgba[i * 4]);
    if (after > before + 1.5 / 255.0) ++brighter;
    if (after < before - 0.5 / 255.0) ++darker;
  }
  std::printf("[ night pass ] night, 60° view north at 45°, EV100 -2: %d of %zu pixels brightened by stars\n", brighter,
              sky.pixel_count());
  EXPECT_GT(brighter, 10);
  EXPECT_EQ(darker, 0) << "the point pass must only add light";
}

// The places and times where ephemerides and sky geometry break: the poles,
// the date line, 400 m below sea level, 100 km up (the march above the air),
// the Moon and the Sun on the horizon, the year 2100. Sky and night passes in
// both encodings at night exposure: every pixel finite and non-negative.
TEST(NightPass, FiniteAtThePolesTheDateLineInSpaceAnd2100) {
  Fixture f;
  const glm::dmat4 projection = glm::perspective(glm::radians(60.0), double(kWidth) / kHeight, 1.0, 1.0e5);
  struct Case {
    const char* name;
    double lat, lon, height_m, utc_posix_s, heading, pitch;
  } cases[] = {
      {"north pole, polar night", 90.0, 0.0, 10.0, 1734231600.0, 0.0, 10.0},
      {"south pole", -90.0, 0.0, 2835.0, 1734231600.0, 180.0, 5.0},
      {"date line, east", 0.0, 180.0, 0.0, 1734231600.0, 90.0, 20.0},
      {"date line, west", 0.0, -179.9999, 0.0, 1734231600.0, 270.0, 20.0},
      {"Dead Sea shore, -400 m", 31.5, 35.5, -400.0, 1734231600.0, 270.0, 30.0},
      {"100 km up", 47.26, 11.35, 100000.0, 1734231600.0, 0.0, -10.0},
      {"Moon on the horizon (moonrise, Innsbruck 2024-12-10T12:20Z)", 47.26, 11.35, 620.0, 1733833200.0, 82.0, 0.0},
      {"Sun on the horizon (sunset, Innsbruck 2024-12-10T15:22:06Z)", 47.26, 11.35, 620.0, 1733844126.0, 235.5, 0.0},
      {"year 2100, night (2100-12-21T22:00Z)", 47.26, 11.35, 620.0, 4133109600.0, 180.0, 30.0},
  };
  for (const Case& c : cases) {
    for (uint32_t encoding : {ATMO_OUTPUT_LINEAR_HDR, ATMO_OUTPUT_DISPLAY_SRGB}) {
      AtmoViewState vs = geodetic_view(c.heading, c.pitch, projection);
      vs.eye_geodetic[0] = vs.world_origin_geodetic[0] = c.lat;
      vs.eye_geodetic[1] = vs.world_origin_geodetic[1] = c.lon;
      vs.eye_geodetic[2] = vs.world_origin_geodetic[2] = c.height_m;
      vs.output_encoding = encoding;
      vs.exposure_scale = 1.0 / (1.2 * 0.25);  // EV100 -2
      auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
      frame.utc_posix_s = c.utc_posix_s;
      f.context->set_frame(frame);
      f.view->set(vs);
      f.target->bind();
      f.target->clear(0.0f, 0.0f, 0.0f, 1.0f);
      ASSERT_EQ(f.view->render(ATMO_PASS_SKY), ATMO_SUCCESS) << c.name << ": "
                                                              << f.plugin->api().last_error(f.context->handle());
      const AtmoResult night = f.view->render(ATMO_PASS_NIGHT_SKY);
      ASSERT_TRUE(night == ATMO_SUCCESS || night == ATMO_STATUS_NOTHING_TO_DRAW)
          << c.name << ": " << f.plugin->api().last_error(f.context->handle());
      const auto img = f.target->read_color();
      int bad = 0;
      double peak = 0.0;
      for (size_t i = 0; i < img.pixel_count() * 4; ++i) {
        if (!std::isfinite(img.rgba[i]) || img.rgba[i] < 0.0f) ++bad;
        else peak = std::max(peak, double(img.rgba[i]));
      }
      if (encoding == ATMO_OUTPUT_LINEAR_HDR) {
        std::printf("[ night pass ] %-62s night pass %s, brightest exposed value %.3g\n", c.name,
                    night == ATMO_SUCCESS ? "drew" : "had nothing", peak);
      }
      EXPECT_EQ(bad, 0) << c.name << ", encoding " << encoding;
    }
  }
}
