// atmo — the command-line tool: render scenarios through the real plugin,
// validate a plugin build against the ABI contract, compare renders, print
// the ephemeris, fit sphere sets to meshes.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>

#include "clouds_command.h"
#include "compare_command.h"
#include "default_paths.h"
#include "ephemeris_command.h"
#include "render_command.h"
#include "spheres_command.h"
#include "validator.h"

int main(int argc, char** argv) {
  CLI::App app{"atmo: the Atmo atmosphere plugin's command-line tool"};
  app.require_subcommand(1);

  atmo::render::Options render;
  render.plugin_path = atmo::cli::default_plugin_path();
  CLI::App* render_cmd = app.add_subcommand(
      "render", "Render a scenario (JSON, or an OpenSCENARIO .xosc's Environment) through libatmo.so exactly as a host would; write EXR (linear, cd/m^2) and "
                "PNG (tone-mapped), check the scenario's expectations, print per-pass GPU timings");
  render_cmd->add_option("scenario", render.scenario_path,
                         "Scenario file: JSON (see config/scenario.schema.json) or an OpenSCENARIO .xosc, whose "
                         "Environment is imported (docs/OPENSCENARIO.md)")
      ->required()
      ->check(CLI::ExistingFile);
  render_cmd->add_option("--out", render.out_dir, "Output directory (created if missing)")->required();
  render_cmd->add_option("--plugin", render.plugin_path, "Plugin to load")->capture_default_str();
  render_cmd->add_option("--depth", render.depth_override,
                         "Override the scenario's depth convention: standard, reversed or logarithmic");
  render_cmd->add_option("--repeat", render.repeat, "Frames to render per camera for timing (the last is written)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  render_cmd->add_flag("--no-sky-occlusion", render.no_sky_occlusion,
                       "Draw the scenario's objects lit by the open sky, without their sky occlusion (no ATMO_PASS_SKY_OCCLUSION, "
                       "no get_sky_occlusion: no shadows, no bounce), to compare with; the reference image check then "
                       "fails where they cast shadows");

  render_cmd->add_option("--lat", render.import.latitude_deg,
                         "OpenSCENARIO only: the place's latitude, degrees north, over the road network's geoReference "
                         "(default: that, else 48.137)")
      ->check(CLI::Range(-90.0, 90.0));
  render_cmd->add_option("--lon", render.import.longitude_deg,
                         "OpenSCENARIO only: the place's longitude, degrees east (default: the geoReference's, else 11.575)")
      ->check(CLI::Range(-180.0, 180.0));
  render_cmd->add_option("--size", render.size, "OpenSCENARIO only: the camera's WIDTHxHEIGHT in pixels (default 640x360)");

  atmo::validate::Options validate;
  CLI::App* validate_cmd = app.add_subcommand(
      "validate", "Load a plugin build as a host would and check the ABI contract; one process per check; exits "
                  "non-zero if any check fails");
  validate_cmd->add_option("plugin", validate.plugin_path, "Path to the plugin (libatmo.so)")->required();
  validate_cmd->add_option("--filter", validate.filter, "Run only checks whose name contains this text");
  validate_cmd->add_flag("--in-process", validate.in_process, "Run checks in this process (for debugging)");

  atmo::compare::Options compare;
  CLI::App* compare_cmd = app.add_subcommand(
      "compare", "Compare two renders: EXR (linear cd/m^2) by relative luminance error and PSNR, PNG by PSNR; exits "
                 "non-zero outside the given tolerances");
  compare_cmd->add_option("a", compare.a, "First image (.exr or .png)")->required()->check(CLI::ExistingFile);
  compare_cmd->add_option("b", compare.b, "Second image, the reference")->required()->check(CLI::ExistingFile);
  compare_cmd->add_option("--min-psnr", compare.min_psnr_db, "Fail below this PSNR (dB)");
  compare_cmd->add_option("--max-rel-p95", compare.max_relative_p95,
                          "EXR: fail when the 95th percentile relative luminance error exceeds this");
  compare_cmd->add_option("--floor", compare.luminance_floor_cd_m2,
                          "EXR: luminance floor (cd/m^2) of the relative error's denominator")
      ->capture_default_str();

  atmo::ephemeris::Options ephemeris;
  ephemeris.catalog_path = atmo::cli::default_star_catalog_path();
  CLI::App* ephemeris_cmd = app.add_subcommand(
      "ephemeris", "Topocentric apparent places of the Sun, the Moon, Mercury..Saturn (and a catalog star) for an "
                   "observer and a UTC time: azimuth, elevation with and without refraction, distance, RA/Dec, "
                   "magnitude, illuminated fraction, phase, bright limb; the time scales used (docs/EPHEMERIS.md). "
                   "Bad input exits with 2");
  ephemeris_cmd->add_option("--lat", ephemeris.latitude_deg, "Geodetic latitude, degrees north (WGS84)")->required();
  ephemeris_cmd->add_option("--lon", ephemeris.longitude_deg, "Longitude, degrees east")->required();
  ephemeris_cmd->add_option("--height", ephemeris.height_m, "Height above the WGS84 ellipsoid, metres")
      ->capture_default_str();
  ephemeris_cmd->add_option("--utc", ephemeris.utc, "Time, ISO 8601: 2024-12-15T03:00:00Z or with +hh:mm")
      ->required();
  ephemeris_cmd->add_option("--dut1", ephemeris.dut1_s, "UT1 - UTC in seconds (|DUT1| <= 0.9)")
      ->capture_default_str();
  ephemeris_cmd->add_option("--delta-t", ephemeris.delta_t_s, "TT - UT1 in seconds, replacing the leap-second "
                                                               "table / Espenak-Meeus model");
  ephemeris_cmd->add_flag("--json", ephemeris.json, "Print JSON instead of a table");
  CLI::Option* star_hd =
      ephemeris_cmd->add_option("--star", ephemeris.star_hd, "Also a catalog star, by its HD number (e.g. 48915: Sirius)");
  ephemeris_cmd->add_option("--star-name", ephemeris.star_name, "Also a catalog star, by its proper name")
      ->excludes(star_hd);
  ephemeris_cmd->add_option("--catalog", ephemeris.catalog_path, "Star catalog")->capture_default_str();
  ephemeris_cmd->add_flag("--no-refraction", ephemeris.no_refraction, "Refracted elevation = geometric elevation");
  ephemeris_cmd->add_option("--pressure", ephemeris.pressure_hpa,
                            "Air pressure at the observer for refraction, hPa (default: standard atmosphere)");
  ephemeris_cmd->add_option("--temperature", ephemeris.temperature_c,
                            "Air temperature at the observer for refraction, °C (default: standard atmosphere)");

  atmo::clouds_cli::Options clouds;
  CLI::App* clouds_cmd = app.add_subcommand(
      "clouds", "Generates a scenario's procedural cloud layers as the plugin does and writes them to an OpenVDB "
                "file (float grids named density, density_1, ...), to view, edit and load back as \"vdb\" layers");
  clouds_cmd->add_option("scenario", clouds.scenario_path, "Scenario JSON file")->required();
  clouds_cmd->add_option("-o,--out", clouds.out_path, "Output .vdb file")->required();
  clouds_cmd->add_flag("--prototypes", clouds.prototypes_only,
                       "One grid per distinct cloud volume instead of one per placed cloud");

  atmo::spheres_cli::Options spheres;
  CLI::App* spheres_cmd = app.add_subcommand(
      "spheres", "Fits a set of spheres that bounds a closed mesh (OBJ or PLY; metres, x forward, y left, z up), "
                 "minimising the volume outside the mesh (Wang et al. 2006), for soft sky shadows; prints the fit's "
                 "error and writes the sphere-set JSON (atmo-spheres-1). With --make, writes a procedural object "
                 "as OBJ instead. Bad arguments exit with 2, unreadable or malformed files with 1");
  CLI::Option* spheres_mesh = spheres_cmd->add_option("mesh", spheres.mesh_path, "Mesh to fit (.obj or .ply)");
  CLI::Option* spheres_make =
      spheres_cmd->add_option("--make", spheres.make, "Write this procedural object's mesh (OBJ) to --out instead")
          ->check(CLI::IsMember({"aircraft", "vehicle", "building"}))
          ->excludes(spheres_mesh);
  spheres_cmd->add_option("-n,--spheres", spheres.spheres, "Number of spheres")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024))
      ->excludes(spheres_make);
  spheres_cmd->add_option("-o,--out", spheres.out_path, "Output: the sphere-set .json (or the .obj with --make)")
      ->required();
  spheres_cmd->add_option("--grid", spheres.grid, "Inside samples along the mesh's longest side")
      ->capture_default_str()
      ->check(CLI::Range(8, 512))
      ->excludes(spheres_make);
  spheres_cmd->add_option("--measure-grid", spheres.measure_grid,
                          "Rows along the longest side on which the fit's volumes are measured")
      ->capture_default_str()
      ->check(CLI::Range(16, 4096))
      ->excludes(spheres_make);
  spheres_cmd->add_option("--seed", spheres.seed, "Seed of the surface samples (the fit is deterministic per seed)")
      ->capture_default_str()
      ->excludes(spheres_make);

  try {
    app.parse(argc, argv);
    if (*spheres_cmd && spheres.make.empty() && spheres.mesh_path.empty())
      throw CLI::ValidationError("mesh", "give a MESH to fit, or --make aircraft|vehicle|building");
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    // `atmo ephemeris` and `atmo spheres` promise exit code 2 for any bad argument.
    const bool exits_2 = argc > 1 && (std::string(argv[1]) == "ephemeris" || std::string(argv[1]) == "spheres");
    return exits_2 && code != 0 ? 2 : code;
  }
  if (*compare_cmd) return atmo::compare::run_compare(compare);
  if (*clouds_cmd) return atmo::clouds_cli::run_clouds(clouds);
  if (*spheres_cmd) return atmo::spheres_cli::run_spheres(spheres);
  if (*ephemeris_cmd) return atmo::ephemeris::run_ephemeris(ephemeris);

  if (*validate_cmd) return atmo::validate::run_validation(validate) == 0 ? 0 : 1;
  if (*render_cmd) return atmo::render::run_render(render);
  return 2;
}
