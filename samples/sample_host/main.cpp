// atmo-sample-host: how an integrator first meets Atmo. It loads libatmo.so
// through the host SDK only (atmo.hpp), draws its own terrain, lets the plugin
// draw the sky and the haze over it, and tone-maps the linear HDR result.
//
//   atmo-sample-host [--plugin PATH] [--lat D --lon D] [--utc 2024-06-21T15:00:00Z]
//   atmo-sample-host --frames N --out DIR     headless: N frames as DIR/frame_NNN.png
//   atmo-sample-host --cloud cumulus:4:1200:2500   a cloud layer (repeatable; --vdb FILE[:GRID])
//   atmo-sample-host --lights airport+town --rvr 550   the airport and a town, 15 000 lights, in fog
//   atmo-sample-host --objects apron          an aircraft, vans and a hangar with their sky shadows and bounce
#include <cstdio>
#include <cstring>
#include <string>
#include <tuple>
#include <vector>

#include <CLI/CLI.hpp>

#include "atmo_host_scene/depth_setup.h"
#include "modes.h"

#ifndef ATMO_SAMPLE_DEFAULT_PLUGIN
// No plugin target in this build: let the dynamic loader search for it.
#define ATMO_SAMPLE_DEFAULT_PLUGIN "libatmo.so"
#endif

