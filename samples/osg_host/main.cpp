// atmo-osg-host: the plugin in an OpenSceneGraph viewer. OSG draws its own scene (a terrain heightfield, a
// hangar, a tower and tanks as osg::ShapeDrawables) into an FBO with colour and depth textures; the
// plugin's sky pass runs before it and aerial perspective, night sky, clouds and glows after its opaque
// geometry, inside OSG's frame (atmo_bridge.h says where and why); OSG then tone-maps to the window and
// draws a HUD. After every plugin call the live GL state is compared with what osg::State believes
// (gl_state_check.h); a difference, a GL error or a plugin error exits 1.
//
//   atmo-osg-host --frames 3 --out DIR           headless (a GLX pbuffer: run under xvfb-run -a)
//   atmo-osg-host --window                       interactive (first-person manipulator)
//   atmo-osg-host --no-atmo ...                  the same frames without the plugin
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <osg/GLExtensions>
#include <osg/Texture2D>
#include <osgDB/WriteFile>
#include <osgGA/FirstPersonManipulator>
#include <osgViewer/Viewer>

#include "atmo_bridge.h"
#include "atmo_support/headless_gl.h"
#include "core/astro/iso8601.h"
#include "scene.h"

#ifndef ATMO_OSG_DEFAULT_PLUGIN
#define ATMO_OSG_DEFAULT_PLUGIN "libatmo.so"
#endif

namespace {

namespace oh = atmo::osg_host;
namespace hs = atmo::host_scene;

constexpr double kNearM = 1.0, kFarM = 200000.0, kVerticalFovDeg = 50.0;

// The headless camera: on the approach to the runway (heading east), 250 m over the airfield datum, 150 m
// further each frame, looking 5 degrees down: the airfield ahead, the hills up to the terrain's edge 20 km
// away, the sky above.
// --eye and --look instead: a fixed camera.
osg::Matrixd headless_view(int frame, const std::vector<double>& eye_enu, const std::vector<double>& look_deg) {
  const osg::Vec3d eye = eye_enu.size() == 3 ? osg::Vec3d(eye_enu[0], eye_enu[1], eye_enu[2])
                                             : osg::Vec3d(-3600.0 + 150.0 * frame, -40.0, 250.0);
  const double heading = osg::DegreesToRadians(look_deg.size() == 2 ? look_deg[0] : 90.0);
  const double pitch = osg::DegreesToRadians(look_deg.size() == 2 ? look_deg[1] : -5.0);
  const osg::Vec3d forward(std::sin(heading) * std::cos(pitch), std::cos(heading) * std::cos(pitch), std::sin(pitch));
  return osg::Matrixd::lookAt(eye, eye + forward, osg::Vec3d(0, 0, 1));
}

// The frame as the window shows it, and the scene's distance per pixel, read back after OSG's last
// camera (the HUD): a final-draw callback of the master camera runs after its post-render stages.
struct Readback : osg::Camera::DrawCallback {
  osg::ref_ptr<osg::Texture2D> depth;
  mutable osg::ref_ptr<osg::Image> color;
  mutable std::vector<float> depth_values;
  int width = 0, height = 0;
  bool enabled = false;

  void operator()(osg::RenderInfo& render_info) const override {
    if (!enabled) return;
    color = new osg::Image;
    color->readPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE);
    // Direct state access: no texture binding changes behind osg::State.
    using GetTextureImage = void (*)(GLuint, GLint, GLenum, GLenum, GLsizei, void*);
    static const auto get_texture_image = reinterpret_cast<GetTextureImage>(osg::getGLExtensionFuncPtr("glGetTextureImage"));
    const osg::Texture::TextureObject* object = depth->getTextureObject(render_info.getState()->getContextID());
    depth_values.assign(static_cast<size_t>(width) * height, 1.0f);
    if (get_texture_image && object)
      get_texture_image(object->id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(depth_values.size() * sizeof(float)),
                        depth_values.data());
  }
};

// Binary Netpbm (top row first), for the tests to read without a PNG decoder: the frame as P6 (8-bit
// RGB) and the scene's distance from the eye per pixel as P5 (16-bit metres; 65535: no geometry, the sky).
bool write_ppm(const std::string& path, const osg::Image& rgba) {
  std::ofstream out(path, std::ios::binary);
  out << "P6\n" << rgba.s() << " " << rgba.t() << "\n255\n";
  for (int row = 0; row < rgba.t(); ++row)
    for (int x = 0; x < rgba.s(); ++x) out.write(reinterpret_cast<const char*>(rgba.data(x, rgba.t() - 1 - row)), 3);
  return static_cast<bool>(out);
}

