// clouds_command.h — `atmo clouds`: generates a scenario's procedural cloud
// layers exactly as the plugin does (core/clouds/procedural_clouds) and
// writes them to an OpenVDB file (atmo_vdb), one "density" grid per cloud
// volume, so users can look at them, edit them in their own tools, and load
// them back as "vdb" layers. docs/CLOUDS.md.
#pragma once

#include <string>

namespace atmo::clouds_cli {

struct Options {
  std::string scenario_path;
  std::string out_path;          // .vdb
  bool prototypes_only = false;  // one grid per distinct volume instead of one per placed cloud
};

// 0 on success; 2 on bad input (the message names the file and field).
int run_clouds(const Options& options);

}  // namespace atmo::clouds_cli
