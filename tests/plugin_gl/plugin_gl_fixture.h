// Shared set-up of the plugin GL tests: a headless context, the plugin
// loaded through the host SDK, one context and view, an offscreen target.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>

#include "atmo/atmo.hpp"
#include "atmo_support/example_view.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/offscreen_target.h"

namespace plugin_gl {

using atmo::support::HeadlessGl;
using atmo::support::OffscreenTarget;

constexpr int kWidth = 96;
constexpr int kHeight = 64;
// Times at the fixture's place, Innsbruck (47.26 N, 11.35 E).
constexpr double kJulyNightUtc = 1.72e9 + 12 * 3600.0;  // 2024-07-03 21:46 UTC: the Sun well below the horizon

struct Fixture {
  std::unique_ptr<HeadlessGl> gl;
  std::unique_ptr<atmo::Plugin> plugin;
  std::unique_ptr<atmo::Context> context;
  std::unique_ptr<atmo::View> view;
  std::unique_ptr<OffscreenTarget> target;
  AtmoHostServices services = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);

  Fixture() {
    std::string error;
    gl = HeadlessGl::create(HeadlessGl::Profile::Core, &error);
    if (!gl) throw std::runtime_error("no headless GL context: " + error);
    services.gl_get_proc_address = &HeadlessGl::get_proc_address;
    plugin = std::make_unique<atmo::Plugin>(ATMO_PLUGIN_PATH);
    context = std::make_unique<atmo::Context>(*plugin, &services);
    context->gl_init();
    view = std::make_unique<atmo::View>(*context, 0);
    target = OffscreenTarget::create(kWidth, kHeight, &error);
    if (!target) throw std::runtime_error("offscreen target: " + error);
  }

  void set_utc(double utc_posix_s) {
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = utc_posix_s;
    context->set_frame(frame);
  }

  // A new context and view on the same GL context and plugin. A new context
  // builds its lookup tables on first use, synchronously, so it draws the air it
  // is given in its very first frame; a context whose air changes keeps drawing
  // the old air until the new tables come from its worker thread (~0.4 s of CPU, longer on a loaded machine). Tests
  // that compare a frame with the air they just set therefore use a new context.
  void fresh_context() {
    view.reset();
    context.reset();  // gl_shutdown, destroy_context
    context = std::make_unique<atmo::Context>(*plugin, &services);
    context->gl_init();
    view = std::make_unique<atmo::View>(*context, 0);
  }
};

inline glm::dmat4 look(double heading_deg, double pitch_deg) {
  // ENU world; camera looks along heading/pitch, +y up.
  double h = glm::radians(heading_deg), p = glm::radians(pitch_deg);
  glm::dvec3 forward(std::sin(h) * std::cos(p), std::cos(h) * std::cos(p), std::sin(p));
  return glm::lookAt(glm::dvec3(0.0), forward, glm::dvec3(0, 0, 1));
}

inline void copy(const glm::dmat4& m, double out[16]) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[c * 4 + r] = m[c][r];
}

// example_view_state's view over Innsbruck (47.26° N, 11.35° E, ENU world
// there) at `height_m`, turned to heading/pitch through `projection`, with no
// depth texture and output in cd/m^2 (exposure 1).
inline AtmoViewState innsbruck_view(double height_m, double heading_deg, double pitch_deg,
                                    const glm::dmat4& projection) {
  AtmoViewState vs = atmo::support::example_view_state(kWidth, kHeight, 0, height_m);
  copy(look(heading_deg, pitch_deg), vs.view_from_world);
  copy(projection, vs.clip_from_view);
  vs.exposure_scale = 1.0;
  return vs;
}

// A cumulus layer (5 oktas, 6 km area, seed 4) between base and top metres.
inline AtmoCloudLayer cumulus(double base = 1200.0, double top = 2200.0) {
  AtmoCloudLayer l = atmo::make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
  l.type = ATMO_CLOUD_CUMULUS;
  l.coverage_oktas = 5;
  l.base_m = base;
  l.top_m = top;
  l.area_size_m = 6000.0;
  l.seed = 4;
  return l;
}

// An overcast deck (8 oktas, seed 2) 600-1100 m, `area_m` across, its centre
// `east_m` east of innsbruck_view's place.
inline AtmoCloudLayer overcast_deck(double area_m, double east_m = 0.0) {
  AtmoCloudLayer d = atmo::make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
  d.type = ATMO_CLOUD_OVERCAST;
  d.coverage_oktas = 8;
  d.base_m = 600.0;
  d.top_m = 1100.0;
  d.area_size_m = area_m;
  d.area_centre_enu_m[0] = east_m;
  d.seed = 2;
  return d;
}

// Cloud layers over innsbruck_view's place (height 0).
inline AtmoCloudsState clouds_at_innsbruck(const AtmoCloudLayer* layers, uint32_t count) {
  AtmoCloudsState s = atmo::make<AtmoCloudsState>(ATMO_TYPE_CLOUDS_STATE);
  s.origin_geodetic[0] = 47.26;
  s.origin_geodetic[1] = 11.35;
  s.origin_geodetic[2] = 0.0;
  s.layers = layers;
  s.layer_count = count;
  s.setup = ATMO_CLOUD_SETUP_WAIT;  // a frame is a function of its inputs, whatever mode AUTO picks
  return s;
}

}  // namespace plugin_gl
