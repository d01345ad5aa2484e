/* An out-of-tree host built against an installed Atmo (find_package(Atmo) or pkg-config atmo): loads the
 * installed plugin, places an eye 1.5 km east of an ENU origin with atmo_geodetic.h, and asks the plugin
 * for the light at noon and at midnight (calls that need no GL context). Exit 0 when the Sun is up with
 * daylight at noon and down at midnight; prints what it got. Usage: atmo-installed-host PLUGIN */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "atmo/atmo.h"
#include "atmo/atmo_geodetic.h"
#include "atmo/atmo_loader.h"

static AtmoStructHeader header(uint32_t type, uint32_t size) {
  AtmoStructHeader h;
  memset(&h, 0, sizeof h);
  h.type = type;
  h.struct_size = size;
  return h;
}

static int light_at(const AtmoPluginApi* api, AtmoContext ctx, AtmoView view, double utc, AtmoLighting* out) {
  AtmoFrameState frame;
  memset(&frame, 0, sizeof frame);
  frame.header = header(ATMO_TYPE_FRAME_STATE, sizeof frame);
  frame.utc_posix_s = utc;
  frame.deferred_frames = 1;
  AtmoResult r = api->set_frame(ctx, &frame);
  if (r < 0) return fprintf(stderr, "set_frame: %s: %s\n", api->result_string(r), api->last_error(ctx)), 0;
  memset(out, 0, sizeof *out);
  out->header = header(ATMO_TYPE_LIGHTING, sizeof *out);
  r = api->get_lighting(view, out);
  if (r < 0) return fprintf(stderr, "get_lighting: %s: %s\n", api->result_string(r), api->last_error(ctx)), 0;
  return 1;
}

int main(int argc, char** argv) {
  if (argc != 2) return fprintf(stderr, "usage: %s PLUGIN\n", argv[0]), 2;
  AtmoLoadedPlugin plugin;
  AtmoResult r = atmo_load_plugin(argv[1], ATMO_INTERFACE_VERSION_1, ATMO_INTERFACE_VERSION_CURRENT,
                                  "atmo installed host", &plugin);
  if (r < 0) return fprintf(stderr, "atmo_load_plugin: %s\n", plugin.error), 1;
  const AtmoPluginApi* api = &plugin.api;
  printf("loaded %s %u.%u.%u, interface %u\n", api->plugin_name, api->plugin_version >> 16,
         (api->plugin_version >> 8) & 255u, api->plugin_version & 255u, api->interface_version);

  AtmoContextCreateInfo info;
  memset(&info, 0, sizeof info);
  info.header = header(ATMO_TYPE_CONTEXT_CREATE_INFO, sizeof info);
  info.application_name = "atmo installed host";
  AtmoContext ctx = NULL;
  AtmoView view = NULL;
  int ok = 0;
  if ((r = api->create_context(&info, &ctx)) < 0) {
    fprintf(stderr, "create_context: %s\n", api->result_string(r));
    goto done;
  }
  AtmoViewCreateInfo view_info;
  memset(&view_info, 0, sizeof view_info);
  view_info.header = header(ATMO_TYPE_VIEW_CREATE_INFO, sizeof view_info);
  if ((r = api->create_view(ctx, &view_info, &view)) < 0) {
    fprintf(stderr, "create_view: %s: %s\n", api->result_string(r), api->last_error(ctx));
    goto done;
  }
  /* The host's world is ENU at Zurich airport; its camera 1.5 km east, 300 m up, looking north. */
  const double origin[3] = {47.4582, 8.5555, 432.0}, eye_enu[3] = {1500.0, 0.0, 300.0};
  AtmoViewState vs;
  memset(&vs, 0, sizeof vs);
  vs.header = header(ATMO_TYPE_VIEW_STATE, sizeof vs);
  vs.eye_kind = ATMO_POSITION_GEODETIC;
  vs.world_frame = ATMO_WORLD_ENU;
  atmo_geodetic_from_enu(origin, eye_enu, vs.eye_geodetic);
  memcpy(vs.world_origin_geodetic, origin, sizeof origin);
  /* view_from_world: looking north (view -z = world +y), up = world +z. */
  const double view_from_world[16] = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1};
  const double t = tan(0.5 * 60.0 * ATMO_RAD_PER_DEG), n = 1.0, f = 1e5;
  const double clip[16] = {1.0 / (t * 16.0 / 9.0), 0, 0, 0, 0, 1.0 / t, 0, 0, 0, 0, -(f + n) / (f - n), -1,
                           0, 0, -2.0 * f * n / (f - n), 0};
  memcpy(vs.view_from_world, view_from_world, sizeof view_from_world);
  memcpy(vs.clip_from_view, clip, sizeof clip);
  vs.viewport[2] = 320;
  vs.viewport[3] = 180;
  if ((r = api->set_view(view, &vs)) < 0) {
    fprintf(stderr, "set_view: %s: %s\n", api->result_string(r), api->last_error(ctx));
    goto done;
  }
  printf("eye: %.6f deg N %.6f deg E, %.1f m (from ENU %.0f, %.0f, %.0f m)\n", vs.eye_geodetic[0],
         vs.eye_geodetic[1], vs.eye_geodetic[2], eye_enu[0], eye_enu[1], eye_enu[2]);

  AtmoLighting noon, midnight;
  const double june_21_2024_1100_utc = 1718967600.0; /* ~local solar noon at 8.6 deg E */
  if (!light_at(api, ctx, view, june_21_2024_1100_utc, &noon) ||
      !light_at(api, ctx, view, june_21_2024_1100_utc + 12.0 * 3600.0, &midnight))
    goto done;
  printf("noon: Sun elevation %.2f deg, illuminance %.0f lux (G); midnight: Sun elevation %.2f deg\n",
         noon.sun_elevation_rad * ATMO_DEG_PER_RAD, noon.sun_illuminance_lux[1],
         midnight.sun_elevation_rad * ATMO_DEG_PER_RAD);
  ok = noon.sun_elevation_rad > 1.0 && noon.sun_illuminance_lux[1] > 5e4 && midnight.sun_elevation_rad < 0.0;
  if (!ok) fprintf(stderr, "unexpected light: noon's Sun should be high and bright, midnight's below the horizon\n");
done:
  if (view) api->destroy_view(view);
  if (ctx) api->destroy_context(ctx);
  atmo_unload_plugin(&plugin);
  return ok ? 0 : 1;
}
