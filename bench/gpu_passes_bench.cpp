// GPU time of each pass at 1280x720 (wall time to glFinish; GL timer query alongside), for each
// sky method and LUT size, against two trivial full-screen passes timed in the same run (colour
// from the pixel position; and two linear fetches from 32^3 RGBA32F volumes, what the LUT tier's
// aerial pass fetches): on a noisy machine only the ratios mean something. On llvmpipe "GPU" time
// is CPU rasterisation on this machine's cores. BM_*_Rebuild moves the sun every iteration, so
// the sky-view table and the aerial volume are rebuilt each time: minus the cached figure, that is
// the LUT rebuild cost.
//
// BM_NightPoints_*: the night sky's point pass (gl::NightRenderer::draw_points,
// linked statically: it is not reachable through the ABI yet) drawing the real
// visible star and planet list at Innsbruck, 2024-12-15T03:00:00Z (the
// moonlit night scenario), V <= 6.5 and V <= 4.0, in both output encodings
// (DISPLAY_SRGB re-evaluates the sky under every point), with the tables the
// pass samples computed on the CPU and uploaded (as tests/plugin_gl/
// night_points_test.cpp does). Level: the camera and host depth of the other
// passes (lower half host geometry); Up: looking 45 degrees up to the south,
// no host geometry; Down: looking straight down, no source in view (the
// upload and the vertex work alone). The per-point work is counted by the
// in_view counter (sources whose 7x7 squares fall in the viewport's sky) and
// pixels_drawn (checked after the timed loop).
//
// BM_NightSky_*: the LUT sky pass (gl::Renderer::draw_sky, linked statically)
// with the night terms of PassInputs::night filled as plugin/abi/
// night_sky_inputs.cpp add_night_terms does, at Innsbruck, 2024-12-10T19:00Z
// (the Moon 50.1 degrees up at azimuth 181 degrees, 73 % lit; the Sun 35.5
// degrees below the horizon): the bodies from core::compute_sky_bodies, the
// background's rotation from the AstrometryFrame at the same eye and time
// (enu_from_cirs, as the plugin). 192x108 sky-view tables, as BM_Lut_Sky/1.
// Argument `terms`: the bits of gl::NightTerms (0 none, 4 background, 2 Moon
// disc, 1 moonlit sky, 7 all); `view`: 0 the other passes' camera (looking
// north, level, lower half host geometry; the Moon behind), 1 looking at the
// Moon (its disc at the image centre, all sky). The moonlit table is built
// before the timed loop; moon_builds/it (tables built per iteration) shows it
// is not rebuilt in it. BM_NightSky_MoonTableRebuild moves the Moon's
// elevation sine by 3e-3 (> Renderer::kMoonSkyViewElevationStep) every
// iteration, so draw_sky rebuilds the moonlit table each time;
// BM_NightSky_MoonTableOnly times that rebuild alone (Renderer::
// night_sky_textures in DISPLAY_SRGB builds the moonlit table and nothing
// else, the day table being current). After the timed loop one more draw on
// a cleared buffer checks what the terms drew (sky_px, sky_mean_e3,
// centre_e3).
#include <benchmark/benchmark.h>
#include <glad/gl.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "atmo/atmo.hpp"
#include "atmo_support/example_view.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/offscreen_target.h"
#include "core/astro/ephemeris.h"
#include "core/astro/star_catalog.h"
#include "core/atmosphere/atmosphere_model.h"
#include "core/geo/geodesy.h"
#include "core/night_sky/night_plan.h"
#include "core/night_sky/night_sky_twin.h"
#include "core/night_sky/point_sources.h"
#include "core/astro/sky_bodies.h"
#include "core/sky/sky_view_table.h"
#include "gl/night_renderer.h"
#include "gl/renderer.h"
#include "trivial_pass.h"

namespace {

constexpr int kWidth = 1280, kHeight = 720;

struct World {
  std::unique_ptr<atmo::support::HeadlessGl> gl;
  std::unique_ptr<atmo::support::OffscreenTarget> target;
  std::unique_ptr<atmo::Plugin> plugin;
  std::unique_ptr<atmo::Context> context;
  std::unique_ptr<atmo::View> view;
  AtmoHostServices services = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  AtmoViewState view_state{};
  GLuint trivial_program = 0, two_fetch_program = 0, vao = 0, query = 0, volumes[2] = {0, 0};
  double utc_posix_s = 1718964000.0;

