// atmo_vdb: .vdb files <-> CloudVolume (plugin/vdb/vdb_io.h). Inputs are
// built here with OpenVDB itself, written both as a stream (io::Stream: no
// grid offsets, the reader must walk every grid) and as a file (io::File:
// with grid offsets), since the loader takes different paths for the two.
#include "vdb/vdb_io.h"

#include <gtest/gtest.h>

#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;
using atmo::clouds::CloudVolume;
using atmo::clouds::DenseGrid;
using atmo::vdb::LoadOptions;
using atmo::vdb::LoadResult;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += x + "\n";
  return s;
}

class VdbTest : public ::testing::Test {
 protected:
  void SetUp() override {
    openvdb::initialize();
    static std::atomic<int> counter{0};
    dir_ = fs::temp_directory_path() /
           ("atmo_vdb_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  static std::string read_all(const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream o;
    o << f.rdbuf();
    return o.str();
  }
  static void write_all(const std::string& p, const std::string& bytes) {
    std::ofstream f(p, std::ios::binary);
    f << bytes;
  }
  // The same grids as io::Stream writes them (no grid offsets) and as
  // io::File writes them (grid offsets).
  std::vector<std::string> encodings(const openvdb::GridPtrVec& grids) {
    std::ostringstream os(std::ios::binary);
    openvdb::io::Stream(os).write(grids);
    const std::string p = path("grids_" + std::to_string(files_++) + ".vdb");
    openvdb::io::File file(p);
    file.write(grids);
    file.close();
    return {os.str(), read_all(p)};
  }

  fs::path dir_;
  int files_ = 0;
};

openvdb::FloatGrid::Ptr float_grid(const std::string& name, double voxel = 1.0,
                                   const openvdb::Vec3d& offset = openvdb::Vec3d(0.0)) {
  openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
  g->setName(name);
  g->setGridClass(openvdb::GRID_FOG_VOLUME);
  openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(voxel);
  xf->postTranslate(offset);
  g->setTransform(xf);
  return g;
}

void add_blob(openvdb::FloatGrid& g, const openvdb::Coord& c, int r, float peak) {
  auto acc = g.getAccessor();
  for (int z = -r; z <= r; ++z) {
    for (int y = -r; y <= r; ++y) {
      for (int x = -r; x <= r; ++x) {
        const double d2 = x * x + y * y + z * z;
        if (d2 > r * r) continue;
        acc.setValue(c.offsetBy(x, y, z), peak * static_cast<float>(1.0 - d2 / (r * r + 1.0)));
      }
    }
  }
}

// Every active voxel of `g` lands, at its world position, on a voxel of `v`
// with its value (times density_scale, negatives clamped), and `v` holds
// nothing else. Only for volumes loaded without downsampling.
void expect_matches_grid(const CloudVolume& v, const openvdb::FloatGrid& g, double metres_per_unit,
                         double density_scale) {
  ASSERT_FALSE(v.density.empty());
  double grid_sum = 0.0;
  int mismatches = 0;
  for (auto it = g.cbeginValueOn(); it; ++it) {
    ASSERT_TRUE(it.isVoxelValue());
    const openvdb::Vec3d w = g.transform().indexToWorld(it.getCoord()) * metres_per_unit;
    const glm::dvec3 p = (glm::dvec3(w[0], w[1], w[2]) - v.origin_enu_m) / double(v.voxel_size_m) - 0.5;
    const int x = static_cast<int>(std::lround(p.x)), y = static_cast<int>(std::lround(p.y)),
              z = static_cast<int>(std::lround(p.z));
    EXPECT_NEAR(p.x, x, 1e-6);
    EXPECT_NEAR(p.y, y, 1e-6);
    EXPECT_NEAR(p.z, z, 1e-6);
    ASSERT_TRUE(x >= 1 && y >= 1 && z >= 1 && x < v.density.nx - 1 && y < v.density.ny - 1 &&
                z < v.density.nz - 1)
        << "voxel outside the padded box: " << x << " " << y << " " << z;
    const double want = std::max(0.0, double(*it)) * density_scale;
    grid_sum += want;
    if (std::abs(v.density.at(x, y, z) - want) > 1e-6 * std::max(1.0, want)) ++mismatches;
  }
  EXPECT_EQ(mismatches, 0);
  double dense_sum = 0.0;
  for (float d : v.density.values) dense_sum += d;
  EXPECT_NEAR(dense_sum, grid_sum, 1e-5 * std::max(1.0, grid_sum)) << "the dense grid holds extra values";
  // One voxel of zero padding on every face.
  for (int z = 0; z < v.density.nz; ++z) {
    for (int y = 0; y < v.density.ny; ++y) {
      for (int x = 0; x < v.density.nx; ++x) {
        const bool face = x == 0 || y == 0 || z == 0 || x == v.density.nx - 1 || y == v.density.ny - 1 ||
                          z == v.density.nz - 1;
        if (face) {
          ASSERT_EQ(v.density.at(x, y, z), 0.0f) << x << " " << y << " " << z;
        }
      }
    }
  }
}

// A volume with a one-voxel empty border and something on every inner face,
// so that the loaded box (active voxels + padding) is the written box.
CloudVolume test_volume(int nx, int ny, int nz, uint32_t seed) {
  CloudVolume v;
  v.name = "test cloud";
  v.density = DenseGrid(nx, ny, nz);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.3f);
  for (int z = 1; z < nz - 1; ++z) {
    for (int y = 1; y < ny - 1; ++y) {
      for (int x = 1; x < nx - 1; ++x) {
        const float d = u(rng);
        v.density.at(x, y, z) = d < 0.3f ? 0.0f : d - 0.3f + 1e-3f;  // sparse, nothing in (0, 1e-4)
      }
    }
  }
  // Corners of the inner box active, so the bounding box is the inner box.
  v.density.at(1, 1, 1) = 0.5f;
  v.density.at(nx - 2, ny - 2, nz - 2) = 0.25f;
  v.voxel_size_m = 37.5f;
  v.origin_enu_m = glm::dvec3(12345.678, -9876.54321, 1500.25);
  v.optics.extinction_per_m = 0.1234f;
  v.optics.albedo = 0.95f;
  v.optics.droplet_diameter_um = 12.5f;
  return v;
}

