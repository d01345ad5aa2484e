#include "render_command.h"

#include <glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <utility>

#include "atmo/atmo.hpp"
#include "atmo_host_scene/camera.h"
#include "atmo_host_scene/depth_setup.h"
#include "atmo_host_scene/objects.h"
#include "atmo_host_scene/terrain.h"
#include "atmo_scenario/scenario.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/image.h"
#include "atmo_support/image_metrics.h"
#include "atmo_support/offscreen_target.h"
#include "scenario_setup.h"

namespace atmo::render {

namespace {

namespace hs = atmo::host_scene;
namespace sc = atmo::scenario;

struct PassTiming {
  std::string name;
  std::vector<double> ms;  // one per repeat
  std::string status;      // plugin result of the last frame
  double query_ms = 0.0;   // GL timer query of the last frame
  double median() const {
    std::vector<double> s = ms;
    std::sort(s.begin(), s.end());
    return s.empty() ? 0.0 : s[s.size() / 2];
  }
};

hs::DepthConvention depth_of(const sc::Scenario& s, const std::string& override_text) {
  if (!override_text.empty()) {
    hs::DepthConvention c;
    if (!hs::parse_depth_convention(override_text.c_str(), &c))
      throw std::runtime_error("--depth: '" + override_text + "' is not standard, reversed or logarithmic");
    return c;
  }
  switch (s.render.depth_convention) {
    case sc::DepthConvention::Standard: return hs::DepthConvention::Standard;
    case sc::DepthConvention::Logarithmic: return hs::DepthConvention::Logarithmic;
    default: return hs::DepthConvention::Reversed;
  }
}

// Time of one step of the frame: wall time from a drained queue to glFinish
// (llvmpipe defers rasterisation, so a GL timer query alone can miss it), with
// the GL timer query kept for comparison on real GPUs.
class PassTimer {
 public:
  PassTimer() { glGenQueries(1, &query_); }
  ~PassTimer() { glDeleteQueries(1, &query_); }
  template <typename F>
  auto time(F&& f) {
    glFinish();
    auto start = std::chrono::steady_clock::now();
    glBeginQuery(GL_TIME_ELAPSED, query_);
    auto r = f();
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    last_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    GLuint64 ns = 0;
    glGetQueryObjectui64v(query_, GL_QUERY_RESULT, &ns);
    last_query_ms_ = ns * 1e-6;
    return r;
  }
  double last_ms() const { return last_ms_; }
  double last_query_ms() const { return last_query_ms_; }

 private:
  GLuint query_ = 0;
  double last_ms_ = 0.0, last_query_ms_ = 0.0;
};

struct Checks {
  int passed = 0, failed = 0;
  nlohmann::json list = nlohmann::json::array();
  void add(const std::string& name, bool ok, const std::string& detail) {
    (ok ? passed : failed)++;
    std::printf("  %s %s: %s\n", ok ? "PASS" : "FAIL", name.c_str(), detail.c_str());
    list.push_back({{"name", name}, {"passed", ok}, {"detail", detail}});
  }
};

std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), fmt, a, b, c);
  return buf;
}

}  // namespace

// The scenario's cloud layers through set_clouds (none: no call, no cost).
void set_clouds(const sc::Scenario& scenario, atmo::Context& context) {
  if (scenario.clouds.empty()) return;
  std::vector<std::string> paths;
  const std::vector<AtmoCloudLayer> layers = cloud_layers_of(scenario, scenario.clouds, &paths);
  AtmoCloudsState state = clouds_state_of(scenario, layers);
  state.setup = ATMO_CLOUD_SETUP_WAIT;  // a still: the full lighting, whatever the draw mode
  const AtmoResult r = context.set_clouds(state);
  if (r != ATMO_SUCCESS) std::printf("  clouds: %s\n", context.last_error().c_str());
}

// The scenario's fog through set_fog (none: no call, no cost).
void set_fog(const sc::Scenario& scenario, atmo::Context& context) {
  if (scenario.fog) context.set_fog(fog_state_of(scenario));
}