  World() {
    std::string error;
    gl = atmo::support::HeadlessGl::create(atmo::support::HeadlessGl::Profile::Core, &error);
    if (!gl) throw std::runtime_error(error);
    target = atmo::support::OffscreenTarget::create(kWidth, kHeight, &error);
    services.gl_get_proc_address = &atmo::support::HeadlessGl::get_proc_address;
    // ATMO_PLUGIN overrides the build-tree path (e.g. a copy run on another machine).
    const char* override_path = std::getenv("ATMO_PLUGIN");
    plugin = std::make_unique<atmo::Plugin>(override_path ? override_path : ATMO_PLUGIN_PATH);
    context = std::make_unique<atmo::Context>(*plugin, &services);
    context->gl_init();
    view = std::make_unique<atmo::View>(*context, 0);
    set_time(utc_posix_s);
    // Lower half: host geometry at about 2 km; upper half: sky.
    target->bind();
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, kWidth, kHeight / 2);
    glClearDepth(0.9995);
    glClear(GL_DEPTH_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
    view_state = atmo::support::example_view_state(kWidth, kHeight, target->depth_texture(), 900.0);
    view->set(view_state);

    trivial_program = bench_gl::make_trivial_program();
    two_fetch_program = bench_gl::make_program(
        bench_gl::kFullScreenVertex,
        "#version 330 core\nuniform sampler3D a;uniform sampler3D b;out vec4 c;void main(){"
        "vec3 p=vec3(gl_FragCoord.xy/vec2(1280.0,720.0),fract(gl_FragCoord.x*1e-3));"
        "c=vec4(texture(a,p).rgb+texture(b,p).rgb,1.0);}");
    glUseProgram(two_fetch_program);
    glUniform1i(glGetUniformLocation(two_fetch_program, "a"), 0);
    glUniform1i(glGetUniformLocation(two_fetch_program, "b"), 1);
    glUseProgram(0);
    std::vector<float> texels(32 * 32 * 32 * 4, 0.25f);
    glGenTextures(2, volumes);
    for (GLuint t : volumes) {
      glBindTexture(GL_TEXTURE_3D, t);
      glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA32F, 32, 32, 32, 0, GL_RGBA, GL_FLOAT, texels.data());
      glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAX_LEVEL, 0);
    }
    glBindTexture(GL_TEXTURE_3D, 0);
    glGenVertexArrays(1, &vao);
    glGenQueries(1, &query);
  }

  void set_time(double t) {
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = t;
    context->set_frame(frame);
  }

  // Wall time of the draw up to glFinish, after draining the queue: on llvmpipe
  // rasterisation is deferred, so a timer query can miss it. The timer query
  // value is kept too (*query_ms) for real GPUs.
  template <typename F>
  double finished_ms(F&& draw, double* query_ms) {
    glFinish();
    auto start = std::chrono::steady_clock::now();
    glBeginQuery(GL_TIME_ELAPSED, query);
    draw();
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    auto end = std::chrono::steady_clock::now();
    GLuint64 ns = 0;
    glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
    *query_ms = ns * 1e-6;
    return std::chrono::duration<double, std::milli>(end - start).count();
  }
};

World& world() {
  static World w;
  return w;
}

// LUT sizes the error-vs-cost chart tries (index = benchmark argument).
struct Size {
  uint32_t sky_view[2];
  uint32_t volume[3];
};
constexpr Size kSizes[] = {{{96, 54}, {16, 16, 16}}, {{192, 108}, {32, 32, 32}}, {{384, 216}, {64, 64, 64}}};

enum Draw { kTrivial, kTwoFetch, kSky, kAerial, kSkyAndAerial };