int main(int argc, char** argv) {
  namespace sample = atmo::sample;
  sample::Options options;
  sample::SceneSettings settings;
  options.plugin_path = ATMO_SAMPLE_DEFAULT_PLUGIN;
  std::string utc = sample::format_utc(settings.utc_posix_s);
  std::string depth = atmo::host_scene::to_string(settings.depth_convention);

  CLI::App app{"Atmo sample host: terrain, then the plugin's sky and aerial perspective, tone-mapped."};
  app.add_option("--plugin", options.plugin_path, "Path of libatmo.so")->capture_default_str();
  app.add_option("--lat", settings.origin.latitude_deg, "Latitude of the airfield, degrees")
      ->check(CLI::Range(-90.0, 90.0))
      ->capture_default_str();
  app.add_option("--lon", settings.origin.longitude_deg, "Longitude of the airfield, degrees")
      ->check(CLI::Range(-180.0, 360.0))
      ->capture_default_str();
  app.add_option("--elevation", settings.origin.height_m, "Airfield height above the WGS84 ellipsoid, m")
      ->capture_default_str();
  app.add_option("--utc", utc, "UTC time, ISO 8601 (2024-06-21T15:00:00Z) or POSIX seconds")->capture_default_str();
  app.add_option("--width", options.width, "Width in pixels")->check(CLI::Range(16, 16384))->capture_default_str();
  app.add_option("--height", options.height, "Height in pixels")->check(CLI::Range(16, 16384))->capture_default_str();
  app.add_option("--visibility", settings.visibility_m, "Meteorological visibility, m")
      ->check(CLI::Range(50.0, 500000.0))
      ->capture_default_str();
  std::string rvr = "none";
  app.add_option("--rvr,--fog", rvr,
                 "Ground fog's visibility as RVR (its MOR), m, 50 to 10000, or none; the lights glow in it")
      ->capture_default_str();
  app.add_option("--fog-top", settings.fog_top_m, "Fog top above the airfield, m")
      ->check(CLI::Range(1.0, 3000.0))
      ->capture_default_str();
  std::string lights = sample::lights_choice_name(settings.lights);
  app.add_option("--lights", lights,
                 "The lights sent to the plugin: none, runway (the terrain's), airport (2 runways, taxiways) or "
                 "airport+town")
      ->capture_default_str();
  const std::string town_help = "With --lights airport+town: the town's lights, 0 to " +
                                std::to_string(sample::max_town_lights()) +
                                " (1 300 a km^2; default: 15 000 lights in all)";
  auto* town = app.add_option("--town", settings.town_lights, town_help)->capture_default_str();
  std::string objects = sample::objects_choice_name(settings.objects);
  app.add_option("--objects", objects,
                 "The host's objects: none, or apron (an aircraft, two vans, one driving, and a hangar north of the "
                 "runway, with their sky shadows and bounce: set_occluders; the camera starts at the apron)")
      ->capture_default_str();
  app.add_option("--objects-dir", options.objects_dir, "Folder of the objects' meshes and sphere sets")
      ->capture_default_str();
  bool no_object_shadows = false, no_bounce = false;
  app.add_flag("--no-object-shadows", no_object_shadows,
               "The objects lit by the open sky, without their sky occlusion (no shadows, no bounce)");
  app.add_flag("--no-bounce", no_bounce, "The objects' shadows without their bounce (ATMO_OCCLUSION_NO_BOUNCE)");
  app.add_option("--ev", settings.ev100, "Exposure, EV100")->capture_default_str();
  app.add_option("--depth", depth, "Depth convention")
      ->check(CLI::IsMember({"standard", "reversed", "log", "logarithmic"}))
      ->capture_default_str();
  app.add_option("--seed", settings.seed, "Terrain seed")->capture_default_str();
  std::vector<std::string> cloud_layers, vdb_layers;
  app.add_option("--cloud", cloud_layers,
                 "A cloud layer, TYPE:OKTAS:BASE_M:TOP_M[:AREA_KM[:SEED]] (cumulus|stratus|overcast|cirrus; heights "
                 "above the airfield, a square area centred on it, default 20 km, seed 1); repeatable")
      ->allow_extra_args(false);
  app.add_option("--vdb", vdb_layers,
                 "A cloud from an OpenVDB file, FILE[:GRID] (grid default \"density\"; the file's origin at the "
                 "airfield); repeatable")
      ->allow_extra_args(false);
  std::string draw_mode = sample::cloud_draw_mode_name(settings.clouds.draw_mode);
  app.add_option("--cloud-draw", draw_mode, "How the clouds pass draws")
      ->check(CLI::IsMember({sample::cloud_draw_mode_name(ATMO_CLOUD_DRAW_AUTO),
                             sample::cloud_draw_mode_name(ATMO_CLOUD_DRAW_IMPOSTORS),
                             sample::cloud_draw_mode_name(ATMO_CLOUD_DRAW_DIRECT),
                             sample::cloud_draw_mode_name(ATMO_CLOUD_DRAW_LAYER)}))
      ->capture_default_str();
  std::string quality = sample::cloud_quality_name(settings.clouds.quality);
  app.add_option("--cloud-quality", quality, "The layer march's cost knob (AtmoViewState.cloud_quality)")
      ->check(CLI::IsMember({"default", "low", "medium", "high", "full"}))
      ->capture_default_str();
  app.add_option("--cloud-divisor", settings.clouds.march_resolution_divisor,
                 "The cloud march renders at 1/N of the viewport per axis (march_resolution_divisor)")
      ->capture_default_str();
  auto* frames = app.add_option("--frames", options.frames, "Headless: render N frames along a fixed approach")
                     ->check(CLI::PositiveNumber);
  auto* out = app.add_option("--out", options.out_dir, "Headless: folder for frame_NNN.png");
  frames->needs(out);
  out->needs(frames);
  app.add_option("--exit-after", options.exit_after, "Window: close after N frames (smoke tests)")
      ->check(CLI::NonNegativeNumber)
      ->excludes(frames);
  app.add_option("--screenshot", options.screenshot, "Window: write the last frame (with the panel) as PNG")
      ->excludes(frames);
  app.add_flag("--verbose", options.verbose, "Print the plugin's debug and info messages");
  CLI11_PARSE(app, argc, argv);

  std::string utc_error;
  if (!sample::parse_utc(utc, &settings.utc_posix_s, &utc_error)) {
    std::fprintf(stderr, "atmo-sample-host: --utc: %s\n", utc_error.c_str());
    return 2;
  }
  atmo::host_scene::parse_depth_convention(depth.c_str(), &settings.depth_convention);
  std::string option_error;
  if (!sample::parse_rvr(rvr, &settings.fog_visibility_m, &option_error)) {
    // Named as given: --fog is the older name of --rvr.
    const char* name = "--rvr";
    for (int i = 1; i < argc; ++i)
      if (std::strcmp(argv[i], "--fog") == 0 || std::strncmp(argv[i], "--fog=", 6) == 0) name = "--fog";
    std::fprintf(stderr, "atmo-sample-host: %s: %s\n", name, option_error.c_str());
    return 2;
  }
  if (!sample::parse_lights_choice(lights, &settings.lights, &option_error)) {
    std::fprintf(stderr, "atmo-sample-host: --lights: %s\n", option_error.c_str());
    return 2;
  }
  if (!sample::parse_objects_choice(objects, &settings.objects, &option_error)) {
    std::fprintf(stderr, "atmo-sample-host: --objects: %s\n", option_error.c_str());
    return 2;
  }
  settings.object_shadows = !no_object_shadows;
  settings.object_bounce = !no_bounce;
  if (settings.town_lights > sample::max_town_lights()) {
    std::fprintf(stderr, "atmo-sample-host: --town: %u is more than %u (all lights together: at most %u)\n",
                 settings.town_lights, sample::max_town_lights(), ATMO_LIGHTS_MAX);
    return 2;
  }
  if (town->count() > 0 && settings.lights != sample::LightsChoice::AirportTown) {
    std::fprintf(stderr, "atmo-sample-host: --town: the town is sent with --lights airport+town only (not %s)\n",
                 lights.c_str());
    return 2;
  }
  using LayerParser = bool (*)(const std::string&, sample::CloudLayerSettings*, std::string*);
  const std::tuple<const char*, const std::vector<std::string>*, LayerParser> layer_options[] = {
      {"--cloud", &cloud_layers, &sample::parse_cloud_layer}, {"--vdb", &vdb_layers, &sample::parse_vdb_layer}};
  for (const auto& [option, texts, parse] : layer_options) {
    for (const std::string& text : *texts) {
      sample::CloudLayerSettings layer;
      std::string layer_error;
      if (!parse(text, &layer, &layer_error)) {
        std::fprintf(stderr, "atmo-sample-host: %s %s\n", option, layer_error.c_str());
        return 2;
      }
      settings.clouds.layers.push_back(layer);
    }
  }
  for (uint32_t m = 0; m < ATMO_CLOUD_DRAW_MODE_COUNT; ++m)
    if (draw_mode == sample::cloud_draw_mode_name(m)) settings.clouds.draw_mode = static_cast<AtmoCloudDrawMode>(m);
  for (uint32_t q = 0; q < ATMO_CLOUD_QUALITY_COUNT; ++q)
    if (quality == sample::cloud_quality_name(q)) settings.clouds.quality = static_cast<AtmoCloudQuality>(q);
  settings.pose = settings.objects == sample::ObjectsChoice::Apron ? sample::apron_view() : sample::approach_path(0.0);

  return options.frames > 0 ? sample::run_headless(options, settings) : sample::run_window(options, settings);
}
