#include "vtk_atmosphere.h"

#include <cstdio>
#include <cstring>

#include <vtkCamera.h>
#include <vtkMatrix4x4.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkRenderer.h>

namespace atmo::vtk_host {

namespace {

void column_major(vtkMatrix4x4* m, double out[16]) {
  // vtkMatrix4x4 is row-major storage of the same column-vector maths as GL.
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[c * 4 + r] = m->GetElement(r, c);
}

const char* pass_name(AtmoPassKind pass) {
  switch (pass) {
    case ATMO_PASS_SKY: return "ATMO_PASS_SKY";
    case ATMO_PASS_AERIAL_PERSPECTIVE: return "ATMO_PASS_AERIAL_PERSPECTIVE";
    case ATMO_PASS_CLOUDS: return "ATMO_PASS_CLOUDS";
    case ATMO_PASS_NIGHT_SKY: return "ATMO_PASS_NIGHT_SKY";
    case ATMO_PASS_LIGHT_GLOWS: return "ATMO_PASS_LIGHT_GLOWS";
    case ATMO_PASS_LIGHT_POINTS: return "ATMO_PASS_LIGHT_POINTS";
    default: return "ATMO_PASS_?";
  }
}

// The plugin loads GL through the same GLX entry point VTK's context came from.
void* glx_proc(void*, const char* name) { return glx_proc_address(name); }

}  // namespace

VtkAtmosphere::VtkAtmosphere(const AtmosphereSettings& settings) : settings_(settings) {
  plugin_ = std::make_unique<atmo::Plugin>(settings.plugin_path, "atmo-vtk-host");
  auto services = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  services.user = this;
  services.log = &VtkAtmosphere::log_callback;
  services.gl_get_proc_address = &glx_proc;
  context_ = std::make_unique<atmo::Context>(*plugin_, &services);
  // Before the first frame, so the tables are built once, for this air.
  auto air = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
  air.visibility_m = settings.visibility_m;
  context_->set_atmosphere(air);
  lighting_ = atmo::make<AtmoLighting>(ATMO_TYPE_LIGHTING);
}

VtkAtmosphere::~VtkAtmosphere() {
  view_.reset();
  context_.reset();  // gl_shutdown already ran (gl_shutdown()), or the context is gone: destroy only
  plugin_.reset();
}

void VtkAtmosphere::log_callback(void* user, int32_t severity, const char* message) {
  auto* self = static_cast<VtkAtmosphere*>(user);
  const char* text = message ? message : "";
  if (severity >= ATMO_LOG_WARNING || self->settings_.verbose) std::fprintf(stderr, "[atmo] %s\n", text);
  if (severity >= ATMO_LOG_ERROR) self->error(std::string("log: ") + text);
}

void VtkAtmosphere::error(const std::string& text) {
  const std::lock_guard<std::mutex> lock(errors_mutex_);
  errors_.push_back(text);
}

std::vector<std::string> VtkAtmosphere::errors() const {
  const std::lock_guard<std::mutex> lock(errors_mutex_);
  return errors_;
}

bool VtkAtmosphere::ensure_gl(vtkOpenGLRenderWindow* window, std::string* error) {
  if (gl_ready_) return true;
  if (!GlStateProof::load_gl(error)) return false;
  proof_.before(window, "gl_init");
  try {
    context_->gl_init();
    view_ = std::make_unique<atmo::View>(*context_, 0);
  } catch (const atmo::Error& e) {
    proof_.after(window);
    if (error) *error = e.what();
    return false;
  }
  proof_.after(window);
  gl_ready_ = true;
  return true;
}

void VtkAtmosphere::gl_shutdown(vtkOpenGLRenderWindow* window) {
  if (!gl_ready_) return;
  view_.reset();
  proof_.before(window, "gl_shutdown");
  try {
    context_->gl_shutdown();
  } catch (const atmo::Error& e) {
    error(e.what());
  }
  proof_.after(window);
  gl_ready_ = false;
}

bool VtkAtmosphere::begin_frame(vtkRenderer* renderer, int width, int height, unsigned depth_texture) {
  if (!gl_ready_) return false;
  vtkCamera* camera = renderer->GetActiveCamera();
  auto state = atmo::make<AtmoViewState>(ATMO_TYPE_VIEW_STATE);
  double eye[3];
  camera->GetPosition(eye);
  const host_scene::Geodetic g =
      host_scene::geodetic_from_enu(settings_.origin, glm::dvec3(eye[0], eye[1], eye[2]));
  state.eye_kind = ATMO_POSITION_GEODETIC;
  state.eye_geodetic[0] = g.latitude_deg;
  state.eye_geodetic[1] = g.longitude_deg;
  state.eye_geodetic[2] = g.height_m;
  state.world_frame = ATMO_WORLD_ENU;
  state.world_origin_geodetic[0] = settings_.origin.latitude_deg;
  state.world_origin_geodetic[1] = settings_.origin.longitude_deg;
  state.world_origin_geodetic[2] = settings_.origin.height_m;
  // The matrices vtkOpenGLCamera::GetKeyMatrices uses: model-view, and the
  // projection for the renderer's tiled aspect with NDC z in [-1, 1].
  column_major(camera->GetModelViewTransformMatrix(), state.view_from_world);
  column_major(camera->GetProjectionTransformMatrix(renderer->GetTiledAspectRatio(), -1.0, 1.0),
               state.clip_from_view);
  state.viewport[0] = 0;
  state.viewport[1] = 0;
  state.viewport[2] = width;
  state.viewport[3] = height;
  state.depth_texture = depth_texture;
  state.depth_convention = ATMO_DEPTH_STANDARD;  // VTK: glDepthRange(0, 1), GL_LEQUAL
  state.depth_origin = ATMO_DEPTH_ORIGIN_VIEWPORT;  // the texture is the renderer's, not the window's
  state.output_encoding = static_cast<uint32_t>(settings_.encoding);
  state.exposure_scale = settings_.exposure_scale;
  try {
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = settings_.utc_posix_s;
    frame.host_frame_number = ++frame_number_;
    context_->set_frame(frame);
    view_->set(state);
    lighting_ = view_->lighting();
  } catch (const atmo::Error& e) {
    error(e.what());
    return false;
  }
  return true;
}

void VtkAtmosphere::draw(AtmoPassKind pass, vtkOpenGLRenderWindow* window) {
  if (!gl_ready_) return;
  proof_.before(window, pass_name(pass));
  AtmoResult r = ATMO_SUCCESS;
  try {
    r = view_->render(pass);
  } catch (const atmo::Error& e) {
    error(e.what());
    r = e.code();
  }
  proof_.after(window);
  if (r == ATMO_SUCCESS) ++drawn[pass];
  if (r == ATMO_STATUS_NOTHING_TO_DRAW) ++nothing_to_draw[pass];
}

}  // namespace atmo::vtk_host
