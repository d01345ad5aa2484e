// Frame cost of the clouds pass (ATMO_PASS_CLOUDS) at 1280x720 with exactly
// 1, 10, 100 and 500 clouds in view, drawn from impostors (the default,
// ATMO_CLOUD_DRAW_IMPOSTORS) and by the direct march (ATMO_CLOUD_DRAW_DIRECT,
// the reference), against a trivial full-screen pass timed in the same run
// (as atmo_gpu_bench): on a noisy machine, and on llvmpipe where "GPU" time
// is rasterisation on the CPU cores, only the ratios carry over.
//
// Time: wall time of the clouds pass alone from a drained queue to glFinish
// (the GL timer query's value alongside as timer_query_ms). Each frame first
// draws the sky and the aerial perspective (untimed; the host depth is the
// far plane everywhere, so there is no geometry but the aerial pass builds
// its volume for the moved camera, as in a host's frame, before the clouds
// pass samples it).
//
// The scene: a procedural 4-okta cumulus layer (base 1200 m, tops 2500 m,
// 40 km square, 5 to 45 km north of the eye), the eye at 800 m looking north
// 5 degrees up, 60 degrees vertical field of view, the Sun ~50 degrees up.
// Exactly N clouds: after set_clouds (through the ABI) the benchmark keeps the
// N instances nearest the eye whose bounding spheres lie wholly in the view
// frustum, drops the rest from the context's field (linked statically:
// abi/objects.h) and bumps the field's versions, so the renderer re-uploads
// and starts its impostors over (bench/cloud_scene.h). The counter `clouds`
// is the count kept; `in_view` the renderer's own count.
//
// Impostors, steady state: a frame looking straight down (it lights and
// uploads the field and builds the programs), then warm-up frames at the
// start position until no impostor is created or re-rendered (the first
// renders all of them: first_view_ms), then every timed frame moves the eye 5 m east, so views
// go stale and are re-rendered within the per-frame budget (8 by default):
// rerendered/frame, created/frame, stale_left/frame, impostors/frame and
// marched/frame are means over the timed frames (CloudDrawStats, what the
// plugin's "clouds: ..." debug line prints). Direct: the same moving eye;
// every cloud is marched. x_trivial: the pass's time over the trivial
// pass's, timed between the frames of the same benchmark (median of 3 after
// each frame, untimed: so both see the same load on a shared machine;
// trivial_ms is its mean); x_trivial_bm: over BM_TrivialFullScreenPass's mean
// (it runs first, by registration order).
#include <benchmark/benchmark.h>
#include <glad/gl.h>

#include "cloud_scene.h"
#include "trivial_pass.h"

namespace {

using cloud_bench::Camera;
using cloud_bench::Host;

constexpr int kWidth = 1280, kHeight = 720;
constexpr double kStepEastM = 5.0;  // per timed frame
const Camera kStart{0.0, 0.0, 800.0, 5.0};

struct World {
  Host host{kWidth, kHeight};
  AtmoCloudLayer layer = atmo::make<AtmoCloudLayer>(ATMO_TYPE_CLOUD_LAYER);
  GLuint trivial_program = 0, vao = 0, query = 0;
  double trivial_ms = 0.0;  // mean of the trivial pass in this run
  // The scene now in the context (mode, N) and where its eye is, so that
  // Google Benchmark's repeated calls of one benchmark continue the flight.
  int mode = -1;
  size_t wanted = 0, kept = 0;
  Camera cam = kStart;
  double first_view_ms = 0.0;
  int warmup_frames = 0;

  World() {
    layer.type = ATMO_CLOUD_CUMULUS;
    layer.coverage_oktas = 4;
    layer.base_m = 1200.0;
    layer.top_m = 2500.0;
    layer.area_size_m = 40000.0;
    layer.area_centre_enu_m[1] = 25000.0;
    layer.seed = 7;
    trivial_program = bench_gl::make_trivial_program();
    glGenVertexArrays(1, &vao);
    glGenQueries(1, &query);
  }

  void target_bind_and_clear() {
    host.target().bind();
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
  }

