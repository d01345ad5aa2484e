// tools/spheres sphere-set JSON (atmo-spheres-1): round trip, errors naming
// the file and the sphere index / field; and the shipped data/objects files:
// the meshes are the procedural ones, the sphere sets parse and cover them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "mesh.h"
#include "mesh_geometry.h"
#include "sphere_fit.h"
#include "sphere_json.h"

namespace sp = atmo::spheres;

namespace {

std::string parse_error(const std::string& text, const std::string& name = "set.json") {
  try {
    sp::parse_sphere_set(text, name);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}

std::string with_spheres(const std::string& spheres) {
  return R"({"format": "atmo-spheres-1", "mesh": "m.obj", "frame": "object: m, x forward, y left, z up", "spheres": )" +
         spheres + "}";
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(SpheresJson, RoundTrip) {
  sp::SphereSet set;
  set.mesh = "aircraft.obj";
  set.spheres = {{{1.2345678901, -2.5, 4.25}, 3.0000004}, {{0.0, 0.0, 0.0}, 0.0}, {{-17.0, 16.9999999, 1e-7}, 12.5}};
  sp::FitError f;
  f.mesh_volume_m3 = 400.25;
  f.outside_volume_m3 = 934.5;
  f.uncovered_volume_m3 = 0.0413;
  f.surface_distance_mean_m = 0.823;
  f.surface_distance_max_m = 2.48;
  set.fit = f;
  const std::string text = sp::sphere_set_json(set);
  const sp::SphereSet back = sp::parse_sphere_set(text, "round_trip.json");
  EXPECT_EQ(back.mesh, "aircraft.obj");
  EXPECT_EQ(back.frame, sp::kObjectFrame);
  ASSERT_EQ(back.spheres.size(), set.spheres.size());
  for (size_t i = 0; i < set.spheres.size(); ++i) {
    // Centres to 1 um; the radius grows by 1-2 um, so the written sphere holds the original.
    EXPECT_LE(glm::length(back.spheres[i].centre_m - set.spheres[i].centre_m), 0.87e-6) << i;
    EXPECT_GE(back.spheres[i].radius_m,
              set.spheres[i].radius_m + glm::length(back.spheres[i].centre_m - set.spheres[i].centre_m)) << i;
    EXPECT_LE(back.spheres[i].radius_m, set.spheres[i].radius_m + 2.01e-6) << i;
  }
  ASSERT_TRUE(back.fit.has_value());
  EXPECT_EQ(back.fit->mesh_volume_m3, f.mesh_volume_m3);
  EXPECT_EQ(back.fit->outside_volume_m3, f.outside_volume_m3);
  EXPECT_EQ(back.fit->uncovered_volume_m3, f.uncovered_volume_m3);
  EXPECT_EQ(back.fit->surface_distance_mean_m, f.surface_distance_mean_m);
  EXPECT_EQ(back.fit->surface_distance_max_m, f.surface_distance_max_m);
  // A second trip keeps the centres (already on the um grid); the radii grow again, by design.
  const sp::SphereSet again = sp::parse_sphere_set(sp::sphere_set_json(back), "again.json");
  for (size_t i = 0; i < set.spheres.size(); ++i) EXPECT_EQ(again.spheres[i].centre_m, back.spheres[i].centre_m);

  // Through a file, and without "fit".
  set.fit.reset();
  const std::string path = (std::filesystem::temp_directory_path() / "atmo_spheres_round_trip.json").string();
  sp::write_sphere_set(set, path);
  const sp::SphereSet file = sp::read_sphere_set(path);
  EXPECT_EQ(file.spheres.size(), 3u);
  EXPECT_FALSE(file.fit.has_value());
}

TEST(SpheresJson, ErrorsNameTheFileAndTheField) {
  auto expect_error = [](const std::string& text, const std::string& expected) {
    const std::string e = parse_error(text);
    EXPECT_NE(e.find(expected), std::string::npos) << "got: " << e << "\nexpected: " << expected;
  };
  expect_error("{", "set.json: not JSON");
  expect_error("[]", "set.json: expected a JSON object");
  expect_error(R"({"format": "atmo-spheres-2", "mesh": "m.obj", "frame": "", "spheres": []})",
               "set.json: format: expected \"atmo-spheres-1\", got \"atmo-spheres-2\"");
  expect_error(R"({"mesh": "m.obj", "frame": "", "spheres": []})", "set.json: format: missing");
  expect_error(R"({"format": "atmo-spheres-1", "mesh": 3, "frame": "", "spheres": []})",
               "set.json: mesh: expected a string");
  expect_error(with_spheres("{}"), "set.json: spheres: expected an array");
  expect_error(with_spheres(R"([{"centre_m": [0, 0, 0], "radius_m": 1}, {"centre_m": [0, 0, 0], "radius_m": 1},
                                {"centre_m": [0, 0, 0], "radius_m": -1}])"),
               "set.json: spheres[2].radius_m: expected a radius >= 0, got -1");
  expect_error(with_spheres(R"([{"centre_m": [0, 0, 0], "radius_m": 1}, {"centre_m": [0, 0], "radius_m": 1}])"),
               "set.json: spheres[1].centre_m: expected [x, y, z], got [0,0]");
  expect_error(with_spheres(R"([{"centre_m": [0, "1", 0], "radius_m": 1}])"),
               "set.json: spheres[0].centre_m[1]: expected a number, got \"1\"");
  expect_error(with_spheres(R"([{"centre_m": [0, 0, 0]}])"), "set.json: spheres[0].radius_m: missing");
  expect_error(with_spheres(R"([{"centre_m": [0, 0, 0], "radius_m": 1e999}])"), "set.json: not JSON: ");
  expect_error(with_spheres(R"([{"centre_m": [0, 0, 0], "radius_m": 1e999}])"), "overflow parsing '1e999'");
  expect_error(with_spheres(R"([{"centre_m": [0, 0, 0], "radius_m": 1}, 5])"), "set.json: spheres[1]: expected an object");
  std::string text = with_spheres(R"([{"centre_m": [0, 0, 0], "radius_m": 1}])");
  text.insert(text.size() - 1, R"(, "fit": {"spheres": 2})");
  expect_error(text, "set.json: fit.spheres: expected the number of spheres (1), got 2");
  text = with_spheres(R"([{"centre_m": [0, 0, 0], "radius_m": 1}])");
  text.insert(text.size() - 1, R"(, "fit": {"spheres": 1, "mesh_volume_m3": 1, "outside_volume_m3": 1,
      "uncovered_volume_m3": -1, "surface_distance_mean_m": 0, "surface_distance_max_m": 0})");
  expect_error(text, "set.json: fit.uncovered_volume_m3: expected a value >= 0");

  try {
    sp::read_sphere_set("/nonexistent/atmo/no_such_spheres.json");
    ADD_FAILURE() << "no error for a missing file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_spheres.json: cannot open"), std::string::npos) << e.what();
  }
}

