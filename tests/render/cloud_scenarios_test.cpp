// The physics checks of the weather-at-scale scenarios (the EXRs of linear
// cd/m^2 that render_scenario_<name> writes; the layer march, cloud_draw_mode
// "layer"):
// - cumulus_8_oktas_horizon: the bases at the zenith against the diffusion
//   two-stream of the light above the layer through the columns over the eye
//   (two_stream.h, as overcast_low_sun's deck); the clouds are grey, not the
//   clear sky's blue (the zenith's blue/red ratio).
// - cirrus_overhead: the Sun's disc through the cirrus is the clear disc
//   (get_lighting without clouds, the disc's limb-darkening law) times the
//   Beer-Lambert transmittance along the Sun's ray, the generated field
//   marched independently (not hidden, not clear).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include <glm/glm.hpp>

#include "atmo/atmo.hpp"
#include "atmo_host_scene/camera.h"
#include "atmo_scenario/scenario.h"
#include "atmo_support/image.h"
#include "atmo_support/image_metrics.h"
#include "core/clouds/procedural_clouds.h"
#include "scenario_setup.h"
#include "two_stream.h"

namespace hs = atmo::host_scene;
namespace sc = atmo::scenario;
namespace tr = atmo::test_render;

namespace {

// The light at the eye's position with the scenario's air but no clouds.
AtmoLighting clear_lighting(const sc::Scenario& s, size_t ci, double height_enu_m) {
  AtmoHostServices services = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  atmo::Plugin plugin(ATMO_PLUGIN_PATH);
  atmo::Context context(plugin, &services);
  context.set_atmosphere(atmo::render::atmosphere_state_of(s));
  context.set_frame(atmo::render::frame_state_of(s));
  hs::ViewSetup setup = atmo::render::view_setup_of(s, ci, hs::DepthConvention::Reversed);
  setup.pose.position_enu_m.z = height_enu_m;
  atmo::View view(context, 0);
  view.set(hs::make_view_state(setup));
  return view.lighting();
}

atmo::clouds::CloudField field_of(const sc::Scenario& s, const sc::CloudLayer& layer,
                                  atmo::clouds::CloudLayerType type) {
  atmo::clouds::CloudLayerSpec spec;
  spec.type = type;
  spec.coverage_oktas = layer.coverage_oktas;
  spec.base_m = layer.base_m;
  spec.top_m = layer.top_m;
  spec.area_size_m = sc::cloud_layer_area_m(s, layer);
  spec.seed = layer.seed;  // atmo render's context seed is 0
  return atmo::clouds::generate_cloud_layer(spec).field;
}

TEST(CumulusToTheHorizon, TheBasesAgainstTheTwoStreamEstimate) {
  const sc::Scenario s = tr::load(ATMO_CUMULUS_8_OKTAS_JSON);
  ASSERT_EQ(s.clouds.size(), 1u);
  const sc::CloudLayer& layer = s.clouds[0];
  const size_t ci = tr::camera_index(s, "zenith");
  const AtmoLighting above = clear_lighting(s, ci, layer.top_m);
  const atmo::clouds::CloudField field = field_of(s, layer, atmo::clouds::CloudLayerType::Cumulus);
  const tr::ColumnTransmission t = tr::column_transmission(field, layer.base_m, layer.top_m, 400.0);
  const double estimate = tr::zenith_base_luminance(above, s.atmosphere.ground_albedo, t.diffuse);
  const atmo::support::Image img = tr::render_of(ATMO_CUMULUS_8_OKTAS_EXR_STEM, "zenith");
  const glm::dvec3 zenith = tr::mean_within(img, s.cameras[ci], 3.0);
  const float rgb[3] = {float(zenith.r), float(zenith.g), float(zenith.b)};
  const double l = atmo::support::luminance(rgb);
  std::printf("columns within 400 m: tau %.1f (mean), diffuse transmission %.3f; the bases at the zenith %.4g "
              "cd/m^2 estimated, %.4g rendered (%.3fx); blue/red %.3f\n",
              t.tau_mean, t.diffuse, estimate, l, l / estimate, zenith.b / zenith.r);
  // The tolerance of overcast_low_sun's deck (tests/render/overcast_low_sun_test.cpp),
  // widened below for the light that broken cumulus lets in through its sides
  // and gaps, which the slab's estimate has not.
  EXPECT_GT(l / estimate, 0.75);
  EXPECT_LT(l / estimate, 2.0);
  // Clouds scatter all colours alike: the bases take the colour of the light
  // through them (the Sun's, warmer than white, and the ground's bounce:
  // blue/red 0.77 measured), not the clear sky's blue (blue/red > 2).
  EXPECT_LT(zenith.b / zenith.r, 1.3);
  EXPECT_GT(zenith.b / zenith.r, 0.6);
}

TEST(CirrusOverhead, TheSunsDiscDimmedByTheCirrusAlongItsRay) {
  const sc::Scenario s = tr::load(ATMO_CIRRUS_OVERHEAD_JSON);
  ASSERT_EQ(s.clouds.size(), 1u);
  const sc::CloudLayer& layer = s.clouds[0];
  const size_t ci = tr::camera_index(s, "sun");
  const sc::Camera& cam = s.cameras[ci];
  ASSERT_EQ(cam.position.kind, sc::Position::Kind::Enu);
  const AtmoLighting clear = clear_lighting(s, ci, cam.position.enu_m[2]);
  const glm::dvec3 sun(clear.sun_direction_enu[0], clear.sun_direction_enu[1], clear.sun_direction_enu[2]);
  // The optical depth along the Sun's ray, 2 m steps through the layer.
  const atmo::clouds::CloudField field = field_of(s, layer, atmo::clouds::CloudLayerType::Cirrus);
  const double extinction = field.prototypes.at(0).optics.extinction_per_m;
  const glm::dvec3 eye(cam.position.enu_m[0], cam.position.enu_m[1], cam.position.enu_m[2]);
  double tau = 0.0;
  const double t0 = (layer.base_m - 50.0 - eye.z) / sun.z, t1 = (layer.top_m + 50.0 - eye.z) / sun.z;
  for (double t = t0; t < t1; t += 2.0)
    tau += atmo::clouds::field_density_at(field, eye + sun * (t + 1.0)) * 2.0 * extinction;
  const double transmittance = std::exp(-tau);
  // The clear disc's luminance at each pixel (the grey u = 0.6 limb-darkening
  // law of shaders/atmosphere/functions.glsl, mean 1 over the disc) within
  // 0.2 deg of the Sun's centre (the disc's radius is 0.2666 deg).
  const atmo::support::Image img = tr::render_of(ATMO_CIRRUS_OVERHEAD_EXR_STEM, "sun");
  const double radius = 0.2666 * M_PI / 180.0;
  const double omega = 2.0 * M_PI * (1.0 - std::cos(radius));
  const double rad_per_px = cam.vertical_fov_deg * M_PI / 180.0 / cam.height;
  double rendered = 0.0, clear_disc = 0.0;
  int n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double r = tr::from_centre(img, x, y) * rad_per_px;  // small angles
      if (r > 0.2 * M_PI / 180.0) continue;
      const double q = r / radius, mu = std::sqrt(std::max(0.0, 1.0 - q * q));
      clear_disc += clear.sun_illuminance_lux[1] / omega * (1.0 - 0.6 * (1.0 - mu)) / (1.0 - 0.6 / 3.0);
      rendered += atmo::support::luminance(img.pixel(x, y));
      ++n;
    }
  ASSERT_GT(n, 100);
  rendered /= n;
  clear_disc /= n;
  const double ratio = rendered / (clear_disc * transmittance);
  std::printf("the Sun's ray through the cirrus: optical depth %.3f, transmittance %.3f; the disc within 0.2 deg: "
              "clear %.4g cd/m^2 (mean), rendered %.4g (%.3f of clear; %.3fx the clear disc x transmittance)\n",
              tau, transmittance, clear_disc, rendered, rendered / clear_disc, ratio);
  ASSERT_LT(transmittance, 0.9) << "the scenario's cirrus must cover the Sun for the check to mean anything";
  ASSERT_GT(transmittance, 1e-3);
  // The march's clipmap averages the cirrus over its voxels and the cirrus's
  // forward-scattered light adds to the disc: 20 %.
  EXPECT_NEAR(ratio, 1.0, 0.2);
}

}  // namespace