void run(benchmark::State& state, Draw which, uint32_t method, int size, bool rebuild) {
  World& w = world();
  AtmoViewState vs = w.view_state;
  vs.sky_method = method;
  for (int i = 0; i < 2; ++i) vs.sky_view_table_size[i] = kSizes[size].sky_view[i];
  for (int i = 0; i < 3; ++i) vs.aerial_volume_size[i] = kSizes[size].volume[i];
  w.view->set(vs);
  w.target->bind();
  double query_total_ms = 0.0;
  for (auto _ : state) {
    if (rebuild) {
      w.utc_posix_s += 60.0;  // the sun moves a quarter of a degree: every derived table is rebuilt
      w.set_time(w.utc_posix_s);
    }
    double query_ms = 0.0;
    double ms = w.finished_ms([&] {
      glBindVertexArray(w.vao);
      if (which == kTrivial) {
        glUseProgram(w.trivial_program);
        glDrawArrays(GL_TRIANGLES, 0, 3);
      } else if (which == kTwoFetch) {
        glUseProgram(w.two_fetch_program);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_3D, w.volumes[0]);
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_3D, w.volumes[1]);
        glDrawArrays(GL_TRIANGLES, 0, 3);
      } else {
        if (which != kAerial) w.view->render(ATMO_PASS_SKY);
        if (which != kSky) w.view->render(ATMO_PASS_AERIAL_PERSPECTIVE);
      }
    }, &query_ms);
    query_total_ms += query_ms;
    state.SetIterationTime(ms * 1e-3);
  }
  state.counters["timer_query_ms"] = query_total_ms / std::max<double>(1.0, double(state.iterations()));
  state.counters["Mpixel/s"] =
      benchmark::Counter(double(kWidth) * kHeight * state.iterations() * 1e-6, benchmark::Counter::kIsRate);
}

void BM_TrivialFullScreenPass(benchmark::State& s) { run(s, kTrivial, 0, 1, false); }
void BM_TrivialTwoFetchPass(benchmark::State& s) { run(s, kTwoFetch, 0, 1, false); }
// Argument: LUT size index into kSizes (16^3 / 96x54, 32^3 / 192x108, 64^3 / 384x216).
void BM_Lut_Sky(benchmark::State& s) { run(s, kSky, ATMO_SKY_METHOD_LUT, int(s.range(0)), false); }
void BM_Lut_Aerial(benchmark::State& s) { run(s, kAerial, ATMO_SKY_METHOD_LUT, int(s.range(0)), false); }
void BM_Lut_SkyAndAerial(benchmark::State& s) { run(s, kSkyAndAerial, ATMO_SKY_METHOD_LUT, int(s.range(0)), false); }
void BM_Lut_SkyAndAerial_Rebuild(benchmark::State& s) {
  run(s, kSkyAndAerial, ATMO_SKY_METHOD_LUT, int(s.range(0)), true);
}
void BM_Analytic_SkyAndAerial(benchmark::State& s) { run(s, kSkyAndAerial, ATMO_SKY_METHOD_ANALYTIC, 1, false); }
void BM_March_Sky(benchmark::State& s) { run(s, kSky, ATMO_SKY_METHOD_MARCH, 1, false); }
void BM_March_Aerial(benchmark::State& s) { run(s, kAerial, ATMO_SKY_METHOD_MARCH, 1, false); }
void BM_March_SkyAndAerial(benchmark::State& s) { run(s, kSkyAndAerial, ATMO_SKY_METHOD_MARCH, 1, false); }

#define ATMO_GPU_BENCH(name, seconds) \
  BENCHMARK(name)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(seconds)
ATMO_GPU_BENCH(BM_TrivialFullScreenPass, 1.0);
ATMO_GPU_BENCH(BM_TrivialTwoFetchPass, 1.0);
ATMO_GPU_BENCH(BM_Lut_Sky, 1.0)->DenseRange(0, 2);
ATMO_GPU_BENCH(BM_Lut_Aerial, 1.0)->DenseRange(0, 2);
ATMO_GPU_BENCH(BM_Lut_SkyAndAerial, 1.0)->DenseRange(0, 2);
ATMO_GPU_BENCH(BM_Lut_SkyAndAerial_Rebuild, 1.0)->DenseRange(0, 2);
ATMO_GPU_BENCH(BM_Analytic_SkyAndAerial, 1.0);
ATMO_GPU_BENCH(BM_March_Sky, 2.0);
ATMO_GPU_BENCH(BM_March_Aerial, 2.0);
ATMO_GPU_BENCH(BM_March_SkyAndAerial, 2.0);

// ---- The night sky's point pass ----

namespace night = atmo::core::night;
namespace astro = atmo::core::astro;

