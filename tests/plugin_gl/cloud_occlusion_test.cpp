// The sky's bodies behind clouds (issue 19): the Sun's disc, drawn by the sky
// pass before the clouds, seen from below and from inside a thick overcast
// deck contributes < 1e-6 of its clear value; the night pass's Moon, planets
// and stars behind the deck are gone, and the same sky with the deck off the
// line of sight is unchanged; get_lighting's Sun and Moon under the deck are
// dimmed by the clouds' transmittance (0), and unchanged above it or with the
// deck elsewhere.
#include <glad/gl.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "atmo_support/image.h"
#include "atmo_support/image_metrics.h"
#include "plugin_gl_fixture.h"

namespace {

using namespace plugin_gl;
using atmo::support::Image;
using atmo::support::luminance;

constexpr double kNoonUtc = 1718964000.0;    // 2024-06-21T10:00Z: the Sun ~60 deg up at Innsbruck
constexpr double kLowSunUtc = 1718989200.0;  // 2024-06-21T17:00Z: the Sun ~14 deg up, west-north-west
constexpr double kMoonUtc = 1734220800.0;    // 2024-12-15T00:00Z: a full Moon ~60
                                             // deg up, the Sun far below

// A 12 km overcast deck, 600-1100 m (tau >= 11.5 vertically), centred on the
// eye or moved `east_m` away.
AtmoCloudLayer deck(double east_m = 0.0) { return overcast_deck(12000.0, east_m); }

void set_clouds(Fixture& f, const AtmoCloudLayer* layer) {
  const AtmoCloudsState s = clouds_at_innsbruck(layer, layer ? 1 : 0);
  ASSERT_EQ(f.plugin->api().set_clouds(f.context->handle(), &s), ATMO_SUCCESS) << f.context->last_error();
}

AtmoLighting lighting_at(Fixture& f, double utc, double height_m) {
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = utc;
  f.context->set_frame(frame);
  const glm::dmat4 proj = glm::perspective(glm::radians(60.0), double(kWidth) / kHeight, 1.0, 1e5);
  f.view->set(innsbruck_view(height_m, 0.0, 0.0, proj));
  return f.view->lighting();
}

// The passes drawn in order over black, looking at a direction (azimuth,
// elevation in radians) through a 6 deg field (the Sun's disc ~6 pixels
// across).
Image draw(Fixture& f, double utc, double height_m, double azimuth_rad, double elevation_rad,
           const std::vector<AtmoPassKind>& passes) {
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = utc;
  f.context->set_frame(frame);
  const glm::dmat4 proj = glm::perspective(glm::radians(6.0), double(kWidth) / kHeight, 1.0, 1e5);
  f.view->set(innsbruck_view(height_m, glm::degrees(azimuth_rad), glm::degrees(elevation_rad), proj));
  f.target->bind();
  glClearColor(0, 0, 0, 0);
  glClear(GL_COLOR_BUFFER_BIT);
  for (AtmoPassKind p : passes) EXPECT_GE(f.view->render(p), 0) << f.context->last_error();
  glFinish();
  return f.target->read_color();
}

// What the passes before the clouds leave after the clouds: (all passes) -
// (the clouds alone over black) = T * background, per pixel; its largest
// luminance over the frame, and the background's (clear) largest.
struct Leak {
  double through = 0.0;    // cd/m^2, the background's largest luminance after the clouds
  double clear = 0.0;      // cd/m^2, the same without the clouds
  double frame_max = 0.0;  // the whole frame's largest luminance, and its mean
  double frame_mean = 0.0;
};

Leak leak(Fixture& f, double utc, double height_m, double az, double el, std::vector<AtmoPassKind> background,
          const AtmoCloudLayer* layer) {
  Leak r;
  set_clouds(f, nullptr);
  const Image clear = draw(f, utc, height_m, az, el, background);
  set_clouds(f, layer);
  background.push_back(ATMO_PASS_CLOUDS);
  const Image all = draw(f, utc, height_m, az, el, background);
  const Image clouds = draw(f, utc, height_m, az, el, {ATMO_PASS_CLOUDS});
  EXPECT_EQ(atmo::support::count_nonfinite(all), 0u);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      r.clear = std::max(r.clear, luminance(clear.pixel(x, y)));
      r.through = std::max(r.through, luminance(all.pixel(x, y)) - luminance(clouds.pixel(x, y)));
      r.frame_max = std::max(r.frame_max, luminance(all.pixel(x, y)));
      r.frame_mean += luminance(all.pixel(x, y)) / (kWidth * kHeight);
    }
  return r;
}

