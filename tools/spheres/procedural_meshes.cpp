// procedural_meshes.cpp — the test objects, each a union of closed convex
// shells built as lofts: rings of points joined band by band, the end rings
// closed by a fan (or a single point, a pole).
#include <algorithm>
#include <cmath>

#include "mesh.h"
#include "mesh_geometry.h"

namespace atmo::spheres {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

using Ring = std::vector<glm::dvec3>;

// Joins consecutive rings (all of one size n >= 3, or a single point: a pole)
// into one closed shell, and turns it outward if it came out inward.
void add_loft(TriangleMesh& mesh, const std::vector<Ring>& rings) {
  const size_t first_vertex = mesh.vertices.size();
  const size_t first_triangle = mesh.triangles.size();
  std::vector<std::vector<unsigned>> index(rings.size());
  for (size_t r = 0; r < rings.size(); ++r)
    for (const glm::dvec3& p : rings[r]) {
      index[r].push_back(static_cast<unsigned>(mesh.vertices.size()));
      mesh.vertices.push_back(p);
    }
  auto at = [&](size_t r, size_t i) { return index[r][index[r].size() == 1 ? 0 : i % index[r].size()]; };
  size_t n = 0;
  for (const Ring& ring : rings) n = std::max(n, ring.size());
  auto add = [&](unsigned a, unsigned b, unsigned c) {
    if (a != b && b != c && c != a) mesh.triangles.emplace_back(a, b, c);
  };
  for (size_t r = 0; r + 1 < rings.size(); ++r)
    for (size_t i = 0; i < n; ++i) {
      add(at(r, i), at(r, i + 1), at(r + 1, i + 1));
      add(at(r, i), at(r + 1, i + 1), at(r + 1, i));
    }
  // Flat end caps: a fan around the ring's centroid (which lies in its plane).
  auto cap = [&](size_t r, bool start) {
    if (rings[r].size() == 1) return;
    glm::dvec3 centre(0.0);
    for (const glm::dvec3& p : rings[r]) centre += p;
    centre /= static_cast<double>(rings[r].size());
    const unsigned c = static_cast<unsigned>(mesh.vertices.size());
    mesh.vertices.push_back(centre);
    for (size_t i = 0; i < n; ++i) {
      if (start) add(c, at(r, i + 1), at(r, i));
      else add(c, at(r, i), at(r, i + 1));
    }
  };
  cap(0, true);
  cap(rings.size() - 1, false);

  TriangleMesh shell;
  shell.vertices.assign(mesh.vertices.begin() + static_cast<long>(first_vertex), mesh.vertices.end());
  for (size_t t = first_triangle; t < mesh.triangles.size(); ++t)
    shell.triangles.push_back(mesh.triangles[t] - glm::uvec3(static_cast<unsigned>(first_vertex)));
  if (signed_volume_m3(shell) < 0.0)
    for (size_t t = first_triangle; t < mesh.triangles.size(); ++t) std::swap(mesh.triangles[t].y, mesh.triangles[t].z);
}

// A solid of revolution about the line through `origin` along `axis`, with
// radius profile (s along the axis, r) sampled at `around` angles. r = 0 at
// an end makes a pole. A profile concave in s gives a convex solid.
void add_revolution(TriangleMesh& mesh, const glm::dvec3& origin, const glm::dvec3& axis, const glm::dvec3& up,
                    const std::vector<glm::dvec2>& profile, int around) {
  const glm::dvec3 a = glm::normalize(axis);
  const glm::dvec3 u = glm::normalize(up - glm::dot(up, a) * a);
  const glm::dvec3 v = glm::cross(a, u);
  std::vector<Ring> rings;
  for (const glm::dvec2& sr : profile) {
    const glm::dvec3 centre = origin + sr.x * a;
    if (sr.y <= 0.0) {
      rings.push_back({centre});
      continue;
    }
    Ring ring;
    for (int i = 0; i < around; ++i) {
      const double phi = 2.0 * kPi * i / around;
      ring.push_back(centre + sr.y * (std::cos(phi) * u + std::sin(phi) * v));
    }
    rings.push_back(ring);
  }
  add_loft(mesh, rings);
}

// An airfoil-like convex hexagon, chord 1 and thickness `t`, leading edge at
// the origin, the chord along -u (aft), the thickness along w.
std::vector<glm::dvec2> hexagon_section(double t) {
  return {{0.0, 0.0}, {0.2, 0.5 * t}, {0.6, 0.5 * t}, {1.0, 0.0}, {0.6, -0.5 * t}, {0.2, -0.5 * t}};
}

// A lifting surface lofted from a root section to a tip section: the same
// hexagon scaled by each chord (uniformly, so the side faces are planar and
// the shell convex). `le_root`, `le_tip`: leading-edge points; `aft`: the
// chord direction; `thick`: the thickness direction.
void add_surface(TriangleMesh& mesh, const glm::dvec3& le_root, double chord_root, const glm::dvec3& le_tip,
                 double chord_tip, double thickness_ratio, const glm::dvec3& aft, const glm::dvec3& thick) {
  const std::vector<glm::dvec2> section = hexagon_section(thickness_ratio);
  Ring root, tip;
  for (const glm::dvec2& p : section) {
    root.push_back(le_root + chord_root * (p.x * aft + p.y * thick));
    tip.push_back(le_tip + chord_tip * (p.x * aft + p.y * thick));
  }
  add_loft(mesh, {root, tip});
}

// A prism: a convex polygon in the plane through `origin` spanned by (u, w),
// extruded along `length_axis` over [s0, s1].
void add_prism(TriangleMesh& mesh, const glm::dvec3& origin, const glm::dvec3& u, const glm::dvec3& w,
               const glm::dvec3& length_axis, double s0, double s1, const std::vector<glm::dvec2>& polygon) {
  Ring a, b;
  for (const glm::dvec2& p : polygon) {
    a.push_back(origin + p.x * u + p.y * w + s0 * length_axis);
    b.push_back(origin + p.x * u + p.y * w + s1 * length_axis);
  }
  add_loft(mesh, {a, b});
}

const glm::dvec3 kX(1, 0, 0), kY(0, 1, 0), kZ(0, 0, 1);

}  // namespace