constexpr double kNightPosixS = 1734231600.0;  // 2024-12-15T03:00:00Z
constexpr double kLatDeg = 47.26, kLonDeg = 11.35, kHeightM = 900.0;  // example_view_state's eye
constexpr double kLimitingMagnitudes[] = {6.5, 4.0};
constexpr float kNightExposure = 250.0f;  // a moonless night's (docs/NIGHT_SKY.md)

template <typename T>
T checked(std::optional<T> v, const std::string& error) {
  if (!v) throw std::runtime_error(error);
  return std::move(*v);
}

GLuint upload_rgb32f(const atmo::twin::Lut2D& table) {
  GLuint t = 0;
  glGenTextures(1, &t);
  glBindTexture(GL_TEXTURE_2D, t);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, table.width, table.height, 0, GL_RGB, GL_FLOAT, table.texels.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  glBindTexture(GL_TEXTURE_2D, 0);
  return t;
}

enum NightView { kLevel, kUp, kDown };

struct NightScene {
  atmo::gl::NightRenderer renderer;
  atmo::gl::NightSkyTextures textures;
  atmo::gl::PassInputs views[3];
  glm::dmat4 clip_from_view{1.0};
  std::vector<night::PointSource> sources[std::size(kLimitingMagnitudes)];
  GLuint all_far_depth = 0;

  explicit NightScene(World& w) {
    std::string error;
    // The visible list as the plugin would build it (core/night_sky/point_sources).
    const char* catalog_path = std::getenv("ATMO_STAR_CATALOG");
    const astro::StarCatalogLoad catalog =
        astro::load_star_catalog(catalog_path ? catalog_path : ATMO_STAR_CATALOG_PATH);
    if (!catalog.error.empty()) throw std::runtime_error(catalog.error);
    night::StarField field(catalog.stars);
    const astro::TimeScales time = checked(astro::time_scales_from_posix(kNightPosixS, {}, &error), error);
    const astro::Observer observer = checked(astro::observer_from_geodetic(kLatDeg, kLonDeg, kHeightM, &error), error);
    const astro::AstrometryFrame frame = checked(astro::AstrometryFrame::create(time, observer, {}, &error), error);
    const double radius_m = atmo::core::local_earth_radius_m(kLatDeg);
    for (std::size_t i = 0; i < std::size(kLimitingMagnitudes); ++i) {
      night::PointSourceCut cut;
      cut.limiting_magnitude = kLimitingMagnitudes[i];
      cut.earth_radius_m = radius_m;
      night::visible_point_sources(field, frame, cut, nullptr, &sources[i]);
    }
    const astro::BodyEphemeris sun = frame.body(astro::Body::kSun);

    // The tables the pass samples (the Renderer's sizes).
    const auto atm = atmo::core::make_atmosphere_parameters(atmo::core::AtmosphereSettings{}, radius_m,
                                                            sun.distance_m / 149597870700.0);
    const auto transmittance = atmo::core::compute_transmittance_table(atm, atmo::core::kTransmittanceWidth,
                                                                       atmo::core::kTransmittanceHeight);
    const auto multiple_scattering = atmo::core::compute_multiple_scattering_table(atm, transmittance);
    const glm::vec3 sun_enu(sun.direction.enu);
    const auto sky_view = atmo::core::compute_sky_view_table(atm, transmittance, multiple_scattering,
                                                             float(kHeightM), sun_enu.z);
    if (!renderer.init(&error)) throw std::runtime_error(error);
    textures.transmittance = upload_rgb32f(transmittance);
    textures.transmittance_size = glm::vec2(transmittance.width, transmittance.height);
    textures.multiple_scattering = upload_rgb32f(multiple_scattering);
    textures.multiple_scattering_size = glm::vec2(multiple_scattering.width, multiple_scattering.height);
    textures.sky_view = upload_rgb32f(sky_view);
    textures.sky_view_size = glm::vec2(sky_view.width, sky_view.height);
    all_far_depth = atmo::support::make_depth_texture(kWidth, kHeight, std::vector<float>(kWidth * kHeight, 1.0f));

    // Level: the other passes' camera (looking north, level) and host depth.
    const AtmoViewState& vs = w.view_state;
    glm::dmat4 view_from_world(1.0);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) {
        view_from_world[c][r] = vs.view_from_world[c * 4 + r];
        clip_from_view[c][r] = vs.clip_from_view[c * 4 + r];
      }
    for (atmo::gl::PassInputs& in : views) {
      in.atmosphere = atm;
      in.sun_direction_enu = sun_enu;
      in.eye_altitude_m = float(kHeightM);
      in.view_from_clip = glm::mat4(glm::inverse(clip_from_view));
      in.viewport[0] = in.viewport[1] = 0;
      in.viewport[2] = kWidth;
      in.viewport[3] = kHeight;
      in.depth_convention = ATMO_DEPTH_STANDARD;
      in.exposure = kNightExposure;
      in.method = atmo::gl::SkyMethod::kLut;
    }
    views[kLevel].enu_from_view = glm::mat3(glm::transpose(glm::dmat3(view_from_world)));
    views[kLevel].depth_texture = w.target->depth_texture();
    // Up: 45 degrees above the southern horizon, sky only.
    const double pitch = glm::radians(45.0);
    const glm::dmat4 up = glm::lookAt(glm::dvec3(0.0), glm::dvec3(0.0, -std::cos(pitch), std::sin(pitch)),
                                      glm::dvec3(0.0, 0.0, 1.0));
    views[kUp].enu_from_view = glm::mat3(glm::transpose(glm::dmat3(up)));
    views[kUp].depth_texture = all_far_depth;
    // Down: at the ground (nearly straight down; every source is above the horizon cut).
    const glm::dmat4 down = glm::lookAt(glm::dvec3(0.0), glm::dvec3(0.0, 0.01, -1.0), glm::dvec3(0.0, 0.0, 1.0));
    views[kDown].enu_from_view = glm::mat3(glm::transpose(glm::dmat3(down)));
    views[kDown].depth_texture = all_far_depth;
  }

  // Sources whose point square reaches the viewport's sky (the level view's
  // lower half is host geometry): the ones that cost fragments.
  std::size_t in_view(NightView v, const std::vector<night::PointSource>& list) const {
    const glm::dmat3 view_from_enu = glm::transpose(glm::dmat3(views[v].enu_from_view));
    const double margin = atmo::gl::NightRenderer::point_size_px() / 2.0;
    const double min_y = v == kLevel ? kHeight / 2 - margin : -margin;
    std::size_t n = 0;
    for (const night::PointSource& s : list) {
      const glm::dvec4 clip = clip_from_view * glm::dvec4(view_from_enu * glm::dvec3(s.direction_enu), 0.0);
      if (clip.w <= 0.0) continue;
      const double x = (clip.x / clip.w * 0.5 + 0.5) * kWidth, y = (clip.y / clip.w * 0.5 + 0.5) * kHeight;
      n += x > -margin && x < kWidth + margin && y > min_y && y < kHeight + margin;
    }
    return n;
  }
};

