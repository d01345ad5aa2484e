// CPU costs of the core and of the ABI's per-frame calls.
#include <benchmark/benchmark.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <glm/gtc/matrix_transform.hpp>
#include <thread>
#include <vector>

#include "atmo/atmo.hpp"
#include "core/atmosphere/atmosphere_model.h"
#include "core/clouds/cloud_transmittance.h"
#include "core/clouds/procedural_clouds.h"
#include "core/scene/scene.h"
#include "core/astro/solar_position.h"

namespace {

void BM_TransmittanceTable256x64(benchmark::State& state) {
  auto atm = atmo::core::make_atmosphere_parameters(atmo::core::AtmosphereSettings{}, 6370000.0, 1.0);
  for (auto _ : state) {
    auto table = atmo::core::compute_transmittance_table(atm, 256, 64, static_cast<int>(state.range(0)));
    benchmark::DoNotOptimize(table.texels.data());
  }
}
BENCHMARK(BM_TransmittanceTable256x64)->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond);

// Width (mu_s) x height (altitude): 64 x 32 is the default; 32 x 32 was, until
// the twilight test showed its steps.
void BM_MultipleScatteringTable(benchmark::State& state) {
  auto atm = atmo::core::make_atmosphere_parameters(atmo::core::AtmosphereSettings{}, 6370000.0, 1.0);
  auto transmittance = atmo::core::compute_transmittance_table(atm, 256, 64);
  for (auto _ : state) {
    auto table = atmo::core::compute_multiple_scattering_table(atm, transmittance, int(state.range(0)),
                                                               int(state.range(1)));
    benchmark::DoNotOptimize(table.texels.data());
  }
}
BENCHMARK(BM_MultipleScatteringTable)->Args({32, 32})->Args({64, 32})->Unit(benchmark::kMillisecond);

// get_lighting's cloud term (clouds::transmittance_along_ray): one ray from
// 300 m under an 8-okta cumulus layer (1000-2800 m, range(0) km square)
// towards the Sun at range(1) degrees; counters: the layer's instances, the
// bucket grid's build time (once per set_clouds) and its memory.
void BM_CloudTransmittanceAlongRay(benchmark::State& state) {
  struct Layer {
    atmo::clouds::CloudField field;
    atmo::clouds::CloudRayIndex index;
    double build_ms = 0.0;
  };
  static std::map<int64_t, Layer> layers;
  Layer& l = layers[state.range(0)];
  if (l.field.instances.empty()) {
    atmo::clouds::CloudLayerSpec spec;
    spec.coverage_oktas = 8;
    spec.base_m = 1000.0;
    spec.top_m = 2800.0;
    spec.area_size_m = 1000.0 * static_cast<double>(state.range(0));
    spec.seed = 1;
    l.field = atmo::clouds::generate_cloud_layer(spec).field;
    const auto t0 = std::chrono::steady_clock::now();
    l.index = atmo::clouds::build_cloud_ray_index(l.field);
    l.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  const double e = static_cast<double>(state.range(1)) * M_PI / 180.0;
  double azimuth = 0.0;
  for (auto _ : state) {
    const glm::dvec3 dir(std::cos(e) * std::sin(azimuth), std::cos(e) * std::cos(azimuth), std::sin(e));
    benchmark::DoNotOptimize(atmo::clouds::transmittance_along_ray(l.field, l.index, glm::dvec3(0.0, 0.0, 300.0), dir));
    azimuth += 0.1;
  }
  state.counters["instances"] = static_cast<double>(l.field.instances.size());
  state.counters["index_build_ms"] = l.build_ms;
  state.counters["index_KiB"] = static_cast<double>(l.index.memory_bytes()) / 1024.0;
}
BENCHMARK(BM_CloudTransmittanceAlongRay)
    ->Args({20, 60})
    ->Args({20, 5})
    ->Args({100, 60})
    ->Args({100, 5})
    ->Unit(benchmark::kMicrosecond);

void BM_SolarPosition(benchmark::State& state) {
  double t = 1.7e9;
  for (auto _ : state) {
    benchmark::DoNotOptimize(atmo::core::solar_position(t, 0.0));
    t += 0.016;
  }
}
BENCHMARK(BM_SolarPosition);

// 1 km over (0° N, 0° E) in ECEF, looking east, 1280x720.
AtmoViewState ecef_view_state() {
  auto vs = atmo::make<AtmoViewState>(ATMO_TYPE_VIEW_STATE);
  vs.eye_kind = ATMO_POSITION_ECEF;
  vs.eye_ecef_m[0] = 6378137.0 + 1000.0;
  glm::dmat4 v = glm::lookAt(glm::dvec3(0), glm::dvec3(0, 1, 0), glm::dvec3(1, 0, 0));
  glm::dmat4 p = glm::perspective(1.0, 16.0 / 9.0, 1.0, 1e5);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      vs.view_from_world[c * 4 + r] = v[c][r];
      vs.clip_from_view[c * 4 + r] = p[c][r];
    }
  vs.viewport[2] = 1280;
  vs.viewport[3] = 720;
  return vs;
}

