#include "abi/scene_inputs.h"

#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "abi/validation.h"

namespace atmo::abi {

namespace {

// The worker's progress lines, logged on the host's thread (the log service may
// only be called on threads the host calls the plugin on).
void flush_table_log(AtmoContext_T* c) {
  for (TableLogLine& line : c->table_worker.take_messages()) c->services.log(line.severity, line.text);
}

void install(AtmoContext_T* c, AtmosphereTables&& tables) {
  c->transmittance = std::move(tables.transmittance);
  c->multiple_scattering = std::move(tables.multiple_scattering);
  c->tables_key = tables.key;
  ++c->tables_version;
}

// Brings the context's tables towards `wanted`: the first build here; later ones on the worker, installed at
// the host frame they are due (ATMO_DEFERRED_FRAMES after they were asked for), or now when `now`.
void update_tables(AtmoContext_T* c, const TableKey& wanted, bool now = false) {
  c->tables_wanted = wanted;
  flush_table_log(c);
  if (c->tables_version == 0) {
    // First use: there is nothing to draw with, so build here.
    AtmosphereTables tables;
    build_tables(
        wanted, nullptr, [c](TableLogLine line) { c->services.log(line.severity, line.text); }, nullptr, &tables,
        "on the calling thread, before the first frame");
    install(c, std::move(tables));
    return;
  }
  if (wanted == c->tables_key) {
    c->table_worker.cancel_all();  // back to the air in use: drop what was asked for since
    c->tables_requested = TableKey{};
    return;
  }
  if (wanted != c->tables_requested) {
    c->table_worker.request(wanted);
    c->tables_requested = wanted;
    c->tables_requested_frame = c->frame_clock;
    c->tables_due_frame = c->frame_clock + c->deferred_frames;
  }
  // Not before its frame (a fast worker must not make this channel switch before a slow one), and at its frame
  // whatever the worker's pace: it waits for the build (a host frame number that went back counts as due).
  if (!now && c->frame_clock < c->tables_due_frame && c->frame_clock >= c->tables_requested_frame) return;
  c->table_worker.wait_idle();
  AtmosphereTables done;
  if (c->table_worker.take_finished(&done) && done.key == wanted) {
    char ms[32];
    std::snprintf(ms, sizeof(ms), "%.0f", done.build_ms);
    c->services.log(ATMO_LOG_INFO, "atmo: atmosphere tables (" + describe(done.key) + ") in use from host frame " +
                                       std::to_string(c->frame_clock) + " (asked for at frame " +
                                       std::to_string(c->tables_requested_frame) + "), built in " + ms +
                                       " ms on the worker thread");
    install(c, std::move(done));
    c->tables_requested = TableKey{};
    return;
  }
  // The worker could not build them (out of memory): here, now, so every channel still switches at this frame.
  AtmosphereTables tables;
  build_tables(
      wanted, nullptr, [c](TableLogLine line) { c->services.log(line.severity, line.text); }, nullptr, &tables,
      "on the calling thread: the worker's build failed");
  install(c, std::move(tables));
  c->tables_requested = TableKey{};
}

}  // namespace

core::Scene prepare_scene(AtmoContext_T* c, AtmoView_T& view) {
  // set_frame and set_view checked the time and the eye against the
  // ephemeris's own ranges, so it cannot fail here; should it, the call fails
  // (ATMO_ERROR_INTERNAL, with the reason) rather than draw a wrong sky.
  std::string error;
  std::optional<core::SkyBodies> found =
      view.sky_bodies.get(c->utc_posix_s, c->dut1_s, view.eye.eye, view.eye.eye_ecef_m, &error);
  if (!found) throw std::runtime_error("the ephemeris refused a validated time or eye: " + error);
  const core::SkyBodies& bodies = *found;
  core::Scene s = core::make_scene(c->atmosphere, bodies, view.eye);
  update_tables(c, table_key(c->atmosphere, s.sphere_radius_m));
  if (c->tables_key != c->tables_wanted) {
    // The new tables are being built: draw and light with the air (and the
    // model sphere) the tables in use were made for, so everything agrees with them.
    s = core::make_scene(c->tables_key.settings(), bodies, view.eye);
    if (s.sphere_radius_m != c->tables_key.radius_m) {
      s.sphere_radius_m = c->tables_key.radius_m;
      s.atmosphere.bottom_radius_m = static_cast<float>(c->tables_key.radius_m);
      s.atmosphere.top_radius_m = static_cast<float>(c->tables_key.radius_m + core::kAtmosphereThicknessM);
    }
  }
  return s;
}

void air_changed(AtmoContext_T* c) noexcept {
  if (c->tables_version == 0) return;  // the first frame builds them
  try {
    update_tables(c, table_key(c->atmosphere, c->tables_wanted.radius_m));
  } catch (const std::exception& e) {
    // E.g. no thread could be started: the next frame asks again.
    c->services.log(ATMO_LOG_WARNING, std::string("atmo: set_atmosphere: the table build could not start yet: ") + e.what());
  } catch (...) {
  }
}

void wait_for_tables(AtmoContext_T* c, AtmoView_T* view) {
  if (view && view->have_state && c->have_frame) prepare_scene(c, *view);
  c->table_worker.wait_idle();
  if (c->tables_version != 0) {
    update_tables(c, c->tables_wanted, true);
  } else {
    flush_table_log(c);
  }
}

void stop_table_builds(AtmoContext_T* c) noexcept {
  c->table_worker.stop();
  try {
    flush_table_log(c);
  } catch (...) {
  }
}

const core::SkyLighting& view_sky_lighting(AtmoContext_T* ctx, AtmoView_T* view, const core::Scene& scene) {
  constexpr double kSkyLightingSunStepRad = 0.1 * M_PI / 180.0;
  const bool stale = !view->have_sky_lighting || view->sky_lighting_tables_version != ctx->tables_version ||
                     glm::dot(view->sky_lighting_sun_enu, scene.sun_direction_enu) < std::cos(kSkyLightingSunStepRad) ||
                     std::abs(view->sky_lighting_altitude_m - scene.eye_altitude_m) > 0.01 * scene.eye_altitude_m + 10.0;
  if (stale) {
    view->sky_lighting = core::compute_sky_lighting(scene, ctx->transmittance, ctx->multiple_scattering);
    view->sky_lighting_sun_enu = scene.sun_direction_enu;
    view->sky_lighting_altitude_m = scene.eye_altitude_m;
    view->sky_lighting_tables_version = ctx->tables_version;
    view->have_sky_lighting = true;
  }
  return view->sky_lighting;
}

}  // namespace atmo::abi