  void setup(int draw_mode, size_t n) {
    if (draw_mode == mode && n == wanted) return;
    host.set_clouds(cloud_bench::clouds_state(&layer, uint32_t(draw_mode)));
    kept = host.keep_nearest_in_view(n, kStart);
    mode = draw_mode;
    wanted = n;
    cam = kStart;
    // A frame looking straight down (no cloud in view) lights the field,
    // uploads it and builds the programs; then the warm-up at the start: the
    // first frame renders every impostor (first_view_ms), then frames until
    // nothing is created or re-rendered (at most 6).
    host.frame(Camera{kStart.east_m, kStart.north_m, kStart.height_m, -89.0});
    warmup_frames = 0;
    for (int i = 0; i < 6; ++i) {
      const double ms = host.frame(cam);
      if (i == 0) first_view_ms = ms;
      ++warmup_frames;
      const atmo::gl::CloudDrawStats& st = host.stats();
      if ((i > 0 || draw_mode == ATMO_CLOUD_DRAW_DIRECT) && st.impostors_created == 0 && st.impostors_updated == 0)
        break;
    }
  }
};

World& world() {
  static World w;
  return w;
}

// One trivial full-screen pass, wall ms to glFinish (timer query in *query_ms).
double trivial_pass_ms(World& w, double* query_ms) {
  w.host.target().bind();
  glFinish();
  const auto start = std::chrono::steady_clock::now();
  glBeginQuery(GL_TIME_ELAPSED, w.query);
  glBindVertexArray(w.vao);
  glUseProgram(w.trivial_program);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glEndQuery(GL_TIME_ELAPSED);
  glFinish();
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  GLuint64 ns = 0;
  glGetQueryObjectui64v(w.query, GL_QUERY_RESULT, &ns);
  if (query_ms) *query_ms = double(ns) * 1e-6;
  glUseProgram(0);
  return ms;
}

// The median of 3 trivial passes: the ratio base timed between a benchmark's frames.
double trivial_pass_median_ms(World& w) {
  double t[3];
  for (double& x : t) x = trivial_pass_ms(w, nullptr);
  std::sort(t, t + 3);
  return t[1];
}

void BM_TrivialFullScreenPass(benchmark::State& state) {
  World& w = world();
  double total_ms = 0.0, query_total_ms = 0.0;
  for (auto _ : state) {
    double query_ms = 0.0;
    const double ms = trivial_pass_ms(w, &query_ms);
    query_total_ms += query_ms;
    total_ms += ms;
    state.SetIterationTime(ms * 1e-3);
  }
  const double it = std::max<double>(1.0, double(state.iterations()));
  w.trivial_ms = total_ms / it;
  state.counters["timer_query_ms"] = query_total_ms / it;
}

void run_clouds(benchmark::State& state, int draw_mode) {
  World& w = world();
  try {
    w.setup(draw_mode, size_t(state.range(0)));
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  double total_ms = 0.0, query_total_ms = 0.0;
  double in_view = 0, impostors = 0, marched = 0, updated = 0, created = 0, stale = 0, trivial_total_ms = 0.0;
  for (auto _ : state) {
    w.cam.east_m += kStepEastM;
    double query_ms = 0.0;
    const double ms = w.host.frame(w.cam, &query_ms);
    const atmo::gl::CloudDrawStats& st = w.host.stats();
    in_view += st.in_view;
    impostors += st.impostors_drawn;
    marched += st.marched;
    updated += st.impostors_updated;
    created += st.impostors_created;
    stale += st.impostors_stale;
    total_ms += ms;
    query_total_ms += query_ms;
    state.SetIterationTime(ms * 1e-3);
    // The ratio base under the same load: the trivial pass right after each
    // frame (outside the timed region).
    state.PauseTiming();
    trivial_total_ms += trivial_pass_median_ms(w);
    state.ResumeTiming();
  }
  const double it = std::max<double>(1.0, double(state.iterations()));
  state.counters["clouds"] = double(w.kept);
  state.counters["in_view"] = in_view / it;
  state.counters["impostors/frame"] = impostors / it;
  state.counters["marched/frame"] = marched / it;
  state.counters["rerendered/frame"] = updated / it;
  state.counters["created/frame"] = created / it;
  state.counters["stale_left/frame"] = stale / it;
  state.counters["timer_query_ms"] = query_total_ms / it;
  state.counters["first_view_ms"] = w.first_view_ms;
  state.counters["warmup_frames"] = w.warmup_frames;
  // The impostor atlas's GL memory (kept by the renderer across fields: so only where impostors are drawn).
  if (draw_mode == ATMO_CLOUD_DRAW_IMPOSTORS)
    state.counters["atlas_MiB"] = double(w.host.impostor_bytes()) / (1024.0 * 1024.0);
  // Against the trivial pass timed between this benchmark's frames (the same
  // load), and against BM_TrivialFullScreenPass's mean (earlier in the run).
  state.counters["trivial_ms"] = trivial_total_ms / it;
  if (trivial_total_ms > 0.0) state.counters["x_trivial"] = total_ms / trivial_total_ms;
  if (w.trivial_ms > 0.0) state.counters["x_trivial_bm"] = (total_ms / it) / w.trivial_ms;
}

// The sky pass alone at the start eye (800 m, under the layer's tops), with
// no clouds (0), with the whole layer (1), whose shadow map of the Sun makes
// the sky pass take the shadowed light off each ray's part under the clouds
// (sky_pixel.glsl ATMO_SKY_CLOUD_SHADOW, its table built once), and with the
// layer and the eye moving 5 m a frame (2: the table rebuilt every frame);
// the trivial pass after each frame as in run_clouds.
void BM_SkyPass(benchmark::State& state) {
  World& w = world();
  w.host.set_clouds(cloud_bench::clouds_state(state.range(0) ? &w.layer : nullptr, ATMO_CLOUD_DRAW_IMPOSTORS));
  w.mode = -1;  // run_clouds sets its field up again
  Camera cam = kStart;
  w.host.set_view(cam);
  w.target_bind_and_clear();
  w.host.pass_ms(ATMO_PASS_SKY);  // builds the shadow map and the program variant
  double total_ms = 0.0, trivial_total_ms = 0.0;
  for (auto _ : state) {
    if (state.range(0) == 2) {
      cam.east_m += kStepEastM;
      w.host.set_view(cam);
    }
    w.target_bind_and_clear();
    const double ms = w.host.pass_ms(ATMO_PASS_SKY);
    total_ms += ms;
    state.SetIterationTime(ms * 1e-3);
    state.PauseTiming();
    trivial_total_ms += trivial_pass_median_ms(w);
    state.ResumeTiming();
  }
  const double it = std::max<double>(1.0, double(state.iterations()));
  state.counters["trivial_ms"] = trivial_total_ms / it;
  if (trivial_total_ms > 0.0) state.counters["x_trivial"] = total_ms / trivial_total_ms;
}

void BM_Clouds_Impostors(benchmark::State& s) { run_clouds(s, ATMO_CLOUD_DRAW_IMPOSTORS); }
void BM_Clouds_Direct(benchmark::State& s) { run_clouds(s, ATMO_CLOUD_DRAW_DIRECT); }

#define ATMO_CLOUD_BENCH(name) \
  BENCHMARK(name)->UseManualTime()->Unit(benchmark::kMillisecond)->ArgNames({"clouds"})
// (No ArgNames here: with names but no arguments Google Benchmark drops the benchmark.)
BENCHMARK(BM_TrivialFullScreenPass)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_SkyPass)->UseManualTime()->Unit(benchmark::kMillisecond)->ArgNames({"clouds"})->Arg(0)->Arg(1)->Arg(2)->MinTime(1.0);
ATMO_CLOUD_BENCH(BM_Clouds_Impostors)->Arg(1)->Arg(10)->Arg(100)->Arg(500)->MinTime(2.0);
// The direct march takes up to seconds a frame on llvmpipe: a fixed, small number of frames.
ATMO_CLOUD_BENCH(BM_Clouds_Direct)->Arg(1)->Arg(10)->Iterations(5);
ATMO_CLOUD_BENCH(BM_Clouds_Direct)->Arg(100)->Iterations(3);
ATMO_CLOUD_BENCH(BM_Clouds_Direct)->Arg(500)->Iterations(2);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  World& w = world();  // the context first, so the report can name the renderer
  benchmark::AddCustomContext("gl_renderer", w.host.gl().renderer());
  benchmark::AddCustomContext("gl_version", w.host.gl().version());
  benchmark::AddCustomContext("size", std::to_string(kWidth) + "x" + std::to_string(kHeight));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
