// atmo-vtk-host: the plugin inside VTK 9.1's render pipeline (AtmoVtkPass, a
// vtkRenderPass): a terrain, an isosurface and glyph masts under the plugin's
// sky and haze, a VTK overlay renderer on top, and a proof after every plugin
// call that the real GL state and VTK's state cache (vtkOpenGLState) agree.
//
//   atmo-vtk-host --frames 3 --out DIR          offscreen, DIR/vtk_host_NNNN.png (run under xvfb-run -a)
//   atmo-vtk-host --interactive                 a window (terrain interactor style)
//   atmo-vtk-host --no-atmo                     the same frame without the plugin's passes
//   atmo-vtk-host --tone-map [--linear]         vtkToneMappingPass over it (docs/VTK_HOST.md)
//
// Exit status: 0; 1 a plugin error, a GL error, a GL state change or VTK cache mismatch after a plugin
// call, or a VTK error; 2 bad arguments.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <CLI/CLI.hpp>

#include <vtkCamera.h>
#include <vtkCameraPass.h>
#include <vtkInteractorStyleTerrain.h>
#include <vtkLightsPass.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOpaquePass.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkOpenGLRenderer.h>
#include <vtkOutputWindow.h>
#include <vtkPNGWriter.h>
#include <vtkRenderPassCollection.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkSequencePass.h>
#include <vtkToneMappingPass.h>
#include <vtkWindowToImageFilter.h>

#include "atmo_support/headless_gl.h"
#include "atmo_vtk_pass.h"
#include "core/astro/iso8601.h"
#include "vtk_atmosphere.h"
#include "vtk_scene.h"

#ifndef ATMO_VTK_DEFAULT_PLUGIN
#define ATMO_VTK_DEFAULT_PLUGIN "libatmo.so"
#endif

namespace {

namespace vh = atmo::vtk_host;

// Counts VTK's errors (a failed shader, framebuffer or write) so they turn into exit status 1.
class CountingOutputWindow : public vtkOutputWindow {
 public:
  static CountingOutputWindow* New();
  vtkTypeMacro(CountingOutputWindow, vtkOutputWindow);
  void DisplayText(const char* text) override { std::fprintf(stderr, "atmo-vtk-host: VTK: %s", text); }
  void DisplayErrorText(const char* text) override {
    ++errors;
    std::fprintf(stderr, "atmo-vtk-host: VTK error: %s", text);
  }
  void DisplayWarningText(const char* text) override { std::fprintf(stderr, "atmo-vtk-host: VTK warning: %s", text); }
  void DisplayGenericWarningText(const char* text) override { DisplayWarningText(text); }
  void DisplayDebugText(const char*) override {}
  int errors = 0;
};
vtkStandardNewMacro(CountingOutputWindow);

// The overlay's box (x0, y0, x1, y1 of the window, VTK's lower-left origin).
constexpr std::array<double, 4> kOverlay = {0.02, 0.02, 0.32, 0.34};

bool write_png(vtkRenderWindow* window, const std::string& path) {
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();  // the frame just drawn, not one more
  vtkNew<vtkPNGWriter> png;
  png->SetFileName(path.c_str());
  png->SetInputConnection(grab->GetOutputPort());
  png->Write();
  return png->GetErrorCode() == 0;
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 3, width = 480, height = 270;
  std::string out_dir, utc = "2024-06-21T10:00:00Z", plugin_path = ATMO_VTK_DEFAULT_PLUGIN;
  double lat = 46.95, lon = 7.45, visibility_m = 30000.0, ev100 = 15.0;
  bool no_atmo = false, tone_map = false, linear = false, interactive = false, verbose = false;
  CLI::App app{"atmo-vtk-host: Atmo's sky and aerial perspective inside VTK's render passes."};
  app.add_option("--frames", frames, "Frames to render (offscreen)")->check(CLI::Range(1, 100000))->capture_default_str();
  app.add_option("--width", width, "Width in pixels")->check(CLI::Range(16, 8192))->capture_default_str();
  app.add_option("--height", height, "Height in pixels")->check(CLI::Range(16, 8192))->capture_default_str();
  app.add_option("--out", out_dir, "Write each frame as DIR/vtk_host_NNNN.png (and DIR/overlay.txt)");
  app.add_option("--utc", utc, "UTC time, ISO 8601")->capture_default_str();
  app.add_option("--lat", lat, "Latitude of the terrain's centre, degrees")->check(CLI::Range(-90.0, 90.0))
      ->capture_default_str();
  app.add_option("--lon", lon, "Longitude of the terrain's centre, degrees")->check(CLI::Range(-180.0, 360.0))
      ->capture_default_str();
  app.add_option("--visibility", visibility_m, "Meteorological optical range, metres")
      ->check(CLI::Range(50.0, 500000.0))->capture_default_str();
  app.add_option("--ev", ev100, "Exposure value EV100")->check(CLI::Range(-10.0, 25.0))->capture_default_str();
  app.add_flag("--no-atmo", no_atmo, "No plugin: VTK's scene and overlay alone");
  app.add_flag("--tone-map", tone_map, "Insert vtkToneMappingPass (generic filmic) over the scene");
  app.add_flag("--linear", linear, "The plugin writes ATMO_OUTPUT_LINEAR_HDR (default DISPLAY_SRGB)");
  app.add_option("--plugin", plugin_path, "Path to libatmo.so")->capture_default_str();
  app.add_flag("--interactive", interactive, "Open a window and fly with the mouse (needs a display)");
  app.add_flag("--verbose", verbose, "The plugin's info and debug lines");
  CLI11_PARSE(app, argc, argv);

  std::string utc_error;
  const auto utc_s = atmo::core::astro::parse_iso8601_posix(utc, &utc_error);
  if (!utc_s) {
    std::fprintf(stderr, "atmo-vtk-host: --utc: %s\n", utc_error.c_str());
    return 2;
  }
  if (!out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) {
      std::fprintf(stderr, "atmo-vtk-host: --out %s: %s\n", out_dir.c_str(), ec.message().c_str());
      return 2;
    }
  }