NightScene& night_scene() {
  static NightScene n(world());
  return n;
}

// Arguments: 10 x the limiting magnitude (65, 40), the output encoding (0 LINEAR_HDR, 1 DISPLAY_SRGB).
void run_night(benchmark::State& state, NightView view) {
  World& w = world();
  NightScene& n = night_scene();
  const std::size_t list = state.range(0) == 65 ? 0 : 1;
  atmo::gl::PassInputs in = n.views[view];
  in.output_encoding = int(state.range(1));
  const std::vector<night::PointSource>& sources = n.sources[list];
  w.target->bind();
  double query_total_ms = 0.0;
  std::string error;
  for (auto _ : state) {
    double query_ms = 0.0;
    bool ok = true;
    const double ms = w.finished_ms([&] { ok = n.renderer.draw_points(in, n.textures, sources, &error); }, &query_ms);
    if (!ok) {
      state.SkipWithError(error.c_str());
      break;
    }
    query_total_ms += query_ms;
    state.SetIterationTime(ms * 1e-3);
  }
  state.counters["timer_query_ms"] = query_total_ms / std::max<double>(1.0, double(state.iterations()));
  state.counters["sources"] = double(sources.size());
  state.counters["in_view"] = double(n.in_view(view, sources));
  // That the pass drew what it was timed drawing: the pixels it writes on a
  // black colour buffer (about 49 a source in view, less where squares overlap).
  const float black[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glClearBufferfv(GL_COLOR, 0, black);
  if (!n.renderer.draw_points(in, n.textures, sources, &error)) state.SkipWithError(error.c_str());
  const atmo::support::Image img = w.target->read_color();
  std::size_t drawn = 0;
  for (std::size_t i = 0; i < img.pixel_count(); ++i)
    drawn += img.rgba[4 * i] > 0.0f || img.rgba[4 * i + 1] > 0.0f || img.rgba[4 * i + 2] > 0.0f;
  glClearBufferfv(GL_COLOR, 0, black);
  state.counters["pixels_drawn"] = double(drawn);
}

void BM_NightPoints_Level(benchmark::State& s) { run_night(s, kLevel); }
void BM_NightPoints_Up(benchmark::State& s) { run_night(s, kUp); }
void BM_NightPoints_Down(benchmark::State& s) { run_night(s, kDown); }

ATMO_GPU_BENCH(BM_NightPoints_Level, 1.0)->ArgNames({"V10", "srgb"})->ArgsProduct({{65, 40}, {0, 1}});
ATMO_GPU_BENCH(BM_NightPoints_Up, 1.0)->ArgNames({"V10", "srgb"})->ArgsProduct({{65, 40}, {0, 1}});
ATMO_GPU_BENCH(BM_NightPoints_Down, 1.0)->ArgNames({"V10", "srgb"})->Args({65, 0});

// ---- The sky pass's night terms (gl::Renderer::draw_sky) ----

constexpr double kMoonlitPosixS = 1733857200.0;  // 2024-12-10T19:00:00Z: the Moon 50 degrees up, due south
constexpr float kMoonlitExposure = 6.67f;        // EV100 -3, the moonlit night scenario's: 1 / (1.2 * 2^-3)

GLADapiproc load_gl(void* user, const char* name) {
  void* p = atmo::support::HeadlessGl::get_proc_address(user, name);
  GLADapiproc f = nullptr;
  static_assert(sizeof(f) == sizeof(p), "function and object pointers differ in size");
  std::memcpy(&f, &p, sizeof(p));
  return f;
}

// The Moon's direction turned in elevation so that its sine moves by d_sin (azimuth kept).
glm::vec3 moon_moved(const glm::vec3& moon, float d_sin) {
  const float z = moon.z + d_sin;
  const float h = std::sqrt(std::max(1.0f - z * z, 0.0f)), h0 = std::sqrt(moon.x * moon.x + moon.y * moon.y);
  return glm::vec3(moon.x * h / h0, moon.y * h / h0, z);
}

struct NightSkyPassScene {
  atmo::gl::Renderer renderer;
  atmo::gl::PassInputs views[2];  // 0 level (north, host geometry below), 1 at the Moon
  atmo::gl::NightTerms all;       // every term filled; a benchmark keeps the ones it times
  atmo::core::SkyBodies bodies;
  GLuint all_far_depth = 0;

  explicit NightSkyPassScene(World& w) {
    std::string error;
    const atmo::core::Geodetic eye{kLatDeg, kLonDeg, kHeightM};
    bodies = checked(atmo::core::compute_sky_bodies(kMoonlitPosixS, 0.0, eye, &error), error);
    const astro::TimeScales time = checked(astro::time_scales_from_posix(kMoonlitPosixS, {}, &error), error);
    const astro::Observer observer = checked(astro::observer_from_geodetic(kLatDeg, kLonDeg, kHeightM, &error), error);
    const astro::AstrometryFrame frame = checked(astro::AstrometryFrame::create(time, observer, {}, &error), error);
    const double radius_m = atmo::core::local_earth_radius_m(kLatDeg);
    const auto atm =
        atmo::core::make_atmosphere_parameters(atmo::core::AtmosphereSettings{}, radius_m, bodies.sun_distance_au);
    const auto transmittance = atmo::core::compute_transmittance_table(atm, atmo::core::kTransmittanceWidth,
                                                                       atmo::core::kTransmittanceHeight);
    const auto multiple_scattering = atmo::core::compute_multiple_scattering_table(atm, transmittance);
    if (!renderer.init(&load_gl, nullptr, &error)) throw std::runtime_error(error);
    renderer.upload_tables(transmittance, multiple_scattering);
    all_far_depth = atmo::support::make_depth_texture(kWidth, kHeight, std::vector<float>(kWidth * kHeight, 1.0f));

    // The terms as add_night_terms fills them.
    all.moonlit_sky = all.moon_disc = all.background = true;
    all.moon_direction_enu = glm::vec3(bodies.moon_enu);
    const AtmoViewState& vs = w.view_state;
    const double tan_half = 1.0 / std::max(std::abs(vs.clip_from_view[5]), 1e-12);
    all.pixel_angle_rad = float(2.0 * tan_half / double(kHeight));
    all.moonlit_atmosphere = night::moonlit_atmosphere(atm, bodies);
    constexpr double kAuM = 149597870700.0;
    const glm::dvec3 moon_to_sun = night::moon_to_sun_direction(
        bodies.sun_enu_unrefracted, bodies.sun_distance_au * kAuM, bodies.moon_enu_unrefracted, bodies.moon_distance_m);
    all.moon = night::make_moon_disc(bodies.moon_enu, bodies.moon_angular_radius_rad, moon_to_sun,
                                     night::moon_disc_lighting(bodies.moon_phase_angle_rad, bodies.moon_distance_m,
                                                               bodies.moon_sun_distance_au));
    const glm::dmat3 cirs_from_enu = glm::transpose(frame.enu_from_cirs());
    all.sky_background = night::make_night_background(cirs_from_enu, cirs_from_enu * bodies.sun_enu_unrefracted,
                                                      kHeightM, double(atm.bottom_radius_m), night::BackgroundSettings{});

    glm::dmat4 view_from_world(1.0), clip_from_view(1.0);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) {
        view_from_world[c][r] = vs.view_from_world[c * 4 + r];
        clip_from_view[c][r] = vs.clip_from_view[c * 4 + r];
      }
    for (atmo::gl::PassInputs& in : views) {
      in.atmosphere = atm;
      in.sun_direction_enu = glm::vec3(bodies.sun_enu);
      in.eye_altitude_m = float(kHeightM);
      in.view_from_clip = glm::mat4(glm::inverse(clip_from_view));
      in.viewport[0] = in.viewport[1] = 0;
      in.viewport[2] = kWidth;
      in.viewport[3] = kHeight;
      in.depth_convention = ATMO_DEPTH_STANDARD;
      in.exposure = kMoonlitExposure;
      in.output_encoding = int(vs.output_encoding);
      in.method = atmo::gl::SkyMethod::kLut;
      in.table_sizes.sky_view_width = int(kSizes[1].sky_view[0]);  // BM_Lut_Sky/1's table
      in.table_sizes.sky_view_height = int(kSizes[1].sky_view[1]);
    }
    views[0].enu_from_view = glm::mat3(glm::transpose(glm::dmat3(view_from_world)));
    views[0].depth_texture = w.target->depth_texture();
    const glm::dmat4 at_moon = glm::lookAt(glm::dvec3(0.0), bodies.moon_enu, glm::dvec3(0.0, 0.0, 1.0));
    views[1].enu_from_view = glm::mat3(glm::transpose(glm::dmat3(at_moon)));
    views[1].depth_texture = all_far_depth;
  }

  atmo::gl::PassInputs inputs(int view, int bits) const {
    atmo::gl::PassInputs in = views[view];
    in.night = all;
    in.night.moonlit_sky = (bits & 1) != 0;
    in.night.moon_disc = (bits & 2) != 0;
    in.night.background = (bits & 4) != 0;
    return in;
  }
};

