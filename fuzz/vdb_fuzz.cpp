// vdb_fuzz.cpp — the OpenVDB reader (plugin/vdb/vdb_io.h) on any bytes held
// as a file in memory. The options come from the input's size, so any .vdb
// file is a seed as it is. Contract (vdb_io.h): no crash or exception on bad
// input; either a volume (padded, within the voxel budget, finite densities
// >= 0, a finite positive voxel size) or an error naming the source.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_check.h"
#include "vdb/vdb_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  atmo::vdb::LoadOptions options;
  const char* grids[] = {"density", "", "density_1"};
  options.grid_name = grids[size % 3];
  if (size % 2) options.max_voxels = 64;  // forces the downsampling path on all but tiny grids
  options.metres_per_unit = (size % 5) ? 1.0 : 1e-3;
  options.density_scale = (size % 7) ? 1.0 : 1e6;
  const atmo::vdb::LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "fuzz.vdb", options);
  if (!r.ok) {
    FUZZ_CHECK(r.error.find("fuzz.vdb") != std::string::npos, "an error names the source");
    return 0;
  }
  const atmo::clouds::DenseGrid& g = r.volume.density;
  FUZZ_CHECK(g.nx >= 3 && g.ny >= 3 && g.nz >= 3, "one voxel plus its padding");
  FUZZ_CHECK(g.values.size() == static_cast<size_t>(g.nx) * g.ny * g.nz, "values match the dimensions");
  FUZZ_CHECK(g.values.size() <= options.max_voxels, "within the voxel budget");
  for (float v : g.values) FUZZ_CHECK(std::isfinite(v) && v >= 0.0f, "densities finite and >= 0");
  FUZZ_CHECK(std::isfinite(r.volume.voxel_size_m) && r.volume.voxel_size_m > 0.0f, "voxel size finite, > 0");
  FUZZ_CHECK(std::isfinite(r.volume.origin_enu_m.x) && std::isfinite(r.volume.origin_enu_m.y) &&
                 std::isfinite(r.volume.origin_enu_m.z),
             "origin finite");
  return 0;
}