void expect_same_volume(const CloudVolume& a, const CloudVolume& b) {
  ASSERT_EQ(a.density.nx, b.density.nx);
  ASSERT_EQ(a.density.ny, b.density.ny);
  ASSERT_EQ(a.density.nz, b.density.nz);
  double max_err = 0.0;
  for (size_t i = 0; i < a.density.values.size(); ++i) {
    max_err = std::max(max_err, double(std::abs(a.density.values[i] - b.density.values[i])));
  }
  EXPECT_LT(max_err, 1e-6);
  EXPECT_EQ(a.voxel_size_m, b.voxel_size_m);
  EXPECT_NEAR(a.origin_enu_m.x, b.origin_enu_m.x, 1e-9);
  EXPECT_NEAR(a.origin_enu_m.y, b.origin_enu_m.y, 1e-9);
  EXPECT_NEAR(a.origin_enu_m.z, b.origin_enu_m.z, 1e-9);
  EXPECT_EQ(b.rotation, glm::dquat(1.0, 0.0, 0.0, 0.0));
  EXPECT_EQ(a.optics.extinction_per_m, b.optics.extinction_per_m);
  EXPECT_EQ(a.optics.albedo, b.optics.albedo);
  EXPECT_EQ(a.optics.droplet_diameter_um, b.optics.droplet_diameter_um);
}

TEST_F(VdbTest, RoundTripThroughAFileReproducesValuesPlacementAndOptics) {
  const CloudVolume v = test_volume(23, 17, 12, 1);
  const std::string p = path("round trip.vdb");
  ASSERT_EQ(atmo::vdb::write_vdb_file(p, {v}), "");
  const LoadResult r = atmo::vdb::load_vdb_file(p, LoadOptions());
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.warnings.empty()) << joined(r.warnings);
  expect_same_volume(v, r.volume);
  EXPECT_EQ(r.volume.name, p + ":density");

  // What was written is an ordinary sparse fog volume.
  openvdb::io::File file(p);
  file.open();
  openvdb::FloatGrid::Ptr g = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
  file.close();
  ASSERT_TRUE(g);
  EXPECT_EQ(g->getGridClass(), openvdb::GRID_FOG_VOLUME);
  EXPECT_EQ(g->background(), 0.0f);
  size_t nonzero = 0;
  for (float d : v.density.values) nonzero += d >= 1e-4f ? 1 : 0;
  EXPECT_EQ(g->activeVoxelCount(), nonzero);
  EXPECT_EQ(g->metaValue<std::string>("atmo_name"), "test cloud");
  // OpenVDB voxel centres are at integer index coordinates: voxel (0,0,0)
  // sits half a voxel inside the CloudVolume's origin.
  const openvdb::Vec3d c = g->transform().indexToWorld(openvdb::Coord(0, 0, 0));
  EXPECT_NEAR(c[0], v.origin_enu_m.x + 0.5 * v.voxel_size_m, 1e-9);
  EXPECT_NEAR(c[2], v.origin_enu_m.z + 0.5 * v.voxel_size_m, 1e-9);
}

TEST_F(VdbTest, RoundTripInMemoryWithSeveralVolumes) {
  CloudVolume a = test_volume(10, 11, 12, 2), b = test_volume(14, 9, 8, 3);
  b.voxel_size_m = 0.75f;
  b.origin_enu_m = glm::dvec3(-3.25, 4.5, 0.125);
  b.optics.albedo = 0.5f;
  std::string bytes;
  ASSERT_EQ(atmo::vdb::write_vdb_to_memory({a, b}, &bytes), "");
  LoadResult ra = atmo::vdb::load_vdb_from_memory(bytes, "mem", LoadOptions());
  ASSERT_TRUE(ra.ok) << ra.error;
  expect_same_volume(a, ra.volume);
  EXPECT_EQ(ra.volume.name, "mem:density");
  LoadOptions o;
  o.grid_name = "density_1";
  LoadResult rb = atmo::vdb::load_vdb_from_memory(bytes, "mem", o);
  ASSERT_TRUE(rb.ok) << rb.error;
  expect_same_volume(b, rb.volume);
  EXPECT_EQ(rb.volume.name, "mem:density_1");
}

