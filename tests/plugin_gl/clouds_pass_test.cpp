// The cloud pass through the ABI: set_clouds validation (each bad field named,
// nothing changed), a missing or corrupt VDB file refusing the whole call
// (clouds unchanged), no clouds -> no cost, and finite output where the march
// is known to be fragile: inside a cloud, above a deck, the Sun below the
// horizon, far from the origin.
#include <glad/gl.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "plugin_gl_fixture.h"
#include "atmo_support/image.h"
#include "atmo_support/image_metrics.h"

namespace {

using namespace plugin_gl;

AtmoResult raw_set_clouds(Fixture& f, const AtmoCloudsState& s) {
  return f.plugin->api().set_clouds(f.context->handle(), &s);
}

// Renders the clouds pass alone over black; returns the pass's result.
AtmoResult draw_clouds(Fixture& f, double height_m, double pitch_deg, atmo::support::Image* out, double utc = 1.72e9) {
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = utc;
  f.context->set_frame(frame);
  const glm::dmat4 proj = glm::perspective(glm::radians(60.0), double(kWidth) / kHeight, 1.0, 1e5);
  AtmoViewState vs = innsbruck_view(height_m, 0.0, pitch_deg, proj);
  f.view->set(vs);
  f.target->bind();
  glClearColor(0, 0, 0, 0);
  glClear(GL_COLOR_BUFFER_BIT);
  const AtmoResult r = f.view->render(ATMO_PASS_CLOUDS);
  glFinish();
  *out = f.target->read_color();
  return r;
}

size_t count_bad(const atmo::support::Image& img) { return atmo::support::count_nonfinite(img); }

double mean_luminance(const atmo::support::Image& img) {
  double s = 0.0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) s += atmo::support::luminance(img.pixel(x, y));
  return s / (img.width * img.height);
}

TEST(CloudsPass, NoCloudsCostsNothing) {
  Fixture f;
  atmo::support::Image img;
  EXPECT_EQ(draw_clouds(f, 500.0, 10.0, &img), ATMO_STATUS_NOTHING_TO_DRAW);
  const AtmoCloudsState none = clouds_at_innsbruck(nullptr, 0);
  EXPECT_EQ(raw_set_clouds(f, none), ATMO_SUCCESS);
  EXPECT_EQ(draw_clouds(f, 500.0, 10.0, &img), ATMO_STATUS_NOTHING_TO_DRAW);
}