// The scenario's lights (the runway's approach, threshold and edge lights
// when asked for, beamed along the approach, and its own points) through
// set_lights, ENU at the scenario's origin; glows dimmer than 1/2000 of the
// camera's white are not drawn.
void set_lights(const sc::Scenario& scenario, const hs::Terrain& terrain, double exposure, atmo::Context& context) {
  if (!scenario.lights) return;
  const std::vector<AtmoLightPoint> points = light_points_of(scenario, terrain);
  context.set_lights(hs::lights_state_enu(origin_of(scenario), points, glow_threshold_cd_m2_of(exposure)));
}

// "WxH", each in [1, 8192], into the import's camera size.
bool parse_size(const std::string& text, sc::ImportOptions* import) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x') return false;
  if (w < 1 || w > 8192 || h < 1 || h > 8192) return false;
  import->width = w;
  import->height = h;
  return true;
}

int run_render(const Options& options) {
  sc::ImportOptions import = options.import;
  if (!options.size.empty() && !parse_size(options.size, &import)) {
    std::fprintf(stderr, "atmo render: --size: expected WIDTHxHEIGHT, each 1 to 8192, found '%s'\n",
                 options.size.c_str());
    return 2;
  }
  if (!import.empty() && !sc::is_openscenario_path(options.scenario_path)) {
    std::fprintf(stderr, "atmo render: %s: --lat, --lon and --size apply to OpenSCENARIO (.xosc) files only; a JSON "
                 "scenario states its place and cameras\n", options.scenario_path.c_str());
    return 2;
  }
  sc::LoadResult loaded = sc::load_scenario_file(options.scenario_path, import);
  if (!loaded.scenario) {
    std::fprintf(stderr, "atmo render: %s\n", loaded.error.c_str());
    return 2;
  }
  const sc::Scenario& scenario = *loaded.scenario;
  // Output files are named after the scenario file (noon_clear_main.png), which is safe in paths.
  const std::string file_stem = std::filesystem::path(options.scenario_path).stem().string();
  try {
    std::filesystem::create_directories(options.out_dir);
    std::printf("scenario %s: %s (%s UTC, %.4f°, %.4f°, %.0f m)\n", scenario.name.c_str(), scenario.description.c_str(),
                scenario.utc.c_str(), scenario.location.latitude_deg, scenario.location.longitude_deg,
                scenario.location.height_m);
    for (const sc::Notice& n : scenario.import_notes)
      std::printf("  imported: %s: %s\n", n.path.c_str(), n.message.c_str());
    for (const sc::Notice& n : scenario.not_yet_supported)
      std::printf("  not yet supported: %s: %s\n", n.path.c_str(), n.message.c_str());

    // The objects' files first: a file that cannot be read fails before any GL or plugin work.
    const ScenarioObjects objects = objects_of(scenario);

    std::string error;
    auto gl = support::HeadlessGl::create(support::HeadlessGl::Profile::Core, &error);
    if (!gl) throw std::runtime_error("no headless OpenGL context: " + error);
    std::printf("  GL: %s, %s (%s)\n", gl->version().c_str(), gl->renderer().c_str(), gl->platform().c_str());

    AtmoHostServices services = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
    services.gl_get_proc_address = &support::HeadlessGl::get_proc_address;
    atmo::Plugin plugin(options.plugin_path, "atmo render");
    atmo::Context context(plugin, &services);
    context.gl_init();

    context.set_atmosphere(atmo::render::atmosphere_state_of(scenario));
    context.set_frame(atmo::render::frame_state_of(scenario));

    set_clouds(scenario, context);
    set_fog(scenario, context);

    hs::Terrain terrain(terrain_of(scenario));
    if (!terrain.gl_init(&error)) throw std::runtime_error("terrain: " + error);

    // The scenario's objects (read above): drawn by the host after its terrain and the plugin's occluders (ENU at
    // the scenario's origin): their sky shadow, Sun shadow and bounce on the terrain and on themselves.
    hs::ObjectMeshes object_meshes;
    if (!objects.empty()) {
      if (!context.api().set_occluders)
        throw std::runtime_error("/objects: the plugin predates sky occlusion (no set_occluders in its table)");
      if (!object_meshes.gl_init(objects.mesh_pointers(), &error)) throw std::runtime_error("/objects: " + error);
      const std::vector<AtmoOccluderObject> occluders = objects.occluder_objects();
      const AtmoOccludersState state = occluders_state_enu(origin_of(scenario), occluders);
      context.check(context.api().set_occluders(context.handle(), &state), "set_occluders");
      size_t spheres = 0;
      for (const auto& list : objects.spheres) spheres += list.size();
      std::printf("  objects: %zu (%zu meshes, %zu spheres)%s\n", objects.instances.size(), objects.meshes.size(),
                  spheres, options.no_sky_occlusion ? ", sky occlusion pass left out (--no-sky-occlusion)" : "");
    }
    const hs::DepthConvention depth = depth_of(scenario, options.depth_override);

    Checks checks;
    nlohmann::json report = {{"scenario", scenario.name}, {"file", options.scenario_path},
                             {"depth_convention", hs::to_string(depth)}, {"gl_renderer", gl->renderer()},
                             {"cameras", nlohmann::json::array()}};
    for (size_t ci = 0; ci < scenario.cameras.size(); ++ci) {
      const sc::Camera& cam = scenario.cameras[ci];
      auto target = support::OffscreenTarget::create(cam.width, cam.height, &error);
      if (!target) throw std::runtime_error("offscreen target: " + error);
      atmo::View view(context, static_cast<uint32_t>(ci));

      hs::ViewSetup setup = view_setup_of(scenario, ci, depth);
      setup.depth_texture = target->depth_texture();
      view.set(hs::make_view_state(setup));

      const AtmoLighting lighting = view.lighting();
      const double sun_elevation_deg = glm::degrees(lighting.sun_elevation_rad);
      const double ev100 = set_exposure_ev100_of(scenario, ci).value_or(sc::auto_exposure_ev100(sun_elevation_deg));
      const double exposure = hs::exposure_scale_from_ev100(ev100);
      if (scenario.render.output == sc::OutputEncoding::DisplaySrgb) {
        setup.output_encoding = ATMO_OUTPUT_DISPLAY_SRGB;
        setup.exposure_scale = exposure;
        view.set(hs::make_view_state(setup));
      }
      const hs::SceneLighting scene_lighting = hs::lighting_from_atmo(lighting);
      set_lights(scenario, terrain, exposure, context);
      std::printf("camera %s: %dx%d, sun elevation %.2f°, azimuth %.2f°, EV100 %.1f, depth %s\n", cam.name.c_str(),
                  cam.width, cam.height, sun_elevation_deg, glm::degrees(lighting.sun_azimuth_rad), ev100,
                  hs::to_string(depth));

      // The night sky before the clouds, which hide the stars; the light points after the glows (they carry
      // their own fog, atmo.h), so the glow pass's fog does not dim them twice. Passes with nothing to draw
      // (no clouds, no fog, no light above the eye's threshold) return NOTHING_TO_DRAW and cost nothing.
      const std::pair<AtmoPassKind, const char*> passes[] = {{ATMO_PASS_SKY, "sky"},
                                                         {ATMO_PASS_AERIAL_PERSPECTIVE, "aerial perspective"},
                                                         {ATMO_PASS_NIGHT_SKY, "night sky"},
                                                         {ATMO_PASS_CLOUDS, "clouds"},
                                                         {ATMO_PASS_LIGHT_GLOWS, "light glows"},
                                                         {ATMO_PASS_LIGHT_POINTS, "light points"}};
      // The host's surfaces first. The objects' sky occlusion (docs/SKY_OCCLUSION.md) before the aerial
      // perspective adds the air in front: ATMO_PASS_SKY_OCCLUSION over the terrain (facing up:
      // ATMO_PASS_SKY_OCCLUSION_NORMAL_UP), then the objects drawn after it with atmo_sky_occlusion.glsl and
      // their own normals (get_sky_occlusion; the pass would otherwise take their normals from the depth's
      // derivatives: wrong at their silhouettes, and depending on the depth's precision).
      // Neither without objects.
      std::vector<PassTiming> timings = {
          {"terrain (host)", {}, ""}, {"sky occlusion", {}, ""}, {"objects (host)", {}, ""}};  // then the passes
      constexpr size_t kFirstPass = 3;
      const hs::ObjectLighting object_lighting = hs::object_lighting_from_atmo(lighting);
      if (objects.empty()) timings[1].status = timings[2].status = "no objects";
      if (!objects.empty() && options.no_sky_occlusion) timings[1].status = "left out (--no-sky-occlusion)";
      for (const auto& pass : passes) timings.push_back({pass.second, {}, ""});
      PassTimer timer;
      for (int rep = 0; rep < options.repeat; ++rep) {
        target->bind();
        glClearColor(0, 0, 0, 1);
        {
          hs::DepthSetup depth_state(depth);
          if (!depth_state.ok()) throw std::runtime_error("the GL context lacks glClipControl for reversed depth");
          glClearDepth(hs::clear_depth_value(depth));
          glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
          const AtmoFogLighting fog_lighting = view.fog_lighting();
          timer.time([&] {
            terrain.draw(setup, scene_lighting, &fog_lighting);
            return 0;
          });
          timings[0].ms.push_back(timer.last_ms());
          timings[0].query_ms = timer.last_query_ms();
          if (!objects.empty() && !options.no_sky_occlusion) {
            AtmoResult r = timer.time([&] {
              auto info = atmo::make<AtmoPassInfo>(ATMO_TYPE_PASS_INFO);
              info.pass = ATMO_PASS_SKY_OCCLUSION;
              info.flags = ATMO_PASS_SKY_OCCLUSION_NORMAL_UP;
              return context.check(context.api().render_pass(view.handle(), &info), "render_pass");
            });
            timings[1].ms.push_back(timer.last_ms());
            timings[1].query_ms = timer.last_query_ms();
            timings[1].status = plugin.result_string(r);
          }
          if (!objects.empty()) {
            timer.time([&] {
              // This view's occluders this frame (after set_view), for the objects' shader.
              auto occlusion = atmo::make<AtmoSkyOcclusion>(ATMO_TYPE_SKY_OCCLUSION);
              if (!options.no_sky_occlusion)
                context.check(context.api().get_sky_occlusion(view.handle(), &occlusion), "get_sky_occlusion");
              object_meshes.draw(setup, object_lighting, objects.instances,
                                 options.no_sky_occlusion ? nullptr : &occlusion);
              return 0;
            });
            timings[2].ms.push_back(timer.last_ms());
            timings[2].query_ms = timer.last_query_ms();
          }
        }
        const bool stars = !scenario.night_sky || scenario.night_sky->stars;
        for (size_t p = 0; p < std::size(passes); ++p) {
          PassTiming& timing = timings[kFirstPass + p];
          if (passes[p].first == ATMO_PASS_NIGHT_SKY && !stars) {
            timing.status = "left out (night_sky.stars: false)";
            continue;
          }
          AtmoResult r = timer.time([&] { return view.render(passes[p].first); });
          timing.ms.push_back(timer.last_ms());
          timing.query_ms = timer.last_query_ms();
          timing.status = plugin.result_string(r);
        }
      }
      glFinish();
      support::Image image = target->read_color();

      nlohmann::json cam_report = {{"name", cam.name}, {"width", cam.width}, {"height", cam.height},
                                   {"sun_elevation_deg", sun_elevation_deg}, {"ev100", ev100}};
      double frame_ms = 0.0;
      for (const PassTiming& t : timings) {
        std::printf("  %-20s %8.2f ms  %s\n", t.name.c_str(), t.median(), t.status.c_str());
        cam_report["timings_ms"][t.name] = t.median();
        cam_report["gl_timer_query_ms"][t.name] = t.query_ms;
        if (!t.status.empty()) cam_report["status"][t.name] = t.status;
        frame_ms += t.median();
      }
      std::printf("  %-20s %8.2f ms  (per pass: wall time to glFinish, median of %d frame(s), %s)\n", "frame", frame_ms, options.repeat,
                  gl->renderer().c_str());
      cam_report["frame_ms"] = frame_ms;

      const bool linear = scenario.render.output == sc::OutputEncoding::LinearHdr;
      support::Image display = linear ? support::tone_map_to_display(image, static_cast<float>(exposure)) : image;
      const std::string stem = (std::filesystem::path(options.out_dir) / (file_stem + "_" + cam.name)).string();
      if (scenario.outputs.exr) {
        if (!support::write_exr(stem + ".exr", image, &error)) throw std::runtime_error(error);
        std::printf("  wrote %s.exr (%s)\n", stem.c_str(), linear ? "linear, cd/m^2" : "display-referred");
      }
      if (scenario.outputs.png) {
        if (!support::write_png(stem + ".png", display, &error)) throw std::runtime_error(error);
        std::printf("  wrote %s.png\n", stem.c_str());
      }

      // Expectations.
      const std::string prefix = cam.name + ": ";
      if (scenario.expectations.finite) {
        size_t bad = support::count_nonfinite(image);
        checks.add(prefix + "finite", bad == 0, std::to_string(bad) + " pixels with NaN/Inf");
      }
      for (const sc::LuminanceCheck& lc : scenario.expectations.luminance_checks) {
        if (!lc.camera.empty() && lc.camera != cam.name) continue;
        int x = std::clamp(static_cast<int>(lc.u * cam.width), 0, cam.width - 1);
        int y = std::clamp(static_cast<int>(lc.v * cam.height), 0, cam.height - 1);
        double lum = support::luminance(image.pixel(x, y));
        checks.add(prefix + "luminance " + lc.name, lum >= lc.min_cd_m2 && lum <= lc.max_cd_m2,
                   format("%.4g cd/m^2, expected [%.4g, %.4g]", lum, lc.min_cd_m2, lc.max_cd_m2));
      }
      if (scenario.expectations.reference) {
        const sc::Reference& ref = *scenario.expectations.reference;
        std::string ref_path = sc::resolve_path(scenario, ref.image);
        // One reference per scenario: a camera suffix when there are several.
        if (scenario.cameras.size() > 1) ref_path.insert(ref_path.rfind('.'), "_" + cam.name);
        support::Image reference;
        if (!support::read_png(ref_path, &reference, &error)) {
          checks.add(prefix + "reference image", false, error);
        } else if (reference.width != cam.width || reference.height != cam.height) {
          checks.add(prefix + "reference image", false, "size differs from the render");
        } else {
          support::Image quantized;
          std::string png_path = stem + ".png";
          if (!support::read_png(png_path, &quantized, &error)) quantized = display;
          auto diff = support::compare_images(quantized, reference, 1.0);
          checks.add(prefix + "matches " + ref.image, diff.psnr_db >= ref.min_psnr_db,
                     format("PSNR %.2f dB (display-referred PNG, peak 1), expected >= %.1f dB", diff.psnr_db,
                            ref.min_psnr_db));
          cam_report["reference_psnr_db"] = diff.psnr_db;
        }
      }
      if (scenario.expectations.max_frame_ms) {
        checks.add(prefix + "frame time", frame_ms <= *scenario.expectations.max_frame_ms,
                   format("%.2f ms, expected <= %.1f ms", frame_ms, *scenario.expectations.max_frame_ms));
      }
      report["cameras"].push_back(cam_report);
    }
    terrain.gl_shutdown();
    object_meshes.gl_shutdown();
    context.gl_shutdown();

    report["checks"] = checks.list;
    report["not_yet_supported"] = nlohmann::json::array();
    for (const sc::Notice& n : scenario.not_yet_supported)
      report["not_yet_supported"].push_back({{"path", n.path}, {"message", n.message}});
    report["import_notes"] = nlohmann::json::array();
    for (const sc::Notice& n : scenario.import_notes)
      report["import_notes"].push_back({{"path", n.path}, {"message", n.message}});
    std::ofstream(std::filesystem::path(options.out_dir) / (file_stem + "_report.json")) << report.dump(2) << "\n";
    std::printf("scenario %s: %d passed, %d failed\n", scenario.name.c_str(), checks.passed, checks.failed);
    return checks.failed == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "atmo render: %s: %s\n", options.scenario_path.c_str(), e.what());
    return 2;
  }
}

}  // namespace atmo::render