TEST_F(VdbTest, SparseGridWithTwoDistantBlobsGivesTheirBoundingBox) {
  openvdb::FloatGrid::Ptr g = float_grid("density", 2.0, openvdb::Vec3d(10.0, 20.0, -30.0));
  add_blob(*g, openvdb::Coord(-60, -50, -40), 3, 0.8f);
  add_blob(*g, openvdb::Coord(120, 30, 150), 4, 1.0f);
  for (const std::string& bytes : encodings({g})) {
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "blobs.vdb", LoadOptions());
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_TRUE(r.warnings.empty()) << joined(r.warnings);
    // Active box: x -63..124, y -53..34, z -43..154, plus one voxel each side.
    EXPECT_EQ(r.volume.density.nx, 124 - (-63) + 1 + 2);
    EXPECT_EQ(r.volume.density.ny, 34 - (-53) + 1 + 2);
    EXPECT_EQ(r.volume.density.nz, 154 - (-43) + 1 + 2);
    EXPECT_EQ(r.volume.voxel_size_m, 2.0f);
    // Lower corner of padding voxel 0: index (-64.5, -54.5, -44.5).
    EXPECT_NEAR(r.volume.origin_enu_m.x, 10.0 + 2.0 * -64.5, 1e-9);
    EXPECT_NEAR(r.volume.origin_enu_m.y, 20.0 + 2.0 * -54.5, 1e-9);
    EXPECT_NEAR(r.volume.origin_enu_m.z, -30.0 + 2.0 * -44.5, 1e-9);
    expect_matches_grid(r.volume, *g, 1.0, 1.0);
  }
}

TEST_F(VdbTest, TruncatedDataFailsCleanlyAtEveryCut) {
  openvdb::FloatGrid::Ptr g = float_grid("density");
  add_blob(*g, openvdb::Coord(0, 0, 0), 9, 1.0f);
  add_blob(*g, openvdb::Coord(40, 0, 0), 5, 0.7f);
  openvdb::Vec3SGrid::Ptr vel = openvdb::Vec3SGrid::create();
  vel->setName("vel");
  vel->tree().setValue(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1, 2, 3));
  std::vector<std::string> inputs = encodings({vel, g});
  CloudVolume v = test_volume(30, 30, 30, 4);
  std::string own;
  ASSERT_EQ(atmo::vdb::write_vdb_to_memory({v}, &own), "");
  inputs.push_back(own);
  for (const std::string& bytes : inputs) {
    ASSERT_TRUE(atmo::vdb::load_vdb_from_memory(bytes, "whole.vdb", LoadOptions()).ok);
    std::vector<size_t> cuts = {bytes.size() / 10, bytes.size() / 2, bytes.size() * 99 / 100, bytes.size() - 1};
    for (size_t i = 1; i < 200; ++i) cuts.push_back(bytes.size() * i / 200);
    for (size_t i = 1; i < 64; ++i) cuts.push_back(i);  // inside the header
    for (size_t cut : cuts) {
      const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes.substr(0, cut), "cut.vdb", LoadOptions());
      EXPECT_FALSE(r.ok) << "cut at " << cut << " of " << bytes.size();
      EXPECT_TRUE(contains(r.error, "cut.vdb: ")) << r.error;
      EXPECT_LT(r.error.size(), 400u) << r.error;
      EXPECT_TRUE(r.volume.density.empty());
    }
    // From a file too, at 10 %, 50 %, 99 %.
    for (size_t percent : {10, 50, 99}) {
      const std::string p = path("cut_" + std::to_string(percent) + ".vdb");
      write_all(p, bytes.substr(0, bytes.size() * percent / 100));
      const LoadResult r = atmo::vdb::load_vdb_file(p, LoadOptions());
      EXPECT_FALSE(r.ok);
      EXPECT_TRUE(contains(r.error, p)) << r.error;
    }
  }
  // The file written with grid offsets names the truncated grid.
  const LoadResult r = atmo::vdb::load_vdb_from_memory(own.substr(0, own.size() / 2), "half.vdb", LoadOptions());
  EXPECT_TRUE(contains(r.error, "truncated")) << r.error;
}

TEST_F(VdbTest, EmptyFile) {
  const LoadResult r = atmo::vdb::load_vdb_from_memory("", "clouds/a.vdb", LoadOptions());
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.error, "clouds/a.vdb: file is empty");
  const std::string p = path("empty.vdb");
  write_all(p, "");
  const LoadResult f = atmo::vdb::load_vdb_file(p, LoadOptions());
  EXPECT_FALSE(f.ok);
  EXPECT_EQ(f.error, p + ": file is empty");
}

