#pragma once
// One camera of a scenario drawn with ATMO_PASS_LIGHT_POINTS alone, over black:
// the lights' direct images exactly as `atmo render` draws them last in its
// frame (the same air, fog, lights and view through tools/atmo's
// scenario_setup, and the host terrain's depth, which hides lights behind it),
// without the passes before it. A scenario's render less this image is
// everything else (the fog, the glows, the lit ground); its sum of L x Omega
// over a window is the illuminance the points bring to the eye.
#include <glad/gl.h>

#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "atmo/atmo.hpp"
#include "atmo_host_scene/camera.h"
#include "atmo_host_scene/depth_setup.h"
#include "atmo_host_scene/terrain.h"
#include "atmo_scenario/scenario.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/image.h"
#include "atmo_support/offscreen_target.h"
#include "scenario_setup.h"

namespace atmo::test_render {

// The depth convention `atmo render` uses for the scenario (its file's; the
// other two give the same image: depth_*_matches_*).
inline host_scene::DepthConvention render_depth_of(const scenario::Scenario& s) {
  switch (s.render.depth_convention) {
    case scenario::DepthConvention::Standard: return host_scene::DepthConvention::Standard;
    case scenario::DepthConvention::Logarithmic: return host_scene::DepthConvention::Logarithmic;
    default: return host_scene::DepthConvention::Reversed;
  }
}

// A headless GL context, the plugin and the host terrain set up once for camera `ci` of `s` as atmo render
// sets them up (its air, fog and view); render() draws the points of a light list.
class LightPointsOnly {
 public:
  LightPointsOnly(const scenario::Scenario& s, size_t ci, const char* plugin_path)
      : scenario_(s), ci_(ci), depth_(render_depth_of(s)) {
    namespace hs = atmo::host_scene;
    std::string error;
    gl_ = support::HeadlessGl::create(support::HeadlessGl::Profile::Core, &error);
    if (!gl_) throw std::runtime_error("no headless OpenGL context: " + error);
    const scenario::Camera& cam = s.cameras.at(ci);
    target_ = support::OffscreenTarget::create(cam.width, cam.height, &error);
    if (!target_) throw std::runtime_error("offscreen target: " + error);
    AtmoHostServices services = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
    services.gl_get_proc_address = &support::HeadlessGl::get_proc_address;
    plugin_.emplace(plugin_path, "light points only");
    context_.emplace(*plugin_, &services);
    context_->gl_init();
    context_->set_atmosphere(atmo::render::atmosphere_state_of(s));
    context_->set_frame(atmo::render::frame_state_of(s));
    if (s.fog) context_->set_fog(atmo::render::fog_state_of(s));
    terrain_ = std::make_unique<hs::Terrain>(atmo::render::terrain_of(s));
    if (!terrain_->gl_init(&error)) throw std::runtime_error("terrain: " + error);
    view_.emplace(*context_, static_cast<uint32_t>(ci));
    setup_ = atmo::render::view_setup_of(s, ci, depth_);
    setup_.depth_texture = target_->depth_texture();
    view_->set(hs::make_view_state(setup_));
    lighting_ = view_->lighting();
    // atmo render's glow threshold, from the camera's exposure (no glows drawn here; set_lights takes it).
    const double ev100 = atmo::render::set_exposure_ev100_of(s, ci).value_or(
        scenario::auto_exposure_ev100(glm::degrees(lighting_.sun_elevation_rad)));
    glow_threshold_ = atmo::render::glow_threshold_cd_m2_of(hs::exposure_scale_from_ev100(ev100));
  }
  ~LightPointsOnly() {
    gl_->make_current();
    terrain_->gl_shutdown();
    view_.reset();
    context_->gl_shutdown();
  }
  LightPointsOnly(const LightPointsOnly&) = delete;
  LightPointsOnly& operator=(const LightPointsOnly&) = delete;

  // The scenario's own lights (atmo::render::light_points_of, what atmo render passes to set_lights).
  std::vector<AtmoLightPoint> scenario_lights() const { return atmo::render::light_points_of(scenario_, *terrain_); }

  // Linear cd/m^2, row 0 the top, as the render's EXR; `result` (optional) gets the pass's result.
  support::Image render(const std::vector<AtmoLightPoint>& lights, AtmoResult* result = nullptr) {
    namespace hs = atmo::host_scene;
    gl_->make_current();  // several may live in one process
    context_->set_lights(hs::lights_state_enu(atmo::render::origin_of(scenario_), lights, glow_threshold_));
    target_->bind();
    glClearColor(0, 0, 0, 1);
    {
      // The host's terrain for its depth only; then the colour cleared.
      hs::DepthSetup depth_state(depth_);
      if (!depth_state.ok()) throw std::runtime_error("no glClipControl");
      glClearDepth(hs::clear_depth_value(depth_));
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      terrain_->draw(setup_, hs::lighting_from_atmo(lighting_), nullptr);
      glClear(GL_COLOR_BUFFER_BIT);
    }
    const AtmoResult r = view_->render(ATMO_PASS_LIGHT_POINTS);
    if (result) *result = r;
    glFinish();
    return target_->read_color();
  }

 private:
  scenario::Scenario scenario_;
  size_t ci_;
  host_scene::DepthConvention depth_;
  std::unique_ptr<support::HeadlessGl> gl_;
  std::unique_ptr<support::OffscreenTarget> target_;
  std::optional<atmo::Plugin> plugin_;
  std::optional<atmo::Context> context_;
  std::optional<atmo::View> view_;
  std::unique_ptr<host_scene::Terrain> terrain_;
  host_scene::ViewSetup setup_;
  AtmoLighting lighting_{};
  double glow_threshold_ = 0.0;
};

// The solid angle of pixel (x, y) of a camera (sr): the pinhole's (pixel pitch / focal length)^2 cos^3 of the
// angle off the axis, square pixels.
inline double pixel_solid_angle_sr(const scenario::Camera& cam, int x, int y) {
  const double f = 0.5 * cam.height / std::tan(0.5 * glm::radians(cam.vertical_fov_deg));  // px
  const double dx = x + 0.5 - 0.5 * cam.width, dy = y + 0.5 - 0.5 * cam.height;
  const double r2 = (dx * dx + dy * dy) / (f * f);
  return 1.0 / (f * f) / std::pow(1.0 + r2, 1.5);
}

}  // namespace atmo::test_render