TEST(CloudsPass, InvalidStatesAreRejectedWithTheFieldNamed) {
  Fixture f;
  AtmoCloudLayer good = cumulus();
  struct Case {
    const char* what;
    AtmoCloudLayer layer;
    AtmoResult code;
    const char* message;
  };
  std::vector<Case> cases;
  AtmoCloudLayer l = good;
  l.type = 99;
  cases.push_back({"bad type", l, ATMO_ERROR_INVALID_ARGUMENT, "layers[0].type = 99"});
  l = good;
  l.base_m = std::nan("");
  cases.push_back({"NaN base", l, ATMO_ERROR_NON_FINITE_VALUE, "layers[0]"});
  l = good;
  l.top_m = 900.0;
  cases.push_back({"top below base", l, ATMO_ERROR_OUT_OF_RANGE, "base_m"});
  l = good;
  l.coverage_oktas = 9;
  cases.push_back({"9 oktas", l, ATMO_ERROR_OUT_OF_RANGE, "coverage_oktas = 9"});
  l = good;
  l.header.struct_size = 40;
  cases.push_back({"undersized layer", l, ATMO_ERROR_STRUCT_TOO_SMALL, "struct_size is 40"});
  l = good;
  l.type = ATMO_CLOUD_VDB_FILE;
  cases.push_back({"vdb without a path", l, ATMO_ERROR_INVALID_ARGUMENT, "vdb_path is NULL"});
  for (const Case& c : cases) {
    const AtmoCloudsState s = clouds_at_innsbruck(&c.layer, 1);
    EXPECT_EQ(raw_set_clouds(f, s), c.code) << c.what;
    EXPECT_NE(f.context->last_error().find(c.message), std::string::npos) << c.what << ": " << f.context->last_error();
  }
  // The state's own enums.
  AtmoCloudsState bad_setup = clouds_at_innsbruck(&good, 1);
  bad_setup.setup = ATMO_CLOUD_SETUP_COUNT;
  EXPECT_EQ(raw_set_clouds(f, bad_setup), ATMO_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(f.context->last_error().find("AtmoCloudsState.setup = 2"), std::string::npos) << f.context->last_error();
  // Nothing changed: still no clouds.
  atmo::support::Image img;
  EXPECT_EQ(draw_clouds(f, 500.0, 10.0, &img), ATMO_STATUS_NOTHING_TO_DRAW);
}

// All or nothing (atmo.h): a call with a missing or corrupt VDB file is
// refused with ATMO_ERROR_IO and the clouds stay as they were, from no clouds
// and from a deck already set. (Before, the good layers of the call replaced
// the clouds: this test then drew the new seed's clouds.)
TEST(CloudsPass, ABadVdbFileRefusesTheCallAndKeepsTheClouds) {
  Fixture f;
  const std::string corrupt = ::testing::TempDir() + "atmo_corrupt.vdb";
  std::ofstream(corrupt, std::ios::binary) << "not a vdb file at all";
  AtmoCloudLayer layers[3] = {cumulus(), cumulus(), cumulus()};
  layers[0].seed = 77;  // other clouds than those kept
  layers[1].type = ATMO_CLOUD_VDB_FILE;
  layers[1].vdb_path = "/nonexistent/cloud.vdb";
  layers[2].type = ATMO_CLOUD_VDB_FILE;
  layers[2].vdb_path = corrupt.c_str();
  const AtmoCloudsState bad_call = clouds_at_innsbruck(layers, 3);
  atmo::support::Image img;
  EXPECT_EQ(raw_set_clouds(f, bad_call), ATMO_ERROR_IO);
  const std::string e = f.context->last_error();
  std::printf("set_clouds: %s\n", e.c_str());
  EXPECT_NE(e.find("layers[1]"), std::string::npos) << e;
  EXPECT_NE(e.find("/nonexistent/cloud.vdb"), std::string::npos) << e;
  EXPECT_EQ(draw_clouds(f, 500.0, 15.0, &img), ATMO_STATUS_NOTHING_TO_DRAW);  // still no clouds

  const AtmoCloudLayer deck = cumulus();
  ASSERT_EQ(raw_set_clouds(f, clouds_at_innsbruck(&deck, 1)), ATMO_SUCCESS);
  atmo::support::Image before, after;
  ASSERT_EQ(draw_clouds(f, 500.0, 15.0, &before), ATMO_SUCCESS);
  ASSERT_GT(mean_luminance(before), 0.0);
  EXPECT_EQ(raw_set_clouds(f, bad_call), ATMO_ERROR_IO);
  ASSERT_EQ(draw_clouds(f, 500.0, 15.0, &after), ATMO_SUCCESS);
  const auto diff = atmo::support::compare_images(before, after, 1.0);
  std::printf("clouds after a refused set_clouds: max |difference| %.3g\n", diff.max_abs);
  EXPECT_EQ(diff.max_abs, 0.0) << "the refused call changed the clouds";
  EXPECT_EQ(count_bad(after), 0u);
}

TEST(CloudsPass, FiniteWhereTheMarchIsFragile) {
  Fixture f;
  const AtmoCloudLayer layer = cumulus(1200.0, 2200.0);
  const AtmoCloudsState s = clouds_at_innsbruck(&layer, 1);
  ASSERT_EQ(raw_set_clouds(f, s), ATMO_SUCCESS);
  struct Case {
    const char* what;
    double height_m, pitch_deg, utc;
  };
  const Case cases[] = {
      {"below the layer, noon", 500.0, 20.0, 1.72e9},
      {"inside the layer", 1700.0, 0.0, 1.72e9},
      {"above the layer looking down", 4000.0, -45.0, 1.72e9},
      {"night (Sun below the horizon)", 500.0, 20.0, 1.72e9 + 12 * 3600},
      {"high above", 60000.0, -60.0, 1.72e9},
  };
  for (const Case& c : cases) {
    atmo::support::Image img;
    const AtmoResult r = draw_clouds(f, c.height_m, c.pitch_deg, &img, c.utc);
    EXPECT_GE(r, 0) << c.what;
    EXPECT_EQ(count_bad(img), 0u) << c.what;
    std::printf("%-32s %s, mean %.4g cd/m^2\n", c.what, f.plugin->result_string(r).c_str(), mean_luminance(img));
  }
}

// Seen from above, an overcast deck hides the ground (issue: <= 1 %): the host's frame shows
// through by the clouds' transmittance, measured by drawing the clouds over
// two host colours (premultiplied blending: out = clouds + T * host).
TEST(CloudsPass, AnOvercastDeckHidesTheGroundFromAbove) {
  Fixture f;
  const AtmoCloudLayer deck = overcast_deck(8000.0);
  const AtmoCloudsState s = clouds_at_innsbruck(&deck, 1);
  ASSERT_EQ(raw_set_clouds(f, s), ATMO_SUCCESS);
  auto draw_over = [&](float host_red) {
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = 1.72e9;
    f.context->set_frame(frame);
    const glm::dmat4 proj = glm::perspective(glm::radians(40.0), double(kWidth) / kHeight, 1.0, 1e5);
    f.view->set(innsbruck_view(2500.0, 30.0, -70.0, proj));
    f.target->bind();
    glClearColor(host_red, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    EXPECT_EQ(f.view->render(ATMO_PASS_CLOUDS), ATMO_SUCCESS);
    glFinish();
    return f.target->read_color();
  };
  const float red = 1.0e4f;
  const atmo::support::Image black = draw_over(0.0f), lit = draw_over(red);
  double worst = 0.0, mean = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const double t = (lit.pixel(x, y)[0] - black.pixel(x, y)[0]) / red;
      worst = std::max(worst, t);
      mean += t / (kWidth * kHeight);
    }
  std::printf("ground seen through the deck from 2500 m: transmittance mean %.2e, worst pixel %.2e\n", mean, worst);
  EXPECT_LE(worst, 0.01);
  EXPECT_EQ(count_bad(black), 0u);
}

// The Sun crossing the horizon under a cumulus layer: every frame finite and
// the clouds never brighter at a lower Sun (the light fades through sunset).
TEST(CloudsPass, SunCrossingTheHorizon) {
  Fixture f;
  const AtmoCloudLayer layer = cumulus(1200.0, 2200.0);
  ASSERT_EQ(raw_set_clouds(f, clouds_at_innsbruck(&layer, 1)), ATMO_SUCCESS);
  // 2024-06-14 19:00-20:20 UTC at Innsbruck: the Sun sets about 19:15 UTC.
  double previous = 1e30;
  for (double minutes = 0.0; minutes <= 80.0; minutes += 10.0) {
    atmo::support::Image img;
    const double utc = 1718391600.0 + minutes * 60.0;
    const AtmoResult r = draw_clouds(f, 500.0, 20.0, &img, utc);
    EXPECT_GE(r, 0);
    EXPECT_EQ(count_bad(img), 0u) << minutes;
    const double m = mean_luminance(img);
    std::printf("19:00 UTC + %2.0f min: mean %.4g cd/m^2\n", minutes, m);
    EXPECT_GE(m, 0.0);
    EXPECT_LE(m, previous * 1.05 + 1e-6) << "brighter after " << minutes << " min";
    previous = m;
  }
}

}  // namespace