TEST_F(VdbTest, GarbageIsNotAVdb) {
  std::mt19937 rng(7);
  std::string junk(4096, '\0');
  for (char& c : junk) c = static_cast<char>(rng());
  for (const std::string& bytes : {junk, std::string("VDB"), std::string("#!/bin/sh\necho hello\n")}) {
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "junk.bin", LoadOptions());
    EXPECT_FALSE(r.ok);
    EXPECT_TRUE(contains(r.error, "junk.bin: not a VDB file")) << r.error;
  }
}

TEST_F(VdbTest, MissingFileNamesThePath) {
  const std::string p = path("no such dir/cloud.vdb");
  const LoadResult r = atmo::vdb::load_vdb_file(p, LoadOptions());
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(contains(r.error, p)) << r.error;
  EXPECT_TRUE(contains(r.error, "No such file or directory")) << r.error;
  const LoadResult d = atmo::vdb::load_vdb_file(dir_.string(), LoadOptions());
  EXPECT_FALSE(d.ok);
  EXPECT_TRUE(contains(d.error, "directory")) << d.error;
}

TEST_F(VdbTest, WrongGridNameListsTheGrids) {
  openvdb::Vec3SGrid::Ptr t = openvdb::Vec3SGrid::create();
  t->setName("temperature");
  t->tree().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3s(1, 0, 0));
  openvdb::FloatGrid::Ptr s = float_grid("smoke");
  add_blob(*s, openvdb::Coord(0, 0, 0), 2, 1.0f);
  for (const std::string& bytes : encodings({t, s})) {
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "clouds/a.vdb", LoadOptions());
    EXPECT_FALSE(r.ok);
    EXPECT_EQ(r.error,
              "clouds/a.vdb: no float grid named \"density\" (grids: \"temperature\" (vec3s), \"smoke\" (float))");
    // "" picks the first float grid.
    LoadOptions any;
    any.grid_name = "";
    const LoadResult f = atmo::vdb::load_vdb_from_memory(bytes, "clouds/a.vdb", any);
    ASSERT_TRUE(f.ok) << f.error;
    EXPECT_EQ(f.volume.name, "clouds/a.vdb:smoke");
    expect_matches_grid(f.volume, *s, 1.0, 1.0);
  }
}

TEST_F(VdbTest, Vec3GridIsTheWrongType) {
  openvdb::Vec3SGrid::Ptr g = openvdb::Vec3SGrid::create();
  g->setName("density");
  g->tree().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3s(1, 0, 0));
  for (const std::string& bytes : encodings({g})) {
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "v.vdb", LoadOptions());
    EXPECT_FALSE(r.ok);
    EXPECT_TRUE(contains(r.error, "v.vdb: grid \"density\" has value type vec3s, not a float")) << r.error;
  }
}

TEST_F(VdbTest, LevelSetIsRefused) {
  openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(3.0f);
  g->setName("density");
  g->setGridClass(openvdb::GRID_LEVEL_SET);
  for (int i = -3; i <= 3; ++i) g->tree().setValue(openvdb::Coord(i, 0, 0), float(std::abs(i)) - 1.5f);
  for (const std::string& bytes : encodings({g})) {
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "ls.vdb", LoadOptions());
    EXPECT_FALSE(r.ok);
    EXPECT_TRUE(contains(r.error, "is a level set (signed distance), not a density fog volume")) << r.error;
    LoadOptions any;
    any.grid_name = "";
    const LoadResult a = atmo::vdb::load_vdb_from_memory(bytes, "ls.vdb", any);
    EXPECT_FALSE(a.ok);
    EXPECT_TRUE(contains(a.error, "is a level set (signed distance)")) << a.error;
  }
}

TEST_F(VdbTest, GridWithoutActiveVoxelsIsEmpty) {
  openvdb::FloatGrid::Ptr g = float_grid("density");
  g->tree().setValueOff(openvdb::Coord(1, 2, 3), 0.5f);  // a value, but inactive
  for (const std::string& bytes : encodings({g})) {
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "e.vdb", LoadOptions());
    EXPECT_FALSE(r.ok);
    EXPECT_EQ(r.error, "e.vdb: grid \"density\" is empty: no active voxels");
  }
}

TEST_F(VdbTest, NanAndInfAreErrors) {
  openvdb::FloatGrid::Ptr g = float_grid("density");
  add_blob(*g, openvdb::Coord(0, 0, 0), 3, 1.0f);
  g->tree().setValue(openvdb::Coord(3, 4, 5), std::numeric_limits<float>::quiet_NaN());
  g->tree().setValue(openvdb::Coord(3, 4, 6), std::numeric_limits<float>::infinity());
  for (const std::string& bytes : encodings({g})) {
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "nan.vdb", LoadOptions());
    EXPECT_FALSE(r.ok);
    EXPECT_TRUE(contains(r.error, "nan.vdb: grid \"density\" has 2 NaN or infinite value(s) (first at index (3, 4, 5))"))
        << r.error;
  }
}

