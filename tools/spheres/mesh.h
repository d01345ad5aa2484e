// mesh.h — a closed triangle mesh (the host's object, before it is fitted
// with spheres), read from OBJ or PLY, and the procedural test objects.
// Object frame: metres, x forward, y left, z up, the object standing on z = 0.
#pragma once

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace atmo::spheres {

struct TriangleMesh {
  std::vector<glm::dvec3> vertices;    // m, object frame
  std::vector<glm::uvec3> triangles;   // counter-clockwise seen from outside (outward normals)
};

// Reads a Wavefront OBJ (v and f lines; polygons fanned into triangles; v/vt/vn
// and negative indices accepted) or a PLY (ascii or binary_little_endian;
// vertex x y z, face vertex_indices). Throws std::runtime_error naming the file
// and the line or element that is wrong.
TriangleMesh read_mesh(const std::string& path);
void write_obj(const TriangleMesh& mesh, const std::string& path);

// The procedural objects the tests, scenario and sample host use (closed,
// outward-facing): an airliner-like aircraft (~36 m long, 34 m span, fuselage,
// wings at ~4 m above the ground, tailplane, fin, two engines under the wings),
// a van-like vehicle (~5 x 2 x 2.2 m) and a hangar-like building (~40 x 30 x 12 m).
// The aircraft and the vehicle are unions of overlapping closed convex shells
// (fuselage, wings, ...) in one mesh: each shell is closed and outward-facing,
// the shells intersect one another, and "inside the mesh" means inside any
// shell (mesh_geometry.h's inside test treats the union so). The aircraft's
// gear is left out (too thin to matter for sky shadows): it floats, its
// lowest point the engines' at ~2 m.
TriangleMesh make_aircraft_mesh();
TriangleMesh make_vehicle_mesh();
TriangleMesh make_building_mesh();

}  // namespace atmo::spheres