TriangleMesh make_aircraft_mesh() {
  TriangleMesh mesh;
  const int around = 24;

  // Fuselage: 36 m, 4 m across, axis at 4.5 m; an ellipsoidal nose (x 12..18),
  // a cylinder, a cone tapering to 0.5 m at the tail (x -18). The profile is
  // concave, so the shell is convex.
  const double axis_z = 4.5, radius = 2.0;
  std::vector<glm::dvec2> fuselage;
  fuselage.push_back({-18.0, 0.5});
  for (int i = 1; i <= 4; ++i) fuselage.push_back({-18.0 + 3.0 * i, 0.5 + (radius - 0.5) * i / 4.0});
  for (double x : {0.0, 6.0, 12.0}) fuselage.push_back({x, radius});
  for (int i = 1; i < 8; ++i) {
    const double angle = 0.5 * kPi * i / 8.0;
    fuselage.push_back({12.0 + 6.0 * std::sin(angle), radius * std::cos(angle)});
  }
  fuselage.push_back({18.0, 0.0});
  add_revolution(mesh, {0.0, 0.0, axis_z}, kX, kZ, fuselage, around);

  // Wings: 34 m span, 25 deg leading-edge sweep, 3 deg dihedral, root chord 7 m
  // and 0.5 m thick (7 %) inside the fuselage at y = +-1, tip chord 2 m at y = +-17.
  const double sweep = 25.0 * kDeg, dihedral = 3.0 * kDeg;
  for (double side : {1.0, -1.0}) {
    const glm::dvec3 le_root(3.0, side * 1.0, 3.8);
    const double half_span = 16.0;
    const glm::dvec3 le_tip = le_root + glm::dvec3(-half_span * std::tan(sweep), side * half_span,
                                                    half_span * std::tan(dihedral));
    add_surface(mesh, le_root, 7.0, le_tip, 2.0, 0.5 / 7.0, -kX, kZ);
  }

  // Engines under the wings at y = +-5.7 (the nacelle's top cuts into the wing's
  // underside): 4.5 m long, 2 m across, intake closed by a flat cap.
  for (double side : {1.0, -1.0}) {
    const std::vector<glm::dvec2> nacelle = {{0.0, 0.85}, {0.4, 1.0}, {2.5, 1.0}, {4.5, 0.6}};
    add_revolution(mesh, {2.3, side * 5.7, 3.0}, -kX, kZ, nacelle, around);
  }

  // Tailplane: 12 m span, 30 deg sweep, root chord 3.5 m inside the tail cone.
  for (double side : {1.0, -1.0}) {
    const glm::dvec3 le_root(-13.0, side * 0.5, 4.8);
    const double half_span = 5.5;
    const glm::dvec3 le_tip =
        le_root + glm::dvec3(-half_span * std::tan(30.0 * kDeg), side * half_span, half_span * std::tan(3.0 * kDeg));
    add_surface(mesh, le_root, 3.5, le_tip, 1.5, 0.3 / 3.5, -kX, kZ);
  }

  // Fin: root chord 5 m from z = 5 (inside the fuselage) to its tip at 11.5 m, 35 deg sweep.
  {
    const glm::dvec3 le_root(-12.0, 0.0, 5.0);
    const double height = 6.5;
    const glm::dvec3 le_tip = le_root + glm::dvec3(-height * std::tan(35.0 * kDeg), 0.0, height);
    add_surface(mesh, le_root, 5.0, le_tip, 2.2, 0.35 / 5.0, -kX, kY);
  }
  return mesh;
}

TriangleMesh make_vehicle_mesh() {
  TriangleMesh mesh;
  // Body: 5 m long (x -2.5..2.5), 2 m wide, from 0.3 m to 2.2 m, the front's
  // top edge bevelled into a windscreen slope; the side profile is convex.
  const std::vector<glm::dvec2> profile = {{-2.5, 0.3}, {2.5, 0.3}, {2.5, 1.2}, {1.7, 2.2}, {-2.5, 2.2}};
  add_prism(mesh, glm::dvec3(0.0), kX, kZ, kY, -1.0, 1.0, profile);
  // Wheels: 0.7 m across, 0.25 m wide, touching z = 0, their inner halves in the body.
  for (double x : {1.7, -1.7})
    for (double side : {1.0, -1.0}) {
      const std::vector<glm::dvec2> wheel = {{0.0, 0.35}, {0.25, 0.35}};
      add_revolution(mesh, {x, side * 0.8, 0.35}, side * kY, kZ, wheel, 16);
    }
  return mesh;
}

TriangleMesh make_building_mesh() {
  TriangleMesh mesh;
  // Hangar: 40 m (x) by 30 m (y), walls 8 m, a gabled roof along x with its ridge at 12 m.
  const std::vector<glm::dvec2> gable = {{-15.0, 0.0}, {15.0, 0.0}, {15.0, 8.0}, {0.0, 12.0}, {-15.0, 8.0}};
  add_prism(mesh, glm::dvec3(0.0), kY, kZ, kX, -20.0, 20.0, gable);
  return mesh;
}

}  // namespace atmo::spheres