TEST_F(VdbTest, NegativeValuesAreClampedWithAWarning) {
  openvdb::FloatGrid::Ptr g = float_grid("density");
  add_blob(*g, openvdb::Coord(0, 0, 0), 3, 1.0f);
  g->tree().setValue(openvdb::Coord(1, 1, 1), -0.25f);
  g->tree().setValue(openvdb::Coord(-2, 0, 0), -2.0f);
  for (const std::string& bytes : encodings({g})) {
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "neg.vdb", LoadOptions());
    ASSERT_TRUE(r.ok) << r.error;
    ASSERT_EQ(r.warnings.size(), 1u) << joined(r.warnings);
    EXPECT_TRUE(contains(r.warnings[0], "2 negative value(s) (min -2) clamped to 0")) << r.warnings[0];
    expect_matches_grid(r.volume, *g, 1.0, 1.0);  // checks the clamped voxels are 0
    float lowest = 0.0f;
    for (float d : r.volume.density.values) lowest = std::min(lowest, d);
    EXPECT_EQ(lowest, 0.0f);
  }
}

double mass(const CloudVolume& v) {
  double s = 0.0;
  for (float d : v.density.values) s += d;
  return s * std::pow(double(v.voxel_size_m), 3.0);
}

glm::dvec3 centre_of_mass(const CloudVolume& v) {
  glm::dvec3 c(0.0);
  double s = 0.0;
  for (int z = 0; z < v.density.nz; ++z)
    for (int y = 0; y < v.density.ny; ++y)
      for (int x = 0; x < v.density.nx; ++x) {
        const double d = v.density.at(x, y, z);
        c += d * (v.origin_enu_m + (glm::dvec3(x, y, z) + 0.5) * double(v.voxel_size_m));
        s += d;
      }
  return c / s;
}

TEST_F(VdbTest, LargeGridIsDownsampledWithinTheBudget) {
  openvdb::FloatGrid::Ptr g = float_grid("density", 0.5, openvdb::Vec3d(100.0, -50.0, 7.0));
  {
    auto acc = g->getAccessor();
    for (int z = 0; z < 40; ++z)
      for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x)
          acc.setValue(openvdb::Coord(x - 5, y + 3, z), 0.2f + 0.8f * float((x * 7 + y * 3 + z * 5) % 13) / 12.0f);
  }
  LoadOptions full_opts;
  const LoadResult full = atmo::vdb::load_vdb_from_memory(encodings({g})[0], "big.vdb", full_opts);
  ASSERT_TRUE(full.ok) << full.error;
  EXPECT_TRUE(full.warnings.empty());
  for (const std::string& bytes : encodings({g})) {
    LoadOptions o;
    o.max_voxels = 4096;
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "big.vdb", o);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_LE(r.volume.density.voxel_count(), 4096u);
    // (ceil(40 / f) + 2)^3 <= 4096 first holds for f = 3: 16^3.
    EXPECT_EQ(r.volume.density.nx, 16);
    EXPECT_EQ(r.volume.voxel_size_m, 0.5f * 3.0f);
    EXPECT_NEAR(mass(r.volume), mass(full.volume), 0.02 * mass(full.volume));
    const glm::dvec3 a = centre_of_mass(r.volume), b = centre_of_mass(full.volume);
    EXPECT_LT(glm::length(a - b), 0.5 * r.volume.voxel_size_m);
    ASSERT_EQ(r.warnings.size(), 1u) << joined(r.warnings);
    EXPECT_TRUE(contains(r.warnings[0], "downsampled by 3")) << r.warnings[0];
  }
}

TEST_F(VdbTest, FarApartVoxelsAreDownsampledNotRefused) {
  openvdb::FloatGrid::Ptr g = float_grid("density", 3.0);
  g->tree().setValue(openvdb::Coord(-2000, 0, 100), 0.5f);
  g->tree().setValue(openvdb::Coord(3000, 4000, 5000), 1.0f);
  for (const std::string& bytes : encodings({g})) {
    LoadOptions o;
    o.max_voxels = 1u << 20;
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "far.vdb", o);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_LE(r.volume.density.voxel_count(), o.max_voxels);
    EXPECT_NEAR(mass(r.volume), 1.5 * 27.0, 1e-3);
    ASSERT_EQ(r.warnings.size(), 1u) << joined(r.warnings);
    // Each voxel's mass sits in the coarse voxel that covers its world position.
    for (const openvdb::Coord& c : {openvdb::Coord(-2000, 0, 100), openvdb::Coord(3000, 4000, 5000)}) {
      const openvdb::Vec3d w = g->transform().indexToWorld(c);
      const glm::dvec3 p = (glm::dvec3(w[0], w[1], w[2]) - r.volume.origin_enu_m) / double(r.volume.voxel_size_m);
      const float d = r.volume.density.at(int(p.x), int(p.y), int(p.z));
      EXPECT_NEAR(d * std::pow(double(r.volume.voxel_size_m), 3.0), g->tree().getValue(c) * 27.0, 1e-3);
    }
  }
}

TEST_F(VdbTest, InstancedGridIsAnErrorNotACrash) {
  openvdb::FloatGrid::Ptr g = float_grid("smoke");
  add_blob(*g, openvdb::Coord(0), 2, 1.0f);
  openvdb::GridBase::Ptr copy = g->copyGrid();  // shares the tree: written as an instance
  copy->setName("density");
  for (const std::string& bytes : encodings({g, copy})) {
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "inst.vdb", LoadOptions());
    EXPECT_FALSE(r.ok);
    EXPECT_TRUE(contains(r.error, "instance")) << r.error;
    LoadOptions o;
    o.grid_name = "smoke";
    EXPECT_TRUE(atmo::vdb::load_vdb_from_memory(bytes, "inst.vdb", o).ok);
  }
}

