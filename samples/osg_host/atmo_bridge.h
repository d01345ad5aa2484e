// atmo_bridge.h — the plugin inside OpenSceneGraph's frame.
//
// Where the passes run: custom osg::Drawables placed in render bins of the scene camera, not camera draw
// callbacks. OSG 3.6 runs a camera's initial and pre-draw callbacks before its RenderStage binds the FBO
// and clears it, and its post-draw and final callbacks after the FBO is unbound, so none of them is
// "inside the camera after the opaque geometry": a callback would have to bind OSG's FBO itself and could
// not sit between the opaque and the transparent bins. A drawable is drawn by the RenderStage with the
// FBO bound and osg::State applied, in bin order: the sky's drawable in bin -10 (before the scene), the
// other passes' in bin 5 (after the opaque bin 0, before OSG's transparent bin 10). Display lists are off
// (a list would record the plugin's GL calls once and replay them without it) and culling is off (the
// drawables have no bound).
//
// The depth texture is attached to the scene camera's FBO; reading it while attached is a feedback loop
// by the GL specification, so for its passes the drawable binds as the draw framebuffer a second FBO
// that holds the same colour texture alone (docs/ABI.md, "The host's depth texture"), and binds OSG's
// back afterwards.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <osg/Drawable>
#include <osg/Texture2D>

#include "atmo/atmo.hpp"
#include "atmo_host_scene/camera.h"
#include "gl_state_check.h"

namespace atmo::osg_host {

constexpr AtmoResult kNotRun = INT32_MIN;

struct FrameReport {
  std::array<AtmoResult, ATMO_PASS_COUNT> pass_results{};  // by AtmoPass; kNotRun: not called
  int plugin_calls = 0;                // [gl-current] plugin calls made in OSG's draw
  int gl_errors = 0;                   // glGetError after a plugin call (the plugin's)
  int host_errors_before = 0;          // errors OSG left pending before a plugin call (not the plugin's)
  std::vector<std::string> errors;     // plugin errors, its error-level log lines, GL errors
};

class AtmoBridge {
 public:
  struct Settings {
    std::string plugin_path;
    bool enabled = true;          // false: --no-atmo, the plugin is not even loaded
    host_scene::Geodetic origin;  // the ENU world's origin (the airfield datum)
    double utc_posix_s = 0.0;
    double visibility_m = 0.0;    // 0: the plugin's default
    double exposure_scale = 1.0;
    double fog_visibility_m = 0.0;  // ground fog's MOR; 0: none
    double fog_top_m = 80.0;        // above the datum
    std::vector<AtmoLightPoint> lights;  // ENU at the origin (the terrain's runway lights)
    int cumulus_oktas = 0;          // a cumulus layer 1200-2500 m over 6 km; 0: no clouds
    bool inject_leak = false;     // test of the checks: change GL state behind OSG's back after a pass
  };

  // Loads the plugin and creates its context (no GL). Throws atmo::Error or std::runtime_error.
  explicit AtmoBridge(const Settings& settings);
  ~AtmoBridge();

  bool enabled() const { return settings_.enabled; }
  const AtmoPluginApi* api() const { return plugin_ ? &plugin_->api() : nullptr; }
  void set_targets(osg::Texture2D* color, osg::Texture2D* depth) {
    color_ = color;
    depth_ = depth;
  }

  // Main thread, before OSG's rendering traversals: set_frame, and set_view from OSG's camera for the
  // lighting of the host's own shading (no GL). Returns false (the reason in the report) on a plugin error.
  bool begin_frame(uint64_t frame_number, const osg::Matrixd& view, const osg::Matrixd& projection,
                   const std::array<int, 4>& viewport, AtmoLighting* lighting);

  // OSG's draw thread, from the drawables: set_view with OSG's draw-time matrices and the depth texture
  // (first = the sky's drawable), then the passes, each followed by the GL error and state checks.
  void draw(osg::RenderInfo& render_info, const std::vector<AtmoPass>& passes, bool first) const;

  // [gl-current] At the end, with OSG's context current.
  void gl_shutdown();

  FrameReport take_report();
  const StateCheckTally& tally() const { return tally_; }

 private:
  static void log_callback(void* user, int32_t severity, const char* message);
  AtmoViewState view_state(const osg::Matrixd& view, const osg::Matrixd& projection, const std::array<int, 4>& viewport,
                           uint32_t depth_texture) const;

  Settings settings_;
  std::unique_ptr<atmo::Plugin> plugin_;
  std::unique_ptr<atmo::Context> context_;
  std::unique_ptr<atmo::View> view_;
  osg::ref_ptr<osg::Texture2D> color_, depth_;
  double last_visibility_m_ = -1.0;
  // Draw-time state (drawImplementation is const in OSG).
  mutable bool gl_ready_ = false;
  mutable GLuint pass_fbo_ = 0;       // the colour texture alone, for the passes
  mutable unsigned gl_context_ = ~0u;
  mutable std::recursive_mutex mutex_;         // the log callback may come from the plugin's calls on any thread
  mutable FrameReport report_;
  mutable StateCheckTally tally_;
};

// A drawable that runs some of the plugin's passes where OSG draws it.
class AtmoPassDrawable : public osg::Drawable {
 public:
  AtmoPassDrawable() = default;
  AtmoPassDrawable(const AtmoBridge* bridge, std::vector<AtmoPass> passes, bool first);
  AtmoPassDrawable(const AtmoPassDrawable& other, const osg::CopyOp& copy = osg::CopyOp::SHALLOW_COPY);
  META_Object(atmo_osg_host, AtmoPassDrawable)

  void drawImplementation(osg::RenderInfo& render_info) const override;

 private:
  const AtmoBridge* bridge_ = nullptr;
  std::vector<AtmoPass> passes_;
  bool first_ = false;
};

const char* pass_name(int pass);

}  // namespace atmo::osg_host