bool write_distances(const std::string& path, const std::vector<float>& depth, int width, int height,
                     const osg::Matrixd& projection) {
  const osg::Matrixd view_from_clip = osg::Matrixd::inverse(projection);
  std::ofstream out(path, std::ios::binary);
  out << "P5\n" << width << " " << height << "\n65535\n";
  for (int row = 0; row < height; ++row) {
    const int y = height - 1 - row;
    for (int x = 0; x < width; ++x) {
      const float d = depth[static_cast<size_t>(y) * width + x];
      unsigned v = 65535;
      if (d < 1.0f) {
        const osg::Vec4d clip(2.0 * (x + 0.5) / width - 1.0, 2.0 * (y + 0.5) / height - 1.0, 2.0 * d - 1.0, 1.0);
        const osg::Vec4d p = clip * view_from_clip;
        const double metres = osg::Vec3d(p.x(), p.y(), p.z()).length() / p.w();
        v = static_cast<unsigned>(std::min(65534.0, std::max(0.0, std::round(metres))));
      }
      const char bytes[2] = {static_cast<char>(v >> 8), static_cast<char>(v & 255)};
      out.write(bytes, 2);
    }
  }
  return static_cast<bool>(out);
}

osg::ref_ptr<osg::Texture2D> target_texture(int width, int height, GLint internal, GLenum format) {
  osg::ref_ptr<osg::Texture2D> t = new osg::Texture2D;
  t->setTextureSize(width, height);
  t->setInternalFormat(internal);
  t->setSourceFormat(format);
  t->setSourceType(GL_FLOAT);
  t->setFilter(osg::Texture::MIN_FILTER, osg::Texture::NEAREST);
  t->setFilter(osg::Texture::MAG_FILTER, osg::Texture::NEAREST);
  t->setWrap(osg::Texture::WRAP_S, osg::Texture::CLAMP_TO_EDGE);
  t->setWrap(osg::Texture::WRAP_T, osg::Texture::CLAMP_TO_EDGE);
  return t;
}