TEST_F(VdbTest, TilesAreExpandedAndDownsampledByTheirOverlap) {
  openvdb::FloatGrid::Ptr g = float_grid("density");
  // 32^3 aligned: OpenVDB stores it as tiles, not voxels.
  g->tree().fill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(31)), 0.5f, true);
  g->tree().setValue(openvdb::Coord(40, 3, 3), 1.0f);
  ASSERT_GT(g->tree().activeTileCount(), 0u);
  const double want_sum = 0.5 * 32 * 32 * 32 + 1.0;
  for (const std::string& bytes : encodings({g})) {
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "tiles.vdb", LoadOptions());
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.volume.density.nx, 41 + 2);
    EXPECT_EQ(r.volume.density.ny, 32 + 2);
    EXPECT_EQ(r.volume.density.at(1, 1, 1), 0.5f);
    EXPECT_EQ(r.volume.density.at(32, 32, 32), 0.5f);
    EXPECT_EQ(r.volume.density.at(33, 1, 1), 0.0f);
    EXPECT_EQ(r.volume.density.at(41, 4, 4), 1.0f);
    EXPECT_NEAR(mass(r.volume), want_sum, 1e-3);
    LoadOptions o;
    o.max_voxels = 1000;  // (ceil(41 / f) + 2) * (ceil(32 / f) + 2)^2 <= 1000: f = 5
    const LoadResult d = atmo::vdb::load_vdb_from_memory(bytes, "tiles.vdb", o);
    ASSERT_TRUE(d.ok) << d.error;
    EXPECT_EQ(d.volume.voxel_size_m, 5.0f);
    EXPECT_LE(d.volume.density.voxel_count(), 1000u);
    EXPECT_NEAR(mass(d.volume), want_sum, 1e-3 * want_sum);
  }
}

TEST_F(VdbTest, MetresPerUnitAndDensityScaleAreApplied) {
  openvdb::FloatGrid::Ptr g = float_grid("density", 0.25, openvdb::Vec3d(1.0, 2.0, 3.0));
  add_blob(*g, openvdb::Coord(10, -4, 7), 4, 0.9f);
  for (const std::string& bytes : encodings({g})) {
    LoadOptions o;
    o.metres_per_unit = 40.0;
    o.density_scale = 0.5;
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "s.vdb", o);
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_FLOAT_EQ(r.volume.voxel_size_m, 0.25f * 40.0f);
    EXPECT_NEAR(r.volume.origin_enu_m.x, (1.0 + 0.25 * (6 - 1.5)) * 40.0, 1e-9);
    expect_matches_grid(r.volume, *g, 40.0, 0.5);
    EXPECT_NEAR(max_density(r.volume.density), 0.45, 1e-6);
  }
}

TEST_F(VdbTest, LargeValuesAreKeptWithAWarning) {
  openvdb::FloatGrid::Ptr g = float_grid("density");
  add_blob(*g, openvdb::Coord(0), 2, 30.0f);
  const LoadResult r = atmo::vdb::load_vdb_from_memory(encodings({g})[1], "hot.vdb", LoadOptions());
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(max_density(r.volume.density), 30.0f);  // the centre voxel, unclamped
  ASSERT_EQ(r.warnings.size(), 1u) << joined(r.warnings);
  EXPECT_TRUE(contains(r.warnings[0], "above 10")) << r.warnings[0];
}

TEST_F(VdbTest, HalfFloatAndDoubleGridsLoad) {
  openvdb::FloatGrid::Ptr h = float_grid("density");
  add_blob(*h, openvdb::Coord(2, 3, 4), 3, 1.0f);
  h->setSaveFloatAsHalf(true);
  for (const std::string& bytes : encodings({h})) {
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "half.vdb", LoadOptions());
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_NEAR(max_density(r.volume.density), 1.0, 1e-3);
  }
  openvdb::DoubleGrid::Ptr d = openvdb::DoubleGrid::create(0.0);
  d->setName("density");
  d->tree().setValue(openvdb::Coord(5, 5, 5), 0.75);
  d->tree().setValue(openvdb::Coord(7, 5, 5), 0.25);
  for (const std::string& bytes : encodings({d})) {
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "double.vdb", LoadOptions());
    ASSERT_TRUE(r.ok) << r.error;
    EXPECT_EQ(r.volume.density.nx, 3 + 2);
    EXPECT_EQ(r.volume.density.at(1, 1, 1), 0.75f);
    EXPECT_EQ(r.volume.density.at(3, 1, 1), 0.25f);
  }
}

