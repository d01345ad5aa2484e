// spheres_command.h — `atmo spheres`: fits a set of spheres to a closed
// triangle mesh (OBJ or PLY) for soft sky shadows (tools/spheres/sphere_fit.h,
// Wang et al. 2006), prints the fit's error and writes the sphere-set JSON
// (atmo-spheres-1); with --make, writes one of the procedural test objects as
// OBJ instead (data/objects/README.md).
#pragma once

#include <cstdint>
#include <string>

namespace atmo::spheres_cli {

struct Options {
  std::string mesh_path;  // OBJ or PLY
  std::string make;       // aircraft, vehicle or building: write that mesh instead of fitting
  std::string out_path;   // sphere JSON, or the OBJ with --make
  int spheres = 32;
  int grid = 48;
  int measure_grid = 1024;
  uint64_t seed = 1;
};

// 0 on success; 1 when a file cannot be read, is malformed, or cannot be
// written (the message names the file and the line or field).
int run_spheres(const Options& options);

}  // namespace atmo::spheres_cli
