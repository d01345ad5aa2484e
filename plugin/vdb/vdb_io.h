// vdb_io.h — reading and writing OpenVDB files as CloudVolumes (atmo_vdb).
// The one place OpenVDB is compiled: this header names no OpenVDB type (its
// headers cost ~8 s per translation unit), so callers see only CloudVolume.
// Nothing here throws or crashes on bad input: every failure (missing file,
// not a VDB, truncated, wrong grid, NaN) comes back as a message that names
// the source.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/clouds/cloud_volume.h"

namespace atmo::vdb {

struct LoadOptions {
  // Grid to read; "" = the first float (or double) fog-volume grid in the file.
  std::string grid_name = "density";
  // Memory budget of the dense grid, in voxels (default 64 MiB of float). A
  // larger grid is downsampled (box filter, one integer factor on all axes,
  // mass preserved) with a warning, never refused. At least 27 (3^3: one
  // voxel plus its zero padding).
  size_t max_voxels = 256u * 256u * 256u;
  // The scenario's "scale": metres per unit of the file's world space.
  double metres_per_unit = 1.0;
  // Multiplies every value (after negative values are clamped to 0).
  double density_scale = 1.0;
};

struct LoadResult {
  bool ok = false;
  // On failure: what and where, e.g.
  // "clouds/a.vdb: no float grid named \"density\" (grids: \"temperature\" (vec3s))".
  std::string error;
  // Downsampling, negative values clamped, very large values, ignored background.
  std::vector<std::string> warnings;
  // name = "<source>:<grid>". density = the active-voxel bounding box plus one
  // voxel of zero padding on every side (trilinear sampling fades to 0 at the
  // border). voxel_size_m = file voxel size * metres_per_unit * downsample
  // factor. origin_enu_m = world position (times metres_per_unit) of the
  // lower corner of dense voxel 0 (cloud_volume.h: voxel centres at i + 0.5).
  // rotation = identity (rotated files are refused; the layer's heading rotates).
  // optics = defaults, or the atmo_* metadata written by write_vdb_*.
  atmo::clouds::CloudVolume volume;
};

// Parses a whole .vdb held in memory; source_name prefixes every message.
LoadResult load_vdb_from_memory(const std::string& bytes, const std::string& source_name,
                                const LoadOptions& options);
// Reads the file and calls load_vdb_from_memory; a missing or unreadable file
// gives an error naming the path and the system's reason.
LoadResult load_vdb_file(const std::string& path, const LoadOptions& options);

// Writes each volume as a FloatGrid named "density" (the first) or
// "density_<i>" (the others), class fog volume, background 0, voxels below
// 1e-4 left inactive (sparse). Transform: uniform scale voxel_size_m, then a
// translation of origin_enu_m + voxel_size_m / 2, because OpenVDB puts voxel
// centres at integer index coordinates and CloudVolume at integer + 0.5.
// Grid metadata: "atmo_name" (string), "atmo_extinction_per_m", "atmo_albedo",
// "atmo_droplet_diameter_um" (float), restored by the loaders. Volumes with a
// non-identity rotation are refused (not supported yet). Grid offsets are
// written (as io::File does), so readers can skip grids and detect truncation.
// Returns "" on success, else the error.
std::string write_vdb_file(const std::string& path,
                           const std::vector<atmo::clouds::CloudVolume>& volumes);
std::string write_vdb_to_memory(const std::vector<atmo::clouds::CloudVolume>& volumes,
                                std::string* out_bytes);

}  // namespace atmo::vdb