TEST_F(VdbTest, UnsupportedTransformsAreErrors) {
  struct Case {
    openvdb::math::Transform::Ptr xf;
    std::string expect;
  };
  openvdb::math::Transform::Ptr rotated = openvdb::math::Transform::createLinearTransform(1.0);
  rotated->preRotate(0.3, openvdb::math::Z_AXIS);
  openvdb::math::Transform::Ptr stretched = openvdb::math::Transform::createLinearTransform(1.0);
  stretched->preScale(openvdb::Vec3d(1.0, 2.0, 1.0));
  openvdb::math::Transform::Ptr frustum = openvdb::math::Transform::createFrustumTransform(
      openvdb::BBoxd(openvdb::Vec3d(0.0), openvdb::Vec3d(10.0)), 0.5, 10.0, 1.0);
  for (const Case& c : {Case{rotated, "rotated"}, Case{stretched, "non-uniform voxel size"},
                        Case{frustum, "non-linear transform"}}) {
    openvdb::FloatGrid::Ptr g = float_grid("density");
    add_blob(*g, openvdb::Coord(0), 2, 1.0f);
    g->setTransform(c.xf);
    for (const std::string& bytes : encodings({g})) {
      const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "xf.vdb", LoadOptions());
      EXPECT_FALSE(r.ok);
      EXPECT_TRUE(contains(r.error, c.expect)) << r.error;
    }
  }
}

// A damaged length in a grid's metadata (found by fuzz/vdb_fuzz.cpp): OpenVDB's
// MetaMap::readMeta allocates and zeroes whatever a length says before reading
// it (a 70 KB file took 30 s and 1 GB). The reader checks every metadata
// length against the bytes left first, and says which length is wrong.
TEST_F(VdbTest, DamagedMetadataLengthIsAnErrorBeforeAnyAllocation) {
  openvdb::FloatGrid::Ptr g = float_grid("density");
  add_blob(*g, openvdb::Coord(0), 2, 1.0f);
  g->insertMeta("atmo_note_key", openvdb::StringMetadata("atmo_note_value"));
  for (const std::string& good : encodings({g})) {
    ASSERT_TRUE(atmo::vdb::load_vdb_from_memory(good, "m.vdb", LoadOptions()).ok);
    // The 4-byte length before the key (a string) and before the value (the metadata's size).
    for (const char* field : {"atmo_note_key", "atmo_note_value"}) {
      const size_t at = good.find(field);
      ASSERT_NE(at, std::string::npos);
      ASSERT_GE(at, 4u);
      std::string bad = good;
      const uint32_t huge = 0x7ffffff0u;
      std::memcpy(&bad[at - 4], &huge, sizeof(huge));
      const LoadResult r = atmo::vdb::load_vdb_from_memory(bad, "m.vdb", LoadOptions());
      EXPECT_FALSE(r.ok) << field;
      EXPECT_TRUE(contains(r.error, "m.vdb") && contains(r.error, "metadata") &&
                  contains(r.error, "2147483632-byte") && contains(r.error, "runs past the end"))
          << field << ": " << r.error;
    }
  }
}

// OpenVDB 10's bloscFromStream/unzipFromStream read a chunk stored
// uncompressed (size -n) into the node's buffer before comparing n with the
// buffer's size: a damaged n overflowed the heap (fuzz/findings/). A leaf with
// three active values is mask-compressed to 12 bytes, which zip stores
// uncompressed (-12, then the floats; blosc pads small chunks and compresses
// them, so the blosc path is the fuzzer's file below); the damaged files say
// more, or less. Before the fix: heap-buffer-overflow in unzipFromStream (ASan).
TEST_F(VdbTest, DamagedChunkSizeIsAnErrorBeforeOpenVdbReadsIntoTheNode) {
  openvdb::FloatGrid::Ptr g = float_grid("density");
  g->setGridClass(openvdb::GRID_UNKNOWN);  // OpenVDB never zips a fog volume
  const float v[3] = {0.625f, 0.375f, 0.875f};
  for (int i = 0; i < 3; ++i) g->tree().setValue(openvdb::Coord(i, 0, 0), v[i]);
  std::string chunk(8 + sizeof(v), '\0');  // int64 size, then the three values
  const int64_t stored = -static_cast<int64_t>(sizeof(v));
  std::memcpy(&chunk[0], &stored, 8);
  std::memcpy(&chunk[8], v, sizeof(v));
  {
    const uint32_t compression = openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK;
    std::ostringstream os(std::ios::binary);
    openvdb::io::Stream out(os);
    out.setCompression(compression);
    out.write({g});
    const std::string good = os.str();
    ASSERT_TRUE(atmo::vdb::load_vdb_from_memory(good, "c.vdb", LoadOptions()).ok);
    const size_t at = good.find(chunk);
    ASSERT_NE(at, std::string::npos) << "no uncompressed 12-byte leaf chunk";
    for (int64_t says : {int64_t{-4012}, int64_t{-8}, std::numeric_limits<int64_t>::min()}) {
      std::string bad = good;
      std::memcpy(&bad[at], &says, 8);
      const LoadResult r = atmo::vdb::load_vdb_from_memory(bad, "c.vdb", LoadOptions());
      EXPECT_FALSE(r.ok) << says;
      EXPECT_TRUE(contains(r.error, "c.vdb") && contains(r.error, "uncompressed chunk at byte " + std::to_string(at)) &&
                  contains(r.error, "where its node holds 12") && contains(r.error, "\"density\""))
          << says << ": " << r.error;
    }
    // A compressed chunk larger than the file is refused before OpenVDB allocates it.
    std::string bad = good;
    const int64_t huge = int64_t{1} << 40;
    std::memcpy(&bad[at], &huge, 8);
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bad, "c.vdb", LoadOptions());
    EXPECT_FALSE(r.ok);
    EXPECT_TRUE(contains(r.error, "compressed chunk of 1099511627776 bytes") && contains(r.error, "runs past the end"))
        << r.error;
  }
}

