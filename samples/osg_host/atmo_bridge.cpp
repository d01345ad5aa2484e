#include "atmo_bridge.h"

#include <cstdio>
#include <cstring>
#include <stdexcept>

#include <osg/FrameBufferObject>
#include <osg/GLExtensions>
#include <osg/State>
#include <osgUtil/RenderBin>
#include <osgUtil/RenderStage>

namespace atmo::osg_host {

namespace hs = atmo::host_scene;

const char* pass_name(int pass) {
  switch (pass) {
    case ATMO_PASS_SKY: return "sky";
    case ATMO_PASS_AERIAL_PERSPECTIVE: return "aerial perspective";
    case ATMO_PASS_CLOUDS: return "clouds";
    case ATMO_PASS_NIGHT_SKY: return "night sky";
    case ATMO_PASS_LIGHT_GLOWS: return "light glows";
    case ATMO_PASS_LIGHT_POINTS: return "light points";
    case ATMO_PASS_SKY_OCCLUSION: return "sky occlusion";
  }
  return "?";
}

namespace {

// The plugin loads GL through OSG's own lookup (glXGetProcAddressARB here).
void* get_proc_address(void*, const char* name) { return osg::getGLExtensionFuncPtr(name); }

std::string gl_error_text(GLenum e) {
  char text[32];
  std::snprintf(text, sizeof text, "0x%04x", e);
  return text;
}

// The FBO OSG's RenderStage bound for the stage being drawn (osg::State does not track framebuffers).
GLuint stage_fbo(osg::RenderInfo& render_info) {
  osg::RenderInfo::RenderBinStack& bins = render_info.getRenderBinStack();
  if (bins.empty() || !bins.back()->getStage()) return 0;
  const osg::FrameBufferObject* fbo = bins.back()->getStage()->getFrameBufferObject();
  return fbo ? fbo->getHandle(render_info.getState()->getContextID()) : 0;
}

}  // namespace

AtmoBridge::AtmoBridge(const Settings& settings) : settings_(settings) {
  report_.pass_results.fill(kNotRun);
  if (!settings_.enabled) return;
  plugin_ = std::make_unique<atmo::Plugin>(settings_.plugin_path, "atmo-osg-host");
  auto services = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  services.user = this;
  services.log = &AtmoBridge::log_callback;
  services.gl_get_proc_address = &get_proc_address;
  context_ = std::make_unique<atmo::Context>(*plugin_, &services);
  view_ = std::make_unique<atmo::View>(*context_, 0);
  // The weather, once (no GL): fog and the runway's lights glowing in it, a cumulus layer.
  const hs::Geodetic& o = settings_.origin;
  if (settings_.fog_visibility_m > 0.0) {
    auto fog = atmo::make<AtmoFogState>(ATMO_TYPE_FOG_STATE);
    fog.visibility_m = settings_.fog_visibility_m;
    fog.top_height_m = o.height_m + settings_.fog_top_m;
    context_->set_fog(fog);
  }
  if (!settings_.lights.empty())
    context_->set_lights(atmo::lights_state(0, settings_.lights, o.latitude_deg, o.longitude_deg, o.height_m));
  if (settings_.cumulus_oktas > 0) {
    auto layer = atmo::make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
    layer.type = ATMO_CLOUD_CUMULUS;
    layer.coverage_oktas = settings_.cumulus_oktas;
    layer.base_m = 1200.0;
    layer.top_m = 2500.0;
    layer.area_size_m = 6000.0;  // over the airfield: cheap to generate
    layer.seed = 1;
    auto clouds = atmo::clouds_state(o.latitude_deg, o.longitude_deg, o.height_m, &layer, 1);
    clouds.setup = ATMO_CLOUD_SETUP_WAIT;  // each frame a function of the inputs (tests, pictures)
    if (context_->set_clouds(clouds) < 0) throw atmo::Error(ATMO_ERROR_IO, "set_clouds: " + context_->last_error());
  }
}

AtmoBridge::~AtmoBridge() {
  view_.reset();
  context_.reset();  // gl_shutdown() first, with the context current
  plugin_.reset();
}

void AtmoBridge::log_callback(void* user, int32_t severity, const char* message) {
  auto* self = static_cast<AtmoBridge*>(user);
  if (severity < ATMO_LOG_WARNING) return;
  std::fprintf(stderr, "[atmo %s] %s\n", atmo::log_severity_name(severity), message ? message : "");
  if (severity >= ATMO_LOG_ERROR) {
    const std::lock_guard<std::recursive_mutex> lock(self->mutex_);
    self->report_.errors.push_back(std::string("plugin log (") + atmo::log_severity_name(severity) + "): " + (message ? message : ""));
  }
}

AtmoViewState AtmoBridge::view_state(const osg::Matrixd& view, const osg::Matrixd& projection,
                                     const std::array<int, 4>& viewport, uint32_t depth_texture) const {
  auto s = atmo::make<AtmoViewState>(ATMO_TYPE_VIEW_STATE);
  // OSG's world is the ENU frame of the airfield datum (z up, OSG's own up axis).
  s.world_frame = ATMO_WORLD_ENU;
  s.world_origin_geodetic[0] = settings_.origin.latitude_deg;
  s.world_origin_geodetic[1] = settings_.origin.longitude_deg;
  s.world_origin_geodetic[2] = settings_.origin.height_m;
  const osg::Vec3d eye = osg::Matrixd::inverse(view).getTrans();
  const hs::Geodetic g = hs::geodetic_from_enu(settings_.origin, glm::dvec3(eye.x(), eye.y(), eye.z()));
  s.eye_kind = ATMO_POSITION_GEODETIC;
  s.eye_geodetic[0] = g.latitude_deg;
  s.eye_geodetic[1] = g.longitude_deg;
  s.eye_geodetic[2] = g.height_m;
  // osg::Matrixd is row-major for row vectors (v' = v M): its 16 values in memory are the column-major
  // matrix of the same map for column vectors, the plugin's (and glLoadMatrixd's) layout: copied as they lie.
  for (int i = 0; i < 16; ++i) {
    s.view_from_world[i] = view.ptr()[i];
    s.clip_from_view[i] = projection.ptr()[i];
  }
  for (int i = 0; i < 4; ++i) s.viewport[i] = viewport[static_cast<size_t>(i)];
  s.depth_texture = depth_texture;
  s.depth_convention = ATMO_DEPTH_STANDARD;  // OSG's default: glDepthRange(0, 1), GL_LESS, cleared to 1
  s.output_encoding = ATMO_OUTPUT_LINEAR_HDR;  // into the RGBA16F colour texture; the tone map follows
  s.exposure_scale = settings_.exposure_scale;
  return s;
}

bool AtmoBridge::begin_frame(uint64_t frame_number, const osg::Matrixd& view, const osg::Matrixd& projection,
                             const std::array<int, 4>& viewport, AtmoLighting* lighting) {
  if (!enabled()) return true;
  try {
    if (settings_.visibility_m != last_visibility_m_) {
      auto air = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
      air.visibility_m = settings_.visibility_m;
      context_->set_atmosphere(air);
      last_visibility_m_ = settings_.visibility_m;
    }
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.host_frame_number = frame_number;
    frame.utc_posix_s = settings_.utc_posix_s;
    context_->set_frame(frame);
    view_->set(view_state(view, projection, viewport, 0));
    *lighting = view_->lighting();
  } catch (const atmo::Error& e) {
    const std::lock_guard<std::recursive_mutex> lock(mutex_);
    report_.errors.push_back(e.what());
    return false;
  }
  return true;
}

void AtmoBridge::draw(osg::RenderInfo& render_info, const std::vector<AtmoPass>& passes, bool first) const {
  osg::State& state = *render_info.getState();
  const GLuint osg_fbo = stage_fbo(render_info);
  const std::string phase = first ? "sky drawable" : "after-opaque drawable";
  if (!enabled()) {
    // The control: the same check where the plugin would have been called (a snapshot against itself:
    // OSG's own differences only).
    const StateSnapshot s = snapshot_gl_state(render_info, osg_fbo, osg_fbo);
    tally_call(s, s, phase + " (no plugin)", &tally_);
    return;
  }
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  osg::GLExtensions* ext = state.get<osg::GLExtensions>();
  // Errors OSG left pending are not the plugin's (it keeps them pending anyway): read them first.
  const auto drain_host_errors = [&] {
    while (glGetError() != GL_NO_ERROR) ++report_.host_errors_before;
  };
  drain_host_errors();
  const StateSnapshot at_start = snapshot_gl_state(render_info, osg_fbo, osg_fbo);
  // After each [gl-current] call: its GL errors, and GL against osg::State. A difference there when OSG
  // called the drawable, before any plugin call (at_start), is OSG's own; any other is a mismatch.
  const auto after_call = [&](const std::string& what, GLuint draw_fbo) {
    ++report_.plugin_calls;
    for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
      ++report_.gl_errors;
      report_.errors.push_back("GL error " + gl_error_text(e) + " after " + what);
    }
    tally_call(at_start, snapshot_gl_state(render_info, draw_fbo, osg_fbo), "after " + what, &tally_);
  };
  try {
    if (!gl_ready_) {
      gl_context_ = state.getContextID();
      drain_host_errors();
      context_->gl_init();
      gl_ready_ = true;
      after_call("gl_init", osg_fbo);
    }
    const GLuint color = color_->getTextureObject(gl_context_) ? color_->getTextureObject(gl_context_)->id() : 0;
    const GLuint depth = depth_->getTextureObject(gl_context_) ? depth_->getTextureObject(gl_context_)->id() : 0;
    if (!color || !depth) throw std::runtime_error("the scene camera's colour or depth texture has no GL object yet");
    if (first) {
      // OSG's matrices as it draws this frame: the drawable hangs under the camera with no transform, so
      // the model-view matrix is the view matrix.
      const osg::Viewport* vp = state.getCurrentViewport();
      const std::array<int, 4> viewport{int(vp->x()), int(vp->y()), int(vp->width()), int(vp->height())};
      view_->set(view_state(state.getModelViewMatrix(), state.getProjectionMatrix(), viewport, depth));
    }
    if (!pass_fbo_) {
      ext->glGenFramebuffers(1, &pass_fbo_);
      ext->glBindFramebuffer(GL_DRAW_FRAMEBUFFER, pass_fbo_);
      ext->glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color, 0);
      const GLenum status = ext->glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER);
      if (status != GL_FRAMEBUFFER_COMPLETE)
        report_.errors.push_back("the passes' colour-only framebuffer is incomplete: " + gl_error_text(status));
    } else {
      ext->glBindFramebuffer(GL_DRAW_FRAMEBUFFER, pass_fbo_);
    }
    for (AtmoPass pass : passes) {
      AtmoResult r = kNotRun;
      drain_host_errors();
      try {
        r = view_->render(pass);
      } catch (const atmo::Error& e) {
        r = e.code();
        report_.errors.push_back(e.what());
      }
      report_.pass_results[static_cast<size_t>(pass)] = r;
      if (settings_.inject_leak && pass == ATMO_PASS_AERIAL_PERSPECTIVE) {
        // A leak, on purpose: front-face culling left on behind osg::State's back (it believes culling off,
        // so it never turns it off: OSG's later quads, the tone map's and the HUD's, vanish).
        glEnable(GL_CULL_FACE);
        glCullFace(GL_FRONT);
      }
      after_call(std::string("pass ") + pass_name(pass), pass_fbo_);
    }
  } catch (const std::exception& e) {
    report_.errors.push_back(e.what());
  }
  ext->glBindFramebuffer(GL_DRAW_FRAMEBUFFER, osg_fbo);
  // The drawable as a whole (the host's framebuffer switch included) against its start.
  tally_call(at_start, snapshot_gl_state(render_info, osg_fbo, osg_fbo), "the " + phase + "'s end", &tally_);
}

