// atmo — the command-line tool: render scenarios through the real plugin,
// validate a plugin build against the ABI contract.
#include <CLI/CLI.hpp>

#include <cstdio>

#include "compare_command.h"
#include "render_command.h"
#include "validator.h"

int main(int argc, char** argv) {
  CLI::App app{"atmo: the Atmo atmosphere plugin's command-line tool"};
  app.require_subcommand(1);

  atmo::render::Options render;
  CLI::App* render_cmd = app.add_subcommand(
      "render", "Render a scenario (JSON) through libatmo.so exactly as a host would; write EXR (linear, cd/m^2) and "
                "PNG (tone-mapped), check the scenario's expectations, print per-pass GPU timings");
  render_cmd->add_option("scenario", render.scenario_path, "Scenario file (see config/scenario.schema.json)")
      ->required()
      ->check(CLI::ExistingFile);
  render_cmd->add_option("--out", render.out_dir, "Output directory (created if missing)")->required();
  render_cmd->add_option("--plugin", render.plugin_path, "Plugin to load")->capture_default_str();
  render_cmd->add_option("--depth", render.depth_override,
                         "Override the scenario's depth convention: standard, reversed or logarithmic");
  render_cmd->add_option("--repeat", render.repeat, "Frames to render per camera for timing (the last is written)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));

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

  CLI11_PARSE(app, argc, argv);
  if (*compare_cmd) return atmo::compare::run_compare(compare);

  if (*validate_cmd) return atmo::validate::run_validation(validate) == 0 ? 0 : 1;
  if (*render_cmd) return atmo::render::run_render(render);
  return 2;
}