// The fuzzer's inputs (fuzz/findings/): a negative blosc chunk size that wrote
// 26 221 bytes into a 4 688-byte buffer (heap-buffer-overflow in
// bloscFromStream), and a compressed chunk of an internal node's tile values
// that does not decode: OpenVDB throws after loading the node's child mask and
// before setting its children, and the node's destructor deleted tile values
// as child pointers (UBSan: member call on misaligned address, ~InternalNode).
TEST_F(VdbTest, FuzzFindingsAreRefused) {
  const struct {
    const char* file;
    const char* says;
  } findings[] = {{"vdb_openvdb_negative_chunk_size_overflow.vdb", "uncompressed chunk"},
                  {"vdb_openvdb_undecodable_chunk_child_mask.vdb", "corrupt"}};
  for (const auto& f : findings) {
    const std::string bytes = read_all(std::string(ATMO_FUZZ_FINDINGS_DIR "/") + f.file);
    ASSERT_GT(bytes.size(), 10000u) << f.file;
    const LoadResult r = atmo::vdb::load_vdb_from_memory(bytes, "finding.vdb", LoadOptions());
    EXPECT_FALSE(r.ok) << f.file;
    EXPECT_TRUE(contains(r.error, "finding.vdb") && contains(r.error, f.says)) << f.file << ": " << r.error;
  }
}

// fuzz_vdb: a box 2^30 voxels long and one wide searched its downsampling
// factor one step at a time (10^9 steps, a timeout); huge values summed in
// float made the downsampled densities infinite.
TEST_F(VdbTest, AThinHugeBoxDownsamplesAtOnceAndHugeDensitiesAreAnError) {
  openvdb::FloatGrid::Ptr g = float_grid("density");
  g->tree().setValue(openvdb::Coord(0, 0, -(1 << 29)), 0.5f);
  g->tree().setValue(openvdb::Coord(0, 0, (1 << 29)), 0.5f);
  LoadOptions o;
  o.max_voxels = 64;
  const LoadResult thin = atmo::vdb::load_vdb_from_memory(encodings({g})[0], "thin.vdb", o);
  ASSERT_TRUE(thin.ok) << thin.error;
  EXPECT_LE(thin.volume.density.values.size(), 64u);
  openvdb::FloatGrid::Ptr h = float_grid("density");
  for (int i = 0; i < 8; ++i) h->tree().setValue(openvdb::Coord(i, 0, 0), 3e38f);
  o.density_scale = 1e6;
  const LoadResult huge = atmo::vdb::load_vdb_from_memory(encodings({h})[0], "huge.vdb", o);
  EXPECT_FALSE(huge.ok);
  EXPECT_TRUE(contains(huge.error, "huge.vdb") && contains(huge.error, "exceed the float range")) << huge.error;
}

TEST_F(VdbTest, BadOptionsAndBadVolumesAreErrors) {
  openvdb::FloatGrid::Ptr g = float_grid("density");
  add_blob(*g, openvdb::Coord(0), 2, 1.0f);
  const std::string bytes = encodings({g})[0];
  LoadOptions o;
  o.max_voxels = 26;
  EXPECT_TRUE(contains(atmo::vdb::load_vdb_from_memory(bytes, "o.vdb", o).error, "max_voxels"));
  o = LoadOptions();
  o.metres_per_unit = 0.0;
  EXPECT_TRUE(contains(atmo::vdb::load_vdb_from_memory(bytes, "o.vdb", o).error, "metres_per_unit"));
  o = LoadOptions();
  o.density_scale = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(contains(atmo::vdb::load_vdb_from_memory(bytes, "o.vdb", o).error, "density_scale"));

  CloudVolume v = test_volume(6, 6, 6, 5);
  std::string out;
  v.rotation = glm::angleAxis(0.5, glm::dvec3(0.0, 0.0, 1.0));
  EXPECT_TRUE(contains(atmo::vdb::write_vdb_to_memory({v}, &out), "rotat"));
  v = test_volume(6, 6, 6, 5);
  v.density.at(2, 2, 2) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(contains(atmo::vdb::write_vdb_to_memory({v}, &out), "NaN"));
  EXPECT_TRUE(contains(atmo::vdb::write_vdb_to_memory({}, &out), "no volumes"));
  v = test_volume(6, 6, 6, 5);
  const std::string p = path("missing dir/out.vdb");
  const std::string e = atmo::vdb::write_vdb_file(p, {v});
  EXPECT_TRUE(contains(e, p) && contains(e, "No such file or directory")) << e;
}

}  // namespace
