// GPU time of each pass at 1280x720 (wall time to glFinish; GL timer query alongside), for each
// sky method and LUT size, against two trivial full-screen passes timed in the same run (colour
// from the pixel position; and two linear fetches from 32^3 RGBA32F volumes, what the LUT tier's
// aerial pass fetches): on a noisy machine only the ratios mean something. On llvmpipe "GPU" time
// is CPU rasterisation on this machine's cores. BM_*_Rebuild moves the sun every iteration, so
// the sky-view table and the aerial volume are rebuilt each time: minus the cached figure, that is
// the LUT rebuild cost.
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

GLuint make_program(const char* vs_src, const char* fs_src) {
  GLuint s1 = glCreateShader(GL_VERTEX_SHADER), s2 = glCreateShader(GL_FRAGMENT_SHADER);
  glShaderSource(s1, 1, &vs_src, nullptr);
  glShaderSource(s2, 1, &fs_src, nullptr);
  glCompileShader(s1);
  glCompileShader(s2);
  GLuint program = glCreateProgram();
  glAttachShader(program, s1);
  glAttachShader(program, s2);
  glLinkProgram(program);
  glDeleteShader(s1);
  glDeleteShader(s2);
  return program;
}

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

    const char* vs_src = "#version 330 core\nvoid main(){vec2 p=vec2((gl_VertexID<<1)&2,gl_VertexID&2);"
                         "gl_Position=vec4(p*2.0-1.0,0.5,1.0);}";
    // Colour from the pixel position: a constant colour would let llvmpipe fill tiles without shading.
    trivial_program =
        make_program(vs_src, "#version 330 core\nout vec4 c;void main(){c=vec4(gl_FragCoord.xy*1e-3,0.5,1.0);}");
    two_fetch_program = make_program(
        vs_src,
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