// set_frame + set_view + get_lighting through the ABI: the per-channel,
// per-frame CPU cost a host pays (no GL).
// The plugin with one context and view at noon, set to ecef_view_state().
struct AbiSession {
  atmo::Plugin plugin{ATMO_PLUGIN_PATH};
  atmo::Context context{plugin};
  atmo::View view{context, 0};
  AtmoFrameState frame = atmo::make<AtmoFrameState>(ATMO_TYPE_FRAME_STATE);
  AtmoViewState vs = ecef_view_state();
  AbiSession() {
    frame.utc_posix_s = 1718964000.0;
    context.set_frame(frame);
    view.set(vs);
  }
};

void BM_AbiPerFrameCalls(benchmark::State& state) {
  AbiSession abi;
  atmo::Context& context = abi.context;
  atmo::View& view = abi.view;
  AtmoFrameState& frame = abi.frame;
  AtmoViewState& vs = abi.vs;
  view.lighting();  // builds the transmittance table once
  for (auto _ : state) {
    frame.utc_posix_s += 1.0 / 60.0;
    vs.eye_ecef_m[1] += 1.0;
    context.set_frame(frame);
    view.set(vs);
    benchmark::DoNotOptimize(view.lighting());
  }
}
BENCHMARK(BM_AbiPerFrameCalls)->Unit(benchmark::kMicrosecond);

// How long a new air takes to show (docs/ABI.md "A changed air shows once its
// tables are built"): set_atmosphere, then get_lighting every millisecond (a
// fast host's frames) until the Sun's illuminance is the new air's. The air
// alternates between 40 km and 5 km visibility. Arg: threads kept busy
// meanwhile (the machine's load). Wall time per iteration is the latency.
void BM_NewAirLatency(benchmark::State& state) {
  AbiSession abi;
  double previous = abi.view.lighting().sun_illuminance_lux[1];  // the first tables: built on this thread
  std::atomic<bool> stop{false};
  std::vector<std::thread> load;
  for (int i = 0; i < state.range(0); ++i)
    load.emplace_back([&stop] {
      volatile double x = 1.0;
      while (!stop.load(std::memory_order_relaxed)) x = x * 1.0000001 + 1e-9;
    });
  bool clear = true;
  int polls = 0;
  for (auto _ : state) {
    clear = !clear;
    auto air = atmo::make<AtmoAtmosphereState>(ATMO_TYPE_ATMOSPHERE_STATE);
    air.visibility_m = clear ? 40000.0 : 5000.0;
    abi.context.set_atmosphere(air);
    for (;;) {
      ++polls;
      // Each poll is a host frame (a 1 kHz host): the new air is due ATMO_DEFERRED_FRAMES frames after it was
      // asked for, and that frame waits for the build if it is not done.
      ++abi.frame.host_frame_number;
      abi.context.set_frame(abi.frame);
      const double now = abi.view.lighting().sun_illuminance_lux[1];
      if (now != previous) {
        previous = now;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  stop = true;
  for (std::thread& t : load) t.join();
  state.counters["polls"] = benchmark::Counter(polls, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_NewAirLatency)->Arg(0)->Arg(2)->Arg(4)->Iterations(6)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