TEST(CloudOcclusion, TheSunsDiscDoesNotShineThroughADeck) {
  Fixture f;
  for (double utc : {kNoonUtc, kLowSunUtc}) {
    const AtmoLighting l = lighting_at(f, utc, 300.0);
    ASSERT_GT(l.sun_elevation_rad, glm::radians(5.0));
    const AtmoCloudLayer d = deck();
    for (double height : {300.0, 650.0}) {  // below the deck, inside it (50 m above its base)
      const Leak k = leak(f, utc, height, l.sun_azimuth_rad, l.sun_elevation_rad, {ATMO_PASS_SKY}, &d);
      std::printf(
          "Sun %.1f deg up, eye at %.0f m: the disc %.3g cd/m^2 clear, "
          "%.3g through the deck (%.2e of "
          "clear); frame's brightest %.3g = %.2fx its mean\n",
          glm::degrees(l.sun_elevation_rad), height, k.clear, k.through, k.through / k.clear, k.frame_max,
          k.frame_max / k.frame_mean);
      EXPECT_GT(k.clear, 1e8);  // the disc is in the frame
      EXPECT_LT(k.through, 1e-6 * k.clear);
    }
    // The deck off the line of sight: the disc as clear (the deck 40 km east).
    const AtmoCloudLayer away = deck(40000.0);
    const Leak k = leak(f, utc, 300.0, l.sun_azimuth_rad, l.sun_elevation_rad, {ATMO_PASS_SKY}, &away);
    std::printf("  the deck 40 km east: the disc %.4g of clear\n", k.through / k.clear);
    EXPECT_NEAR(k.through / k.clear, 1.0, 1e-3);
  }
}

TEST(CloudOcclusion, TheMoonPlanetsAndStarsAreHiddenByADeck) {
  Fixture f;
  const AtmoLighting l = lighting_at(f, kMoonUtc, 300.0);
  ASSERT_GT(l.moon_elevation_rad, glm::radians(20.0));
  ASSERT_LT(l.sun_elevation_rad, glm::radians(-18.0));
  const AtmoCloudLayer d = deck();
  for (double height : {300.0, 650.0}) {
    const Leak k =
        leak(f, kMoonUtc, height, l.moon_azimuth_rad, l.moon_elevation_rad, {ATMO_PASS_SKY, ATMO_PASS_NIGHT_SKY}, &d);
    std::printf(
        "the Moon %.1f deg up, eye at %.0f m: %.3g cd/m^2 clear, %.3g "
        "through the deck (%.2e)\n",
        glm::degrees(l.moon_elevation_rad), height, k.clear, k.through, k.through / k.clear);
    EXPECT_GT(k.clear, 100.0);  // the Moon's disc is in the frame
    EXPECT_LT(k.through, 1e-6 * k.clear);
  }
  // Stars: the sky overhead, the night pass alone (its points: stars and
  // planets).
  const AtmoCloudLayer away = deck(40000.0);
  const Leak near = leak(f, kMoonUtc, 300.0, 0.0, glm::radians(80.0), {ATMO_PASS_NIGHT_SKY}, &d);
  const Leak clear =
      leak(f, kMoonUtc, 300.0, l.moon_azimuth_rad, l.moon_elevation_rad, {ATMO_PASS_SKY, ATMO_PASS_NIGHT_SKY}, &away);
  std::printf(
      "the sky overhead: brightest %.3g cd/m^2 clear, %.3g through the "
      "deck; the Moon with the deck "
      "40 km east: %.5f of clear\n",
      near.clear, near.through, clear.through / clear.clear);
  EXPECT_GT(near.clear, 0.0);
  EXPECT_LT(near.through, 1e-6 * near.clear);
  EXPECT_NEAR(clear.through / clear.clear, 1.0, 1e-3);
}

TEST(CloudOcclusion, GetLightingsSunAndMoonAreDimmedByTheClouds) {
  Fixture f;
  const AtmoCloudLayer d = deck(), away = deck(40000.0);
  for (double utc : {kNoonUtc, kLowSunUtc}) {
    for (double height : {300.0, 650.0, 1500.0}) {
      set_clouds(f, nullptr);
      const double clear = lighting_at(f, utc, height).sun_illuminance_lux[1];
      set_clouds(f, &d);
      const double under = lighting_at(f, utc, height).sun_illuminance_lux[1];
      set_clouds(f, &away);
      const double elsewhere = lighting_at(f, utc, height).sun_illuminance_lux[1];
      std::printf(
          "sun at %.0f UTC, eye at %.0f m: %.4g lx clear, %.3g with "
          "the deck (%.2e), %.6g with it 40 km "
          "east\n",
          utc, height, clear, under, under / clear, elsewhere);
      ASSERT_GT(clear, 1000.0);
      if (height < 1100.0)
        EXPECT_LT(under, 1e-6 * clear);
      else
        EXPECT_EQ(under, clear);  // above the deck
      EXPECT_EQ(elsewhere, clear);
      EXPECT_GE(under, 0.0);
    }
  }
  set_clouds(f, nullptr);
  const double moon_clear = lighting_at(f, kMoonUtc, 300.0).moon_illuminance_lux[1];
  set_clouds(f, &d);
  const double moon_under = lighting_at(f, kMoonUtc, 300.0).moon_illuminance_lux[1];
  std::printf("the Moon: %.3g lx clear, %.3g under the deck\n", moon_clear, moon_under);
  EXPECT_GT(moon_clear, 0.05);
  EXPECT_LT(moon_under, 1e-6 * moon_clear);
}

}  // namespace