TEST(SpheresJson, ShippedObjectsAreTheProceduralMeshesAndTheirSpheresCoverThem) {
  const std::filesystem::path dir = std::filesystem::path(ATMO_SOURCE_DIR) / "data" / "objects";
  struct Case {
    const char* name;
    sp::TriangleMesh mesh;
    size_t spheres;
  };
  const Case cases[] = {{"aircraft", sp::make_aircraft_mesh(), 32},
                        {"vehicle", sp::make_vehicle_mesh(), 16},
                        {"building", sp::make_building_mesh(), 32}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    // The shipped OBJ is what `atmo spheres --make` writes today.
    const std::string regenerated = (std::filesystem::temp_directory_path() / (std::string(c.name) + "_regenerated.obj")).string();
    sp::write_obj(c.mesh, regenerated);
    const std::string shipped_obj = (dir / (std::string(c.name) + ".obj")).string();
    EXPECT_TRUE(read_text(shipped_obj) == read_text(regenerated))
        << shipped_obj << " differs from the procedural mesh (data/objects/README.md: how to regenerate it)";

    const sp::SphereSet set = sp::read_sphere_set((dir / (std::string(c.name) + ".spheres.json")).string());
    EXPECT_EQ(set.mesh, std::string(c.name) + ".obj");
    ASSERT_EQ(set.spheres.size(), c.spheres);
    ASSERT_TRUE(set.fit.has_value());
    const sp::TriangleMesh mesh = sp::read_mesh(shipped_obj);
    const sp::FitError e = sp::measure_fit(mesh, set.spheres, 256);
    EXPECT_LT(e.uncovered_volume_m3, 0.005 * e.mesh_volume_m3);
    // The recorded fit agrees with a coarser measurement of the same spheres.
    EXPECT_NEAR(e.mesh_volume_m3, set.fit->mesh_volume_m3, 0.02 * set.fit->mesh_volume_m3);
    EXPECT_NEAR(e.outside_volume_m3, set.fit->outside_volume_m3, 0.02 * set.fit->outside_volume_m3);
  }
}
