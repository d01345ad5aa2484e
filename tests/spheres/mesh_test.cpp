// tools/spheres meshes: the procedural objects are closed and outward-facing;
// the inside test counts a ray through an edge or a vertex once and treats a
// union of shells as one solid; OBJ and PLY round trips; malformed files get
// an error naming the file and the line (or the binary element).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "mesh.h"
#include "mesh_geometry.h"

namespace sp = atmo::spheres;

namespace {

std::string temp_path(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "atmo_spheres_tests";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// The error read_mesh throws for `text` written to a file called `name`.
std::string read_error(const std::string& name, const std::string& text) {
  const std::string path = temp_path(name);
  write_text(path, text);
  try {
    sp::read_mesh(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}

// An axis-aligned box as 12 triangles (its faces split along a diagonal), outward.
sp::TriangleMesh box(const glm::dvec3& lo, const glm::dvec3& hi, sp::TriangleMesh mesh = {}) {
  const unsigned o = static_cast<unsigned>(mesh.vertices.size());
  for (int i = 0; i < 8; ++i)
    mesh.vertices.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
  const unsigned quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.triangles.emplace_back(o + q[0], o + q[1], o + q[2]);
    mesh.triangles.emplace_back(o + q[0], o + q[2], o + q[3]);
  }
  return mesh;
}

double rows_volume_m3(const sp::TriangleMesh& mesh, double y0, double z0, double step, int ny, int nz) {
  const sp::InsideRows rows = sp::inside_rows(mesh, y0, z0, step, ny, nz);
  double length = 0.0;
  for (const auto& row : rows.rows)
    for (const sp::Interval& i : row) length += i.x1_m - i.x0_m;
  return length * step * step;
}

}  // namespace

TEST(SpheresMesh, ProceduralObjectsAreClosedAndOutwardFacing) {
  struct Case {
    const char* name;
    sp::TriangleMesh mesh;
    int shells;
    glm::dvec3 size_m;
  };
  const Case cases[] = {{"aircraft", sp::make_aircraft_mesh(), 8, {36.751, 34.0, 9.5}},
                        {"vehicle", sp::make_vehicle_mesh(), 5, {5.0, 2.1, 2.2}},
                        {"building", sp::make_building_mesh(), 1, {40.0, 30.0, 12.0}}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    EXPECT_EQ(sp::closed_mesh_problem(c.mesh), "");
    EXPECT_GT(sp::signed_volume_m3(c.mesh), 0.0);
    int shells = 0;
    sp::triangle_shells(c.mesh, &shells);
    EXPECT_EQ(shells, c.shells);
    const sp::Bounds b = sp::mesh_bounds(c.mesh);
    EXPECT_NEAR(b.size_m().x, c.size_m.x, 1e-3);
    EXPECT_NEAR(b.size_m().y, c.size_m.y, 1e-3);
    EXPECT_NEAR(b.size_m().z, c.size_m.z, 1e-3);
  }
  // The vehicle's wheels and the building stand on the ground; the aircraft's
  // fuselage axis is at 4.5 m, its engines' bottoms at 2 m.
  EXPECT_DOUBLE_EQ(sp::mesh_bounds(sp::make_vehicle_mesh()).min_m.z, 0.0);
  EXPECT_DOUBLE_EQ(sp::mesh_bounds(sp::make_building_mesh()).min_m.z, 0.0);
  EXPECT_NEAR(sp::mesh_bounds(sp::make_aircraft_mesh()).min_m.z, 2.0, 1e-9);
}

TEST(SpheresMesh, ClosedMeshProblemsAreNamed) {
  sp::TriangleMesh cube = box(glm::dvec3(0.0), glm::dvec3(1.0));
  EXPECT_EQ(sp::closed_mesh_problem(cube), "");
  EXPECT_NEAR(sp::signed_volume_m3(cube), 1.0, 1e-12);

  sp::TriangleMesh flipped = cube;
  std::swap(flipped.triangles[3].y, flipped.triangles[3].z);
  EXPECT_NE(sp::closed_mesh_problem(flipped).find("same direction"), std::string::npos) << sp::closed_mesh_problem(flipped);

  sp::TriangleMesh holed = cube;
  holed.triangles.pop_back();
  EXPECT_NE(sp::closed_mesh_problem(holed).find("a hole"), std::string::npos) << sp::closed_mesh_problem(holed);

  sp::TriangleMesh inward = cube;
  for (glm::uvec3& t : inward.triangles) std::swap(t.y, t.z);
  EXPECT_NE(sp::closed_mesh_problem(inward).find("face inward"), std::string::npos) << sp::closed_mesh_problem(inward);
}

TEST(SpheresMesh, RowsThroughEdgesAndVerticesCountOnce) {
  // Rows every 0.25 m from 0 lie on the cube's faces, edges and face diagonals:
  // each must give the whole [0, 1] or nothing, and the volume comes out exact.
  const sp::TriangleMesh cube = box(glm::dvec3(0.0), glm::dvec3(1.0));
  const sp::InsideRows rows = sp::inside_rows(cube, 0.0, 0.0, 0.25, 5, 5);
  int full = 0;
  for (const auto& row : rows.rows) {
    ASSERT_LE(row.size(), 1u);
    if (row.empty()) continue;
    EXPECT_EQ(row[0].x0_m, 0.0);
    EXPECT_EQ(row[0].x1_m, 1.0);
    ++full;
  }
  EXPECT_EQ(full, 16);  // the rows on y = 1 or z = 1 are just outside
  EXPECT_DOUBLE_EQ(rows_volume_m3(cube, 0.0, 0.0, 0.25, 5, 5), 1.0);

  // The building's gable end caps are fans about a centre vertex at z = 5.6 m:
  // a ray through it crosses five triangles' corners and is counted once.
  const sp::TriangleMesh building = sp::make_building_mesh();
  EXPECT_TRUE(sp::point_inside(building, {0.0, 0.0, 5.6}));
  EXPECT_TRUE(sp::point_inside(building, {19.9, 0.0, 5.6}));
  EXPECT_FALSE(sp::point_inside(building, {20.1, 0.0, 5.6}));
  EXPECT_FALSE(sp::point_inside(building, {-20.1, 0.0, 5.6}));
  EXPECT_TRUE(sp::point_inside(building, {0.0, 0.0, 11.9}));
  EXPECT_FALSE(sp::point_inside(building, {0.0, 14.0, 8.5}));  // above the roof's slope (8.27 m there)
  // Rows in y through the walls and the ridge, in z at the cells' middles:
  // 40 x 30 x 8 + the gable's 40 x 30 x 4 / 2.
  EXPECT_NEAR(rows_volume_m3(building, -15.0, 0.125, 0.25, 121, 48), 12000.0, 0.005 * 12000.0);
}

TEST(SpheresMesh, InsideIsTheUnionOfOverlappingShells) {
  const sp::TriangleMesh two = box(glm::dvec3(1.0), glm::dvec3(3.0), box(glm::dvec3(0.0), glm::dvec3(2.0)));
  EXPECT_EQ(sp::closed_mesh_problem(two), "");
  EXPECT_TRUE(sp::point_inside(two, {1.5, 1.5, 1.5}));  // in both
  EXPECT_TRUE(sp::point_inside(two, {0.5, 0.5, 0.5}));
  EXPECT_TRUE(sp::point_inside(two, {2.5, 2.5, 2.5}));
  EXPECT_FALSE(sp::point_inside(two, {2.5, 0.5, 0.5}));
  EXPECT_NEAR(rows_volume_m3(two, 0.0, 0.0, 0.1, 31, 31), 8.0 + 8.0 - 1.0, 1e-9);

  // The aircraft: fuselage, wing root inside the fuselage, wing, engine, fin.
  const sp::TriangleMesh aircraft = sp::make_aircraft_mesh();
  EXPECT_TRUE(sp::point_inside(aircraft, {0.0, 0.0, 4.5}));
  EXPECT_TRUE(sp::point_inside(aircraft, {0.0, 1.2, 3.8}));   // wing root in the fuselage
  EXPECT_TRUE(sp::point_inside(aircraft, {-3.0, 8.0, 4.15}));  // wing
  EXPECT_TRUE(sp::point_inside(aircraft, {0.0, -5.7, 3.0}));   // engine
  EXPECT_TRUE(sp::point_inside(aircraft, {-16.0, 0.0, 9.0}));  // fin
  EXPECT_FALSE(sp::point_inside(aircraft, {0.0, 0.0, 1.0}));
  EXPECT_FALSE(sp::point_inside(aircraft, {0.0, 8.0, 6.0}));
}

TEST(SpheresMesh, ObjRoundTrip) {
  const sp::TriangleMesh mesh = sp::make_aircraft_mesh();
  const std::string path = temp_path("aircraft_round_trip.obj");
  sp::write_obj(mesh, path);
  const sp::TriangleMesh back = sp::read_mesh(path);
  ASSERT_EQ(back.vertices.size(), mesh.vertices.size());
  ASSERT_EQ(back.triangles, mesh.triangles);
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    EXPECT_LT(glm::length(back.vertices[i] - mesh.vertices[i]), 1e-7) << "vertex " << i;
  EXPECT_EQ(sp::closed_mesh_problem(back), "");
}

TEST(SpheresMesh, ObjPolygonsTexturedIndicesAndNegativeIndices) {
  // A unit cube of quads, with v/vt/vn corners and relative (negative) indices.
  const std::string text =
      "# cube\nmtllib none.mtl\no cube\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
      "vt 0 0\nvn 0 0 1\n"
      "f 1/1/1 4/1/1 3/1/1 2/1/1\nf 5//1 6//1 7//1 8//1\nf -8 -7 -3 -4\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";
  const std::string path = temp_path("cube_quads.obj");
  write_text(path, text);
  const sp::TriangleMesh mesh = sp::read_mesh(path);
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  EXPECT_EQ(sp::closed_mesh_problem(mesh), "");
  EXPECT_NEAR(sp::signed_volume_m3(mesh), 1.0, 1e-12);
}

TEST(SpheresMesh, MalformedObjNamesTheLine) {
  std::string e = read_error("bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 3\nf 1 2 9\n");
  EXPECT_NE(e.find("bad_index.obj:6: face index 9 is past the last vertex (3 vertices)"), std::string::npos) << e;
  e = read_error("missing_vertex.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_NE(e.find("missing_vertex.obj:2: vertex needs x y z"), std::string::npos) << e;
  e = read_error("bad_number.obj", "v 0 0 0\nv 1 zero 0\n");
  EXPECT_NE(e.find("bad_number.obj:2: vertex coordinate 'zero' is not a finite number"), std::string::npos) << e;
  e = read_error("short_face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n");
  EXPECT_NE(e.find("short_face.obj:4: face needs at least 3 vertices"), std::string::npos) << e;
  e = read_error("before_first.obj", "v 0 0 0\nf -1 -2 -3\n");
  EXPECT_NE(e.find("before_first.obj:2: face index -2 is before the first vertex"), std::string::npos) << e;
  e = read_error("zero_index.obj", "v 0 0 0\nf 0 1 1\n");
  EXPECT_NE(e.find("zero_index.obj:2: face index '0'"), std::string::npos) << e;
  e = read_error("no_faces.obj", "v 0 0 0\n");
  EXPECT_NE(e.find("no_faces.obj: no faces"), std::string::npos) << e;
  e = read_error("nan.obj", "v 0 0 nan\n");
  EXPECT_NE(e.find("nan.obj:1:"), std::string::npos) << e;
  try {
    sp::read_mesh(temp_path("there_is_no_such_mesh.obj"));
    ADD_FAILURE() << "no error for a missing file";
  } catch (const std::runtime_error& x) {
    EXPECT_NE(std::string(x.what()).find("there_is_no_such_mesh.obj: cannot open"), std::string::npos) << x.what();
  }
}

namespace {

const char* kAsciiCubePly =
    "ply\nformat ascii 1.0\ncomment a unit cube of quads\nelement vertex 8\nproperty float x\nproperty float y\n"
    "property float z\nproperty uchar red\nelement face 6\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0 1\n1 0 0 1\n1 1 0 1\n0 1 0 1\n0 0 1 1\n1 0 1 1\n1 1 1 1\n0 1 1 1\n"
    "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 3 7 6 2\n4 0 4 7 3\n4 1 2 6 5\n";

// The same cube, binary little-endian (float xyz, uchar count, int indices), cut to `keep` bytes of data.
std::string binary_cube_ply(size_t keep = std::string::npos) {
  std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 6\nproperty list uchar int vertex_indices\nend_header\n";
  std::string data;
  auto put = [&](const void* p, size_t n) { data.append(static_cast<const char*>(p), n); };
  for (int i = 0; i < 8; ++i) {
    const float v[3] = {static_cast<float>(i == 1 || i == 2 || i == 5 || i == 6), static_cast<float>(i == 2 || i == 3 || i == 6 || i == 7),
                        static_cast<float>(i >= 4)};
    put(v, sizeof v);  // little-endian hosts only, as the tests run
  }
  const int32_t faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
  for (const auto& f : faces) {
    const uint8_t n = 4;
    put(&n, 1);
    put(f, sizeof f);
  }
  return header + data.substr(0, keep);
}

}  // namespace

TEST(SpheresMesh, PlyAsciiAndBinary) {
  const std::string ascii = temp_path("cube_ascii.ply");
  write_text(ascii, kAsciiCubePly);
  const sp::TriangleMesh a = sp::read_mesh(ascii);
  EXPECT_EQ(a.vertices.size(), 8u);
  EXPECT_EQ(a.triangles.size(), 12u);
  EXPECT_EQ(sp::closed_mesh_problem(a), "");
  EXPECT_NEAR(sp::signed_volume_m3(a), 1.0, 1e-12);

  const std::string binary = temp_path("cube_binary.ply");
  write_text(binary, binary_cube_ply());
  const sp::TriangleMesh b = sp::read_mesh(binary);
  EXPECT_EQ(b.vertices, a.vertices);
  EXPECT_EQ(b.triangles, a.triangles);
}

TEST(SpheresMesh, MalformedPlyNamesTheLineOrElement) {
  // Binary data cut inside face 3 (8 vertices of 12 bytes, 3 faces of 17 bytes, then 6 bytes).
  std::string e = read_error("truncated.ply", binary_cube_ply(8 * 12 + 3 * 17 + 6));
  EXPECT_NE(e.find("truncated.ply: element face 3 (binary): data ends early (truncated file)"), std::string::npos) << e;
  e = read_error("truncated_vertices.ply", binary_cube_ply(5 * 12 + 4));
  EXPECT_NE(e.find("truncated_vertices.ply: element vertex 5 (binary)"), std::string::npos) << e;

  std::string text = kAsciiCubePly;
  text.replace(text.find("4 1 2 6 5"), 9, "4 1 2 6 50");
  e = read_error("bad_index.ply", text);
  EXPECT_NE(e.find("bad_index.ply:25: element face 5: vertex index 50 is past the last vertex"), std::string::npos) << e;

  text = kAsciiCubePly;
  text.replace(text.find("1 1 0 1\n"), 8, "1 1\n");
  e = read_error("missing_vertex.ply", text);
  EXPECT_NE(e.find("missing_vertex.ply:14: element vertex 2: missing or malformed value of 'z'"), std::string::npos) << e;

  text = kAsciiCubePly;
  e = read_error("short.ply", text.substr(0, text.find("4 0 1 5 4")));
  EXPECT_NE(e.find("short.ply: file ends in element face 2 of 6"), std::string::npos) << e;

  e = read_error("big_endian.ply", "ply\nformat binary_big_endian 1.0\nend_header\n");
  EXPECT_NE(e.find("big_endian.ply:2: PLY format 'binary_big_endian' is not supported"), std::string::npos) << e;
  e = read_error("no_xyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n");
  EXPECT_NE(e.find("no_xyz.ply:3: element vertex has no x, y and z"), std::string::npos) << e;
  e = read_error("no_header_end.ply", "ply\nformat ascii 1.0\n");
  EXPECT_NE(e.find("no_header_end.ply: PLY header has no end_header"), std::string::npos) << e;
}