  vtkNew<CountingOutputWindow> messages;
  vtkOutputWindow::SetInstance(messages);

  const atmo::host_scene::Geodetic origin{lat, lon, 500.0};
  std::unique_ptr<vh::VtkAtmosphere> atmosphere;
  if (!no_atmo) {
    vh::AtmosphereSettings s;
    s.plugin_path = plugin_path;
    s.origin = origin;
    s.utc_posix_s = *utc_s;
    s.visibility_m = visibility_m;
    s.encoding = linear ? ATMO_OUTPUT_LINEAR_HDR : ATMO_OUTPUT_DISPLAY_SRGB;
    s.exposure_scale = atmo::host_scene::exposure_scale_from_ev100(ev100);
    s.verbose = verbose;
    try {
      atmosphere = std::make_unique<vh::VtkAtmosphere>(s);
    } catch (const atmo::Error& e) {
      std::fprintf(stderr, "atmo-vtk-host: %s\n", e.what());
      return 1;
    }
  }

  atmo::host_scene::TerrainOptions terrain_options;
  terrain_options.draw_light_points = false;
  const atmo::host_scene::Terrain terrain(terrain_options);
  vh::Scene scene = vh::build_scene(terrain);

  vtkNew<vtkOpenGLRenderer> renderer;
  for (auto& actor : scene.actors) renderer->AddActor(actor);
  renderer->AddLight(scene.sun);
  renderer->SetBackground(0.0, 0.0, 0.0);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetPosition(scene.camera_position.data());
  camera->SetFocalPoint(scene.camera_focal_point.data());
  camera->SetViewUp(0.0, 0.0, 1.0);
  camera->SetViewAngle(45.0);
  camera->SetClippingRange(5.0, 60000.0);  // the terrain's far corner is ~45 km away

  // The opaque scene, as vtkRenderStepsPass's first steps; the plugin's passes around it.
  vtkNew<vtkLightsPass> lights;
  vtkNew<vtkOpaquePass> opaque;
  vtkNew<vtkRenderPassCollection> steps;
  steps->AddItem(lights);
  steps->AddItem(opaque);
  vtkNew<vtkSequencePass> sequence;
  sequence->SetPasses(steps);
  vtkNew<vtkCameraPass> camera_pass;
  camera_pass->SetDelegatePass(sequence);
  vtkNew<vh::AtmoVtkPass> atmo_pass;
  atmo_pass->SetDelegatePass(camera_pass);
  atmo_pass->SetAtmosphere(atmosphere.get());
  if (atmosphere) {
    atmo_pass->SetLightingCallback([&]() {
      vh::apply_lighting(scene, atmosphere->lighting(), linear, atmosphere->settings().exposure_scale);
    });
  }
  vtkNew<vtkToneMappingPass> tone;
  if (tone_map) {
    tone->SetToneMappingType(vtkToneMappingPass::GenericFilmic);
    tone->SetGenericFilmicDefaultPresets();
    tone->SetExposure(1.0);
    tone->SetDelegatePass(atmo_pass);
    renderer->SetPass(tone);
  } else {
    renderer->SetPass(atmo_pass);
  }