// The sky passes use the clouds' shadow map: the sunlit haze in front of the
// host's geometry (20 km away, the aerial-perspective pass over black, so
// the image is the in-scattered light alone) darkens under an overcast deck
// (the Sun's single scattering goes, the air's multiple scattering keeps the
// deck's diffuse transmission), and is left as it is when the same deck lies
// far from the view.
// The mean luminance (cd/m^2) of rows [row_begin, row_end) (row 0 at the top)
// of one pass drawn from 300 m at Innsbruck at noon, looking north level,
// under `layer` (nullptr: no clouds): the aerial-perspective pass over black
// with geometry 20 km away in the lower half (`depth`), or the sky pass with
// no host depth.
double luminance_under(Fixture& f, const AtmoCloudLayer* layer, AtmoPassKind pass, GLuint depth, double vfov_deg,
                       int row_begin, int row_end) {
  const AtmoCloudsState s = clouds_at_innsbruck(layer, layer ? 1 : 0);
  EXPECT_EQ(raw_set_clouds(f, s), ATMO_SUCCESS) << f.context->last_error();
  auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  frame.utc_posix_s = 1718964000.0;  // 2024-06-21T10:00Z: the Sun ~60 deg up
  f.context->set_frame(frame);
  const glm::dmat4 proj = glm::perspective(glm::radians(vfov_deg), double(kWidth) / kHeight, 1.0, 1e5);
  AtmoViewState vs = innsbruck_view(300.0, 0.0, 0.0, proj);
  vs.depth_texture = pass == ATMO_PASS_SKY ? 0 : depth;
  f.view->set(vs);
  f.target->bind();
  glClearColor(0, 0, 0, 0);
  glClear(GL_COLOR_BUFFER_BIT);
  EXPECT_EQ(f.view->render(pass), ATMO_SUCCESS) << f.context->last_error();
  glFinish();
  const atmo::support::Image img = f.target->read_color();
  EXPECT_EQ(count_bad(img), 0u);
  double sum = 0.0;
  int n = 0;
  for (int y = row_begin; y < row_end; ++y)
    for (int x = 0; x < img.width; ++x, ++n) sum += atmo::support::luminance(img.pixel(x, y));
  return sum / n;
}

