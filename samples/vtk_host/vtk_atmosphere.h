// vtk_atmosphere.h — the plugin as the VTK host drives it: one context and one
// view, fed each frame from VTK's camera (ENU world: VTK's x east, y north,
// z up, metres, origin at a geodetic point), every [gl-current] call checked by
// GlStateProof.
#ifndef ATMO_VTK_HOST_VTK_ATMOSPHERE_H
#define ATMO_VTK_HOST_VTK_ATMOSPHERE_H

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "atmo/atmo.hpp"
#include "atmo_host_scene/camera.h"
#include "gl_state_proof.h"

class vtkOpenGLRenderWindow;
class vtkRenderer;

namespace atmo::vtk_host {

struct AtmosphereSettings {
  std::string plugin_path;
  host_scene::Geodetic origin;        // ENU origin of VTK's world
  double utc_posix_s = 0.0;
  double visibility_m = 0.0;          // 0: the plugin's default (40 km)
  AtmoOutputEncoding encoding = ATMO_OUTPUT_DISPLAY_SRGB;
  double exposure_scale = 0.0;        // 0: the plugin's default (EV100 15)
  bool verbose = false;
};

class VtkAtmosphere {
 public:
  // Loads the plugin, creates the context and sets the air (no GL). Throws atmo::Error.
  explicit VtkAtmosphere(const AtmosphereSettings& settings);
  ~VtkAtmosphere();

  // [gl-current] gl_init on the first call (VTK's context exists only once it renders); false with *error.
  bool ensure_gl(vtkOpenGLRenderWindow* window, std::string* error);
  // [gl-current] gl_shutdown, checked like a pass.
  void gl_shutdown(vtkOpenGLRenderWindow* window);

  // set_frame and set_view from the renderer's active camera, exactly as VTK
  // draws it this frame (standard depth, [-1, 1] NDC z), for a viewport of
  // width x height at (0, 0) whose depth is `depth_texture`; then get_lighting. No GL.
  bool begin_frame(vtkRenderer* renderer, int width, int height, unsigned depth_texture);
  // [gl-current] One pass into the bound framebuffer, between GlStateProof's checks.
  void draw(AtmoPassKind pass, vtkOpenGLRenderWindow* window);

  const AtmoLighting& lighting() const { return lighting_; }
  const AtmosphereSettings& settings() const { return settings_; }
  GlStateProof& proof() { return proof_; }
  // Plugin errors (refused calls, error-level log lines), in order.
  std::vector<std::string> errors() const;
  // How often each pass drew (ATMO_SUCCESS) and had nothing to draw, by AtmoPassKind.
  std::array<uint32_t, ATMO_PASS_COUNT> drawn{}, nothing_to_draw{};

 private:
  static void log_callback(void* user, int32_t severity, const char* message);
  void error(const std::string& text);

  AtmosphereSettings settings_;
  std::unique_ptr<atmo::Plugin> plugin_;
  std::unique_ptr<atmo::Context> context_;
  std::unique_ptr<atmo::View> view_;
  AtmoLighting lighting_{};
  uint64_t frame_number_ = 0;
  bool gl_ready_ = false;
  GlStateProof proof_;
  mutable std::mutex errors_mutex_;  // the plugin's workers log through log_callback
  std::vector<std::string> errors_;
};

}  // namespace atmo::vtk_host

#endif  // ATMO_VTK_HOST_VTK_ATMOSPHERE_H