void AtmoBridge::gl_shutdown() {
  if (!gl_ready_) return;
  const osg::GLExtensions* ext = osg::GLExtensions::Get(gl_context_, false);
  if (ext && pass_fbo_) ext->glDeleteFramebuffers(1, &pass_fbo_);
  pass_fbo_ = 0;
  view_.reset();
  try {
    context_->gl_shutdown();
  } catch (const atmo::Error& e) {
    std::fprintf(stderr, "atmo-osg-host: %s\n", e.what());
  }
  gl_ready_ = false;
}

FrameReport AtmoBridge::take_report() {
  const std::lock_guard<std::recursive_mutex> lock(mutex_);
  FrameReport out = report_;
  report_ = FrameReport();
  report_.pass_results.fill(kNotRun);
  return out;
}

AtmoPassDrawable::AtmoPassDrawable(const AtmoBridge* bridge, std::vector<AtmoPass> passes, bool first)
    : bridge_(bridge), passes_(std::move(passes)), first_(first) {
  setUseDisplayList(false);
  setUseVertexBufferObjects(false);
  setCullingActive(false);
  setDataVariance(osg::Object::DYNAMIC);
}

AtmoPassDrawable::AtmoPassDrawable(const AtmoPassDrawable& other, const osg::CopyOp& copy)
    : osg::Drawable(other, copy), bridge_(other.bridge_), passes_(other.passes_), first_(other.first_) {}

void AtmoPassDrawable::drawImplementation(osg::RenderInfo& render_info) const {
  if (bridge_) bridge_->draw(render_info, passes_, first_);
}

}  // namespace atmo::osg_host