NightSkyPassScene& night_sky_pass_scene() {
  static NightSkyPassScene n(world());
  return n;
}

enum NightSkyMode { kSteady, kMoonMoves, kMoonTableOnly };

// Arguments: the NightTerms bits (0..7), the view (0 level, 1 at the Moon).
void run_night_sky(benchmark::State& state, NightSkyMode mode) {
  World& w = world();
  NightSkyPassScene& n = night_sky_pass_scene();
  const int bits = mode == kSteady ? int(state.range(0)) : 1;
  const int view = int(mode == kSteady ? state.range(1) : state.range(0));
  atmo::gl::PassInputs in = n.inputs(view, bits);
  const glm::vec3 moon = in.night.moon_direction_enu;
  // The Moon a little higher and lower, in turn: its elevation sine 3e-3 from the last build's each time
  // (and 1.5e-3 from the position the table was first built for), three times the rebuild step.
  const glm::vec3 moon_at[2] = {moon_moved(moon, 1.5e-3f), moon_moved(moon, -1.5e-3f)};
  w.target->bind();
  std::string error;
  // Bring the tables up to date for `in` before timing (the steady state).
  if (!n.renderer.draw_sky(in, &error)) {
    state.SkipWithError(error.c_str());
    return;
  }
  const atmo::gl::Renderer::Counters before = n.renderer.counters();
  double query_total_ms = 0.0;
  uint64_t k = 0;
  for (auto _ : state) {
    if (mode != kSteady) in.night.moon_direction_enu = moon_at[k++ & 1];
    double query_ms = 0.0;
    bool ok = true;
    const double ms = w.finished_ms([&] {
      if (mode == kMoonTableOnly) {
        atmo::gl::PassInputs srgb = in;
        srgb.output_encoding = ATMO_OUTPUT_DISPLAY_SRGB;  // night_sky_textures builds the moonlit table only then
        atmo::gl::NightSkyTextures textures;
        ok = n.renderer.night_sky_textures(srgb, &textures, &error);
      } else {
        ok = n.renderer.draw_sky(in, &error);
      }
    }, &query_ms);
    if (!ok) {
      state.SkipWithError(error.c_str());
      return;
    }
    query_total_ms += query_ms;
    state.SetIterationTime(ms * 1e-3);
  }
  const atmo::gl::Renderer::Counters& after = n.renderer.counters();
  const double iterations = std::max<double>(1.0, double(state.iterations()));
  state.counters["timer_query_ms"] = query_total_ms / iterations;
  // Tables rebuilt per iteration: 0 in the steady state (the moonlit table cached), 1 where the Moon moves.
  state.counters["moon_builds/it"] = double(after.moon_sky_view_builds - before.moon_sky_view_builds) / iterations;
  state.counters["sky_builds/it"] = double(after.sky_view_builds - before.sky_view_builds) / iterations;
  state.counters["moon_builds_total"] = double(after.moon_sky_view_builds);
  if (mode == kMoonTableOnly) return;
  // That the terms were drawn: one more draw on a cleared buffer; the mean of the sky pixels (those the
  // pass wrote, alpha 1) and the image centre (the Moon's disc in view 1), output units x 1000.
  in.night.moon_direction_enu = moon;
  const float clear[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glClearBufferfv(GL_COLOR, 0, clear);
  if (!n.renderer.draw_sky(in, &error)) {
    state.SkipWithError(error.c_str());
    return;
  }
  const atmo::support::Image img = w.target->read_color();
  double sum = 0.0;
  std::size_t sky = 0;
  for (std::size_t i = 0; i < img.pixel_count(); ++i) {
    if (img.rgba[4 * i + 3] <= 0.0f) continue;
    sum += (img.rgba[4 * i] + img.rgba[4 * i + 1] + img.rgba[4 * i + 2]) / 3.0;
    ++sky;
  }
  const std::size_t centre = std::size_t(kHeight / 2) * kWidth + kWidth / 2;
  state.counters["sky_px"] = double(sky);
  state.counters["sky_mean_e3"] = sky ? 1e3 * sum / double(sky) : 0.0;
  state.counters["centre_e3"] = 1e3 * (img.rgba[4 * centre] + img.rgba[4 * centre + 1] + img.rgba[4 * centre + 2]) / 3.0;
  glClearBufferfv(GL_COLOR, 0, clear);
}

void BM_NightSky(benchmark::State& s) { run_night_sky(s, kSteady); }
void BM_NightSky_MoonTableRebuild(benchmark::State& s) { run_night_sky(s, kMoonMoves); }
void BM_NightSky_MoonTableOnly(benchmark::State& s) { run_night_sky(s, kMoonTableOnly); }

ATMO_GPU_BENCH(BM_NightSky, 1.0)->ArgNames({"terms", "view"})->ArgsProduct({{0, 4, 2, 1, 7}, {0, 1}});
ATMO_GPU_BENCH(BM_NightSky_MoonTableRebuild, 1.0)->ArgNames({"view"})->Arg(0)->Arg(1);
ATMO_GPU_BENCH(BM_NightSky_MoonTableOnly, 1.0)->ArgNames({"view"})->Arg(0);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  World& w = world();  // the context first, so the report can name the renderer
  benchmark::AddCustomContext("gl_renderer", w.gl->renderer());
  benchmark::AddCustomContext("gl_version", w.gl->version());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