// A 46 km overcast deck, 600-1100 m, centred on the eye (or moved away).
AtmoCloudLayer overcast_deck() { return plugin_gl::overcast_deck(46000.0); }

TEST(CloudsPass, TheHazeUnderAnOvercastDeckIsInItsShadow) {
  Fixture f;
  const GLuint depth = atmo::support::make_split_depth_texture(kWidth, kHeight, 0.99995f);
  auto haze = [&](const AtmoCloudLayer* layer) {  // the lower half: the geometry
    return luminance_under(f, layer, ATMO_PASS_AERIAL_PERSPECTIVE, depth, 60.0, kHeight / 2 + 2, kHeight);
  };
  AtmoCloudLayer deck = overcast_deck();
  const double clear = haze(nullptr);
  const double under = haze(&deck);
  deck.area_centre_enu_m[0] = -150000.0;  // the same deck 150 km west, its shadow off the view
  const double elsewhere = haze(&deck);
  std::printf("haze over geometry 20 km away (cd/m^2): clear %.1f, under an overcast %.2f (%.4f of clear), "
              "the deck 150 km away %.1f (%.5f)\n",
              clear, under, under / clear, elsewhere, elsewhere / clear);
  EXPECT_GT(clear, 100.0);
  EXPECT_LT(under, 0.3 * clear);
  EXPECT_GT(under, 0.01 * clear);  // the deck's diffuse light
  EXPECT_NEAR(elsewhere / clear, 1.0, 1e-3);
  glDeleteTextures(1, &depth);
}

// The sky dome just above the horizon, seen under the same deck: its rays run
// ~23 km through the deck's shadow before they leave it at the deck's edge
// (the sky pass takes the shadowed light off the sky-view table along that
// part, sky_pixel.glsl ATMO_SKY_CLOUD_SHADOW), so the horizon darkens, though
// less than the haze in front of geometry 20 km away, whose whole path is in
// the shadow; the same deck far away changes nothing.
TEST(CloudsPass, TheHorizonSkyUnderAnOvercastDeckIsInItsShadow) {
  Fixture f;
  auto horizon = [&](const AtmoCloudLayer* layer) {  // 10 deg field: the 3 rows above the horizon, 0-0.47 deg up
    return luminance_under(f, layer, ATMO_PASS_SKY, 0, 10.0, kHeight / 2 - 3, kHeight / 2);
  };
  AtmoCloudLayer deck = overcast_deck();
  const double clear = horizon(nullptr);
  const double under = horizon(&deck);
  deck.area_centre_enu_m[0] = -150000.0;
  const double elsewhere = horizon(&deck);
  std::printf("sky 0-0.5 deg above the horizon (cd/m^2): clear %.1f, under an overcast %.1f (%.3f of clear), "
              "the deck 150 km away %.1f (%.5f)\n",
              clear, under, under / clear, elsewhere, elsewhere / clear);
  EXPECT_GT(clear, 1000.0);
  EXPECT_LT(under, 0.9 * clear);
  EXPECT_GT(under, 0.2 * clear);  // beyond the deck's edge the air is sunlit
  EXPECT_NEAR(elsewhere / clear, 1.0, 1e-3);
}