std::string result_text(const AtmoPluginApi* api, AtmoResult r) {
  if (r == oh::kNotRun) return "not run";
  if (r == ATMO_SUCCESS) return "drawn";
  return api ? api->result_string(r) : std::to_string(r);
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // the report's lines in order with the errors on stderr
  oh::AtmoBridge::Settings settings;
  settings.plugin_path = ATMO_OSG_DEFAULT_PLUGIN;
  settings.origin = {47.4647, 8.5492, 432.0};
  std::string utc = "2024-06-21T11:00:00Z";
  int frames = 0, width = 640, height = 360;
  double ev100 = 15.0;
  std::string out_dir;
  bool no_atmo = false, window = false;

  CLI::App app{"Atmo in an OpenSceneGraph viewer: OSG's scene with the plugin's passes inside its frame, and a "
               "check of OSG's GL state cache after every plugin call."};
  app.add_option("--plugin", settings.plugin_path, "Path of libatmo.so")->capture_default_str();
  app.add_option("--frames", frames, "Frames to draw (headless: default 3; window: until closed)")
      ->check(CLI::PositiveNumber);
  app.add_option("--width", width, "Width in pixels")->check(CLI::Range(64, 8192))->capture_default_str();
  app.add_option("--height", height, "Height in pixels")->check(CLI::Range(64, 8192))->capture_default_str();
  app.add_option("--out", out_dir, "Folder for frame_NNN.png, the same as frame_NNN.ppm, and frame_NNN_distance.pgm (metres, 65535: sky)");
  app.add_option("--utc", utc, "UTC time, ISO 8601")->capture_default_str();
  app.add_option("--lat", settings.origin.latitude_deg, "Latitude of the airfield, degrees")
      ->check(CLI::Range(-90.0, 90.0))->capture_default_str();
  app.add_option("--lon", settings.origin.longitude_deg, "Longitude of the airfield, degrees")
      ->check(CLI::Range(-180.0, 360.0))->capture_default_str();
  app.add_option("--elevation", settings.origin.height_m, "Airfield height above the WGS84 ellipsoid, m")
      ->capture_default_str();
  app.add_option("--visibility", settings.visibility_m, "Meteorological visibility, m (0: the plugin's default)")
      ->check(CLI::Range(0.0, 500000.0))->capture_default_str();
  app.add_option("--ev", ev100, "Exposure, EV100")->capture_default_str();
  std::vector<double> eye_enu, look_deg;
  app.add_option("--eye", eye_enu, "Fixed camera at EAST,NORTH,UP metres from the airfield datum (default: the approach)")
      ->expected(3)->delimiter(',');
  app.add_option("--look", look_deg, "HEADING,PITCH of the camera, degrees (default 90,-5: east, 5 down)")
      ->expected(2)->delimiter(',');
  app.add_option("--fog", settings.fog_visibility_m, "Ground fog's visibility (RVR), m, with the runway's lights glowing in it")
      ->check(CLI::Range(50.0, 10000.0));
  app.add_option("--fog-top", settings.fog_top_m, "Fog top above the airfield, m")->check(CLI::Range(1.0, 3000.0))
      ->capture_default_str();
  app.add_option("--cumulus", settings.cumulus_oktas, "A cumulus layer (1200-2500 m over a 6 km square at the airfield) of N oktas")
      ->check(CLI::Range(1, 8));
  app.add_flag("--no-atmo", no_atmo, "Draw the same frames without the plugin (not loaded)");
  app.add_flag("--window", window, "Interactive window instead of the headless pbuffer");
  app.add_flag("--inject-leak", settings.inject_leak,
               "Test of the checks: leave front-face culling on behind OSG's back after the aerial perspective");
  CLI11_PARSE(app, argc, argv);

  std::string error;
  const auto t = atmo::core::astro::parse_iso8601_posix(utc, &error);
  if (!t) {
    std::fprintf(stderr, "atmo-osg-host: --utc: %s\n", error.c_str());
    return 2;
  }
  settings.utc_posix_s = *t;
  settings.enabled = !no_atmo;
  settings.exposure_scale = hs::exposure_scale_from_ev100(ev100);
  if (!window && frames == 0) frames = 3;
  if (!out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) {
      std::fprintf(stderr, "atmo-osg-host: --out: cannot create %s: %s\n", out_dir.c_str(), ec.message().c_str());
      return 2;
    }
  }

  hs::TerrainOptions terrain_options;
  const hs::Terrain terrain(terrain_options);
  if (settings.fog_visibility_m > 0.0) settings.lights = terrain.atmo_light_points();
  std::unique_ptr<oh::AtmoBridge> bridge;
  try {
    bridge = std::make_unique<oh::AtmoBridge>(settings);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "atmo-osg-host: %s\n", e.what());
    return 1;
  }
  if (const AtmoPluginApi* api = bridge->api())
    std::printf("plugin %s %u.%u.%u (interface %u) from %s\n", api->plugin_name, api->plugin_version >> 16,
                (api->plugin_version >> 8) & 0xff, api->plugin_version & 0xff, api->interface_version,
                settings.plugin_path.c_str());
  else
    std::printf("--no-atmo: no plugin\n");

  // The graphics context: a GLX pbuffer (headless, under Xvfb) or a window.
  osg::ref_ptr<osg::GraphicsContext::Traits> traits = new osg::GraphicsContext::Traits;
  traits->readDISPLAY();
  traits->setUndefinedScreenDetailsToDefaultScreen();
  traits->x = 40;
  traits->y = 40;
  traits->width = width;
  traits->height = height;
  traits->red = traits->green = traits->blue = traits->alpha = 8;
  traits->depth = 24;
  traits->pbuffer = !window;
  traits->doubleBuffer = true;  // a single-buffered pbuffer is presented (XShmPutImage) at each flush by Mesa's software GLX, and refused
  traits->windowDecoration = window;
  traits->supportsResize = false;
  traits->windowName = "atmo-osg-host";
  osg::ref_ptr<osg::GraphicsContext> gc = osg::GraphicsContext::createGraphicsContext(traits.get());
  if (!gc.valid()) {
    std::fprintf(stderr, "atmo-osg-host: no %s on display '%s' (headless: run under xvfb-run -a)\n",
                 window ? "window" : "GLX pbuffer", traits->displayName().c_str());
    return 2;
  }
  const GLenum buffer = GL_BACK;
  // Nothing to present headless: the frame is read back from the back buffer. Mesa's software GLX would
  // present a pbuffer's swap with XShmPutImage, which X refuses (BadMatch) for a pbuffer.
  struct NoSwap : osg::GraphicsContext::SwapCallback {
    void swapBuffersImplementation(osg::GraphicsContext*) override { glFlush(); }
  };
  if (!window) gc->setSwapCallback(new NoSwap);

  osgViewer::Viewer viewer;
  viewer.setThreadingModel(osgViewer::Viewer::SingleThreaded);  // the plugin's calls are [ctx-sync]
  viewer.setReleaseContextAtEndOfFrameHint(false);
  viewer.setLightingMode(osg::View::NO_LIGHT);
  osg::Camera* master = viewer.getCamera();
  master->setGraphicsContext(gc.get());
  master->setViewport(0, 0, width, height);
  master->setDrawBuffer(buffer);
  master->setReadBuffer(buffer);
  master->setClearColor(osg::Vec4(0, 0, 0, 1));
  master->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
  master->setProjectionMatrixAsPerspective(kVerticalFovDeg, double(width) / height, kNearM, kFarM);

  // The scene camera: OSG's scene into linear HDR colour and depth textures (the plugin reads the depth).
  osg::ref_ptr<osg::Texture2D> color = target_texture(width, height, GL_RGBA16F_ARB, GL_RGBA);
  osg::ref_ptr<osg::Texture2D> depth = target_texture(width, height, GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT);
  bridge->set_targets(color.get(), depth.get());
  osg::ref_ptr<osg::Camera> scene = new osg::Camera;
  scene->setName("scene");
  scene->setRenderOrder(osg::Camera::PRE_RENDER, 0);
  scene->setReferenceFrame(osg::Transform::RELATIVE_RF);  // the master's view and projection
  scene->setViewMatrix(osg::Matrixd::identity());
  scene->setProjectionMatrix(osg::Matrixd::identity());
  scene->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
  scene->setViewport(0, 0, width, height);
  scene->setRenderTargetImplementation(osg::Camera::FRAME_BUFFER_OBJECT);
  scene->setImplicitBufferAttachmentMask(0, 0);
  scene->attach(osg::Camera::COLOR_BUFFER, color.get());
  scene->attach(osg::Camera::DEPTH_BUFFER, depth.get());
  scene->setClearColor(osg::Vec4(0, 0, 0, 1));
  scene->setClearMask(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  scene->setAllowEventFocus(false);

  oh::SceneLighting lighting;
  lighting.attach(scene->getOrCreateStateSet());
  osg::ref_ptr<oh::AtmoPassDrawable> sky = new oh::AtmoPassDrawable(bridge.get(), {ATMO_PASS_SKY}, true);
  sky->getOrCreateStateSet()->setRenderBinDetails(-10, "RenderBin");
  osg::ref_ptr<oh::AtmoPassDrawable> after_opaque = new oh::AtmoPassDrawable(
      bridge.get(),
      {ATMO_PASS_AERIAL_PERSPECTIVE, ATMO_PASS_NIGHT_SKY, ATMO_PASS_CLOUDS, ATMO_PASS_LIGHT_GLOWS, ATMO_PASS_LIGHT_POINTS},
      false);
  after_opaque->getOrCreateStateSet()->setRenderBinDetails(5, "RenderBin");
  scene->addChild(sky.get());
  scene->addChild(oh::make_terrain(terrain).get());
  scene->addChild(oh::make_models(terrain).get());
  scene->addChild(after_opaque.get());

  std::array<int, 4> panel{};
  osg::ref_ptr<osg::Group> root = new osg::Group;
  root->addChild(scene.get());
  root->addChild(oh::make_tone_map_camera(color.get(), width, height, buffer).get());
  root->addChild(oh::make_hud_camera(width, height, buffer, &panel).get());
  viewer.setSceneData(root.get());

  osg::ref_ptr<Readback> readback = new Readback;
  readback->depth = depth;
  readback->width = width;
  readback->height = height;
  readback->enabled = !out_dir.empty();
  master->setFinalDrawCallback(readback.get());

  if (window) {
    osg::ref_ptr<osgGA::FirstPersonManipulator> manipulator = new osgGA::FirstPersonManipulator;
    osg::Vec3d eye, center, up;
    headless_view(0, eye_enu, look_deg).getLookAt(eye, center, up);
    manipulator->setHomePosition(eye, center, osg::Vec3d(0, 0, 1));
    manipulator->setVerticalAxisFixed(true);
    viewer.setCameraManipulator(manipulator.get());
  }
  viewer.realize();
  if (!viewer.isRealized()) {
    std::fprintf(stderr, "atmo-osg-host: the viewer could not be realised\n");
    return 2;
  }
  // Mesa would unload its driver when OSG closes the X display at exit, and LeakSanitizer could not name the
  // module of the driver's one-time allocations: keep it mapped (harmless without the sanitizers).
  atmo::support::pin_gl_drivers();
  std::printf("%dx%d, %s, %s; hud panel: %d %d %d %d (x y width height from the lower left)\n", width, height,
              window ? "window" : "GLX pbuffer", no_atmo ? "without the plugin" : "with the plugin", panel[0], panel[1],
              panel[2], panel[3]);

  int status = 0;
  for (int i = 0; !viewer.done() && (frames == 0 || i < frames); ++i) {
    viewer.advance();
    viewer.eventTraversal();
    viewer.updateTraversal();
    if (!window) master->setViewMatrix(headless_view(i, eye_enu, look_deg));
    const osg::Matrixd view = master->getViewMatrix(), projection = master->getProjectionMatrix();
    AtmoLighting light = atmo::make<AtmoLighting>(ATMO_TYPE_LIGHTING);
    const bool lit = bridge->begin_frame(static_cast<uint64_t>(i), view, projection, {0, 0, width, height}, &light);
    lighting.set(bridge->enabled() && lit ? &light : nullptr, view, settings.exposure_scale);
    viewer.renderingTraversals();

    const oh::FrameReport report = bridge->take_report();
    const oh::StateCheckTally& tally = bridge->tally();
    std::printf("frame %03d:", i);
    if (bridge->enabled()) {
      for (int p : {ATMO_PASS_SKY, ATMO_PASS_AERIAL_PERSPECTIVE, ATMO_PASS_NIGHT_SKY, ATMO_PASS_CLOUDS,
                    ATMO_PASS_LIGHT_GLOWS, ATMO_PASS_LIGHT_POINTS})
        std::printf(" %s %s;", oh::pass_name(p), result_text(bridge->api(), report.pass_results[size_t(p)]).c_str());
      std::printf(" sun elevation %.1f deg;", light.sun_elevation_rad * 180.0 / M_PI);
    }
    std::printf(" GL errors %d (OSG's own before the calls %d); state checks so far %d, mismatches %d\n",
                report.gl_errors, report.host_errors_before, tally.checks, tally.mismatches);
    for (const std::string& e : report.errors) std::fprintf(stderr, "atmo-osg-host: frame %d: %s\n", i, e.c_str());
    if (!report.errors.empty() || report.gl_errors > 0) status = 1;
    if (readback->enabled && readback->color.valid()) {
      char name[64];
      std::snprintf(name, sizeof name, "frame_%03d.png", i);
      const std::string png = (std::filesystem::path(out_dir) / name).string();
      std::snprintf(name, sizeof name, "frame_%03d.ppm", i);
      const std::string ppm = (std::filesystem::path(out_dir) / name).string();
      std::snprintf(name, sizeof name, "frame_%03d_distance.pgm", i);
      const std::string pgm = (std::filesystem::path(out_dir) / name).string();
      if (!osgDB::writeImageFile(*readback->color, png) || !write_ppm(ppm, *readback->color) ||
          !write_distances(pgm, readback->depth_values, width, height, projection)) {
        std::fprintf(stderr, "atmo-osg-host: cannot write %s, %s or %s\n", png.c_str(), ppm.c_str(), pgm.c_str());
        status = 2;
      }
    }
    if (bridge->tally().mismatches > 0) status = 1;
    if (status != 0) break;
  }

  const oh::StateCheckTally& tally = bridge->tally();
  for (const std::string& m : tally.osg_messages)
    std::printf("OSG's own cache difference, there when OSG called the drawable (before any plugin call) and left as it was: %s\n", m.c_str());
  for (const std::string& m : tally.messages) std::fprintf(stderr, "atmo-osg-host: state mismatch: %s\n", m.c_str());
  std::printf("GL state checks: %d after %s (%d GL values compared with osg::State), %d mismatches; %d of OSG's own\n",
              tally.checks, bridge->enabled() ? "plugin calls and drawables" : "the drawables (no plugin)",
              tally.values, tally.mismatches, tally.osg_own);
  if (tally.mismatches > 0) status = std::max(status, 1);
  if (!out_dir.empty() && status == 0) std::printf("wrote %d frames to %s\n", frames, out_dir.c_str());

  gc->makeCurrent();
  bridge->gl_shutdown();
  return status;
}
