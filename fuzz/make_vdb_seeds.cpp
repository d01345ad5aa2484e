// make_vdb_seeds.cpp — writes the VDB fuzz target's seed corpus
// (fuzz/corpus/vdb/): small grids in both of OpenVDB's encodings, io::Stream
// (no grid offsets) and io::File (offsets), plus the plugin's own writer
// (write_vdb_to_memory, with atmo_* metadata). Run once by hand:
//   build-fuzz/fuzz/fuzz_make_vdb_seeds fuzz/corpus/vdb
#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "seed_writer.h"
#include "vdb/vdb_io.h"

namespace {

openvdb::GridBase::Ptr blob(const std::string& name, int radius, double voxel_m) {
  openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
  g->setName(name);
  g->setGridClass(openvdb::GRID_FOG_VOLUME);
  g->setTransform(openvdb::math::Transform::createLinearTransform(voxel_m));
  auto acc = g->getAccessor();
  for (int z = -radius; z <= radius; ++z)
    for (int y = -radius; y <= radius; ++y)
      for (int x = -radius; x <= radius; ++x)
        if (x * x + y * y + z * z <= radius * radius) acc.setValue(openvdb::Coord(x, y, z), 0.5f + 0.1f * float(x));
  return g;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = atmo_fuzz::seed_dir(argc, argv);
  openvdb::initialize();
  const openvdb::GridPtrVec one{blob("density", 2, 10.0)};
  const openvdb::GridPtrVec two{blob("density", 1, 5.0), blob("temperature", 1, 5.0)};
  {  // one grid as io::Stream writes it: no grid offsets
    std::ostringstream os(std::ios::binary);
    openvdb::io::Stream(os).write(one);
    atmo_fuzz::write_seed(dir + "/one_grid_stream.vdb", os.str());
  }
  {  // two grids as io::File writes them: with offsets
    const std::string p = dir + "/two_grids_file.vdb";
    openvdb::io::File file(p);
    file.write(two);
    file.close();
    std::printf("%s\n", p.c_str());
  }
  atmo::clouds::CloudVolume v;
  v.name = "seed";
  v.density = atmo::clouds::DenseGrid(4, 3, 2, 0.25f);
  v.voxel_size_m = 20.0f;
  std::string bytes;
  const std::string error = atmo::vdb::write_vdb_to_memory({v, v}, &bytes);
  if (!error.empty()) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  atmo_fuzz::write_seed(dir + "/atmo_writer_two_volumes.vdb", bytes);
  return 0;
}
