// GPU time of each pass at 1280x720 (wall time to glFinish; GL timer query alongside), against a trivial
// full-screen pass (one triangle, colour from the pixel position) timed in the same run: on a
// noisy machine only the ratios mean something. On llvmpipe "GPU" time is CPU
// rasterisation on this machine's cores.
#include <benchmark/benchmark.h>
#include <glad/gl.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "atmo/atmo.hpp"
#include "atmo_support/example_view.h"
#include "atmo_support/headless_gl.h"
#include "atmo_support/offscreen_target.h"

namespace {

constexpr int kWidth = 1280, kHeight = 720;

struct World {
  std::unique_ptr<atmo::support::HeadlessGl> gl;
  std::unique_ptr<atmo::support::OffscreenTarget> target;
  std::unique_ptr<atmo::Plugin> plugin;
  std::unique_ptr<atmo::Context> context;
  std::unique_ptr<atmo::View> view;
  AtmoHostServices services = atmo::make<AtmoHostServices>(ATMO_TYPE_HOST_SERVICES);
  GLuint trivial_program = 0, vao = 0, query = 0;

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
    auto frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
    frame.utc_posix_s = 1718964000.0;
    context->set_frame(frame);
    // Lower half: host geometry at about 2 km; upper half: sky.
    target->bind();
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, kWidth, kHeight / 2);
    glClearDepth(0.9995);
    glClear(GL_DEPTH_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
    auto vs = atmo::support::example_view_state(kWidth, kHeight, target->depth_texture(), 900.0);
    view->set(vs);

    const char* vs_src = "#version 330 core\nvoid main(){vec2 p=vec2((gl_VertexID<<1)&2,gl_VertexID&2);"
                         "gl_Position=vec4(p*2.0-1.0,0.5,1.0);}";
    // Colour from the pixel position: a constant colour would let llvmpipe fill tiles without shading.
    const char* fs_src = "#version 330 core\nout vec4 c;void main(){c=vec4(gl_FragCoord.xy*1e-3,0.5,1.0);}";
    GLuint s1 = glCreateShader(GL_VERTEX_SHADER), s2 = glCreateShader(GL_FRAGMENT_SHADER);
    glShaderSource(s1, 1, &vs_src, nullptr);
    glShaderSource(s2, 1, &fs_src, nullptr);
    glCompileShader(s1);
    glCompileShader(s2);
    trivial_program = glCreateProgram();
    glAttachShader(trivial_program, s1);
    glAttachShader(trivial_program, s2);
    glLinkProgram(trivial_program);
    glGenVertexArrays(1, &vao);
    glGenQueries(1, &query);
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

void run(benchmark::State& state, int which) {
  World& w = world();
  w.target->bind();
  double query_total_ms = 0.0;
  for (auto _ : state) {
    double query_ms = 0.0;
    double ms = w.finished_ms([&] {
      if (which == 0) {
        glUseProgram(w.trivial_program);
        glBindVertexArray(w.vao);
        glDrawArrays(GL_TRIANGLES, 0, 3);
      } else {
        w.view->render(which == 1 ? ATMO_PASS_SKY : ATMO_PASS_AERIAL_PERSPECTIVE);
      }
    }, &query_ms);
    query_total_ms += query_ms;
    state.SetIterationTime(ms * 1e-3);
  }
  state.counters["timer_query_ms"] = query_total_ms / std::max<double>(1.0, double(state.iterations()));
  state.counters["Mpixel/s"] =
      benchmark::Counter(double(kWidth) * kHeight * state.iterations() * 1e-6, benchmark::Counter::kIsRate);
}

void BM_TrivialFullScreenPass(benchmark::State& s) { run(s, 0); }
void BM_SkyPass_HalfScreenSky(benchmark::State& s) { run(s, 1); }
void BM_AerialPerspective_HalfScreenGeometry(benchmark::State& s) { run(s, 2); }
BENCHMARK(BM_TrivialFullScreenPass)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_SkyPass_HalfScreenSky)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_AerialPerspective_HalfScreenGeometry)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(2.0);

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