  vtkSmartPointer<vtkRenderer> overlay = vh::build_overlay(kOverlay);
  vtkNew<vtkRenderWindow> window;
  window->SetNumberOfLayers(2);
  window->AddRenderer(renderer);
  window->AddRenderer(overlay);
  window->SetSize(width, height);
  window->SetMultiSamples(0);
  window->SetWindowName("atmo-vtk-host");
  if (!interactive) window->SetOffScreenRendering(1);
  auto* gl_window = vtkOpenGLRenderWindow::SafeDownCast(window);
  if (!gl_window) {
    std::fprintf(stderr, "atmo-vtk-host: VTK's render window is not an OpenGL one\n");
    return 1;
  }

  int status = 0;
  if (interactive) {
    vtkNew<vtkRenderWindowInteractor> interactor;
    vtkNew<vtkInteractorStyleTerrain> style;
    interactor->SetInteractorStyle(style);
    interactor->SetRenderWindow(window);
    window->Render();
    atmo::support::pin_gl_drivers();
    interactor->Start();
  } else {
    for (int f = 0; f < frames; ++f) {
      window->Render();
      atmo::support::pin_gl_drivers();  // once the driver is loaded: LeakSanitizer then sees its allocations
      if (!out_dir.empty()) {
        char name[32];
        std::snprintf(name, sizeof name, "vtk_host_%04d.png", f);
        const std::string path = (std::filesystem::path(out_dir) / name).string();
        if (!write_png(window, path)) {
          std::fprintf(stderr, "atmo-vtk-host: could not write %s\n", path.c_str());
          status = 1;
        }
      }
    }
  }
  if (!out_dir.empty()) {
    // The overlay's pixels, top-left origin as PNG rows run: what tests/vtk_host compares.
    int* size = window->GetSize();
    const int x0 = int(std::lround(kOverlay[0] * size[0])), x1 = int(std::lround(kOverlay[2] * size[0]));
    const int y0 = size[1] - int(std::lround(kOverlay[3] * size[1]));
    const int y1 = size[1] - int(std::lround(kOverlay[1] * size[1]));
    if (FILE* f = std::fopen((std::filesystem::path(out_dir) / "overlay.txt").string().c_str(), "w")) {
      std::fprintf(f, "%d %d %d %d\n", x0, y0, x1, y1);
      std::fclose(f);
    }
  }

  if (!atmo_pass->error().empty()) {
    std::fprintf(stderr, "atmo-vtk-host: %s\n", atmo_pass->error().c_str());
    status = 1;
  }
  if (atmosphere) {
    window->MakeCurrent();
    atmosphere->gl_shutdown(gl_window);
    const vh::GlStateProof& p = atmosphere->proof();
    std::printf("atmo-vtk-host: %zu plugin GL calls checked: %zu VTK cache entries and %zu GL values each; "
                "%zu cache mismatches, %zu GL state changes, %zu GL errors (VTK's own cache drift before a call: %zu)\n",
                p.calls(), p.values_compared(), p.snapshot_values(), p.cache_mismatches(), p.state_changes(),
                p.gl_errors(), p.host_cache_drift());
    const char* names[] = {"sky", "aerial perspective", "clouds", "night sky"};
    for (int pass = 0; pass < 4; ++pass)
      std::printf("atmo-vtk-host: %s: drew %u, nothing to draw %u\n", names[pass], atmosphere->drawn[size_t(pass)],
                  atmosphere->nothing_to_draw[size_t(pass)]);
    if (p.cache_mismatches() || p.state_changes() || p.gl_errors()) status = 1;
    for (const std::string& e : atmosphere->errors()) {
      std::fprintf(stderr, "atmo-vtk-host: plugin: %s\n", e.c_str());
      status = 1;
    }
  }
  if (messages->errors > 0) {
    std::fprintf(stderr, "atmo-vtk-host: %d VTK error(s)\n", messages->errors);
    status = 1;
  }
  // VTK's passes free their GL objects only when asked, with the context alive.
  window->MakeCurrent();
  tone->ReleaseGraphicsResources(window);
  atmo_pass->ReleaseGraphicsResources(window);
  renderer->SetPass(nullptr);
  window->Finalize();
  vtkOutputWindow::SetInstance(nullptr);
  return status;
}
