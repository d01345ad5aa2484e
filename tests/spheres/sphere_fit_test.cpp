// tools/spheres sphere fit: the spheres cover the mesh, more spheres leave
// less outside, the fit is deterministic per seed; measure_fit and the
// union-surface distance against geometry with known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "mesh.h"
#include "mesh_geometry.h"
#include "sphere_fit.h"

namespace sp = atmo::spheres;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Coarse options: the whole suite stays fast.
sp::FitOptions coarse(int spheres, uint64_t seed = 1) {
  sp::FitOptions o;
  o.spheres = spheres;
  o.grid = 24;
  o.surface_points = 1500;
  o.iterations = 4;
  o.seed = seed;
  return o;
}

sp::TriangleMesh cube(double half) {
  sp::TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) mesh.vertices.push_back({i & 1 ? half : -half, i & 2 ? half : -half, i & 4 ? half : -half});
  const unsigned quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.triangles.emplace_back(q[0], q[1], q[2]);
    mesh.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return mesh;
}

bool covered(const std::vector<sp::Sphere>& spheres, const glm::dvec3& p) {
  for (const sp::Sphere& s : spheres)
    if (glm::length(p - s.centre_m) <= s.radius_m) return true;
  return false;
}

}  // namespace

TEST(SpheresFit, CoversEachObject) {
  struct Case {
    const char* name;
    sp::TriangleMesh mesh;
  };
  const Case cases[] = {{"aircraft", sp::make_aircraft_mesh()},
                        {"vehicle", sp::make_vehicle_mesh()},
                        {"building", sp::make_building_mesh()}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::vector<sp::Sphere> spheres = sp::fit_spheres(c.mesh, coarse(12));
    EXPECT_EQ(spheres.size(), 12u);
    for (const sp::Sphere& s : spheres) {
      EXPECT_TRUE(std::isfinite(s.radius_m) && s.radius_m > 0.0);
      EXPECT_TRUE(std::isfinite(s.centre_m.x) && std::isfinite(s.centre_m.y) && std::isfinite(s.centre_m.z));
    }
    for (size_t i = 0; i < c.mesh.vertices.size(); ++i)
      EXPECT_TRUE(covered(spheres, c.mesh.vertices[i])) << "vertex " << i;
    const sp::FitError e = sp::measure_fit(c.mesh, spheres, 96);
    EXPECT_GT(e.mesh_volume_m3, 0.0);
    EXPECT_LT(e.uncovered_volume_m3, 0.005 * e.mesh_volume_m3);
    EXPECT_GT(e.outside_volume_m3, 0.0);
    EXPECT_GE(e.surface_distance_max_m, e.surface_distance_mean_m);
    // Fresh surface points (not the fit's samples) are all but all inside.
    const std::vector<glm::dvec3> fresh = sp::sample_surface(c.mesh, 4000, 12345);
    int outside = 0;
    for (const glm::dvec3& p : fresh) outside += !covered(spheres, p);
    EXPECT_LT(outside, 40) << outside << " of 4000 fresh surface points outside the spheres";
  }
}

TEST(SpheresFit, MoreSpheresLeaveLessOutsideTheAircraft) {
  const sp::TriangleMesh aircraft = sp::make_aircraft_mesh();
  const sp::FitError four = sp::measure_fit(aircraft, sp::fit_spheres(aircraft, coarse(4)), 96);
  const sp::FitError many = sp::measure_fit(aircraft, sp::fit_spheres(aircraft, coarse(32)), 96);
  EXPECT_LT(many.outside_volume_m3, 0.5 * four.outside_volume_m3)
      << "K=4: " << four.outside_volume_m3 << " m^3, K=32: " << many.outside_volume_m3 << " m^3";
  EXPECT_LT(many.surface_distance_mean_m, four.surface_distance_mean_m);
  EXPECT_LT(many.uncovered_volume_m3, 0.005 * many.mesh_volume_m3);
  EXPECT_LT(four.uncovered_volume_m3, 0.005 * four.mesh_volume_m3);
}

TEST(SpheresFit, SameSeedSameSpheres) {
  const sp::TriangleMesh vehicle = sp::make_vehicle_mesh();
  const std::vector<sp::Sphere> a = sp::fit_spheres(vehicle, coarse(8, 7));
  const std::vector<sp::Sphere> b = sp::fit_spheres(vehicle, coarse(8, 7));
  const std::vector<sp::Sphere> c = sp::fit_spheres(vehicle, coarse(8, 8));
  ASSERT_EQ(a.size(), b.size());
  bool all_same_as_c = a.size() == c.size();
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].centre_m, b[i].centre_m) << "sphere " << i;
    EXPECT_EQ(a[i].radius_m, b[i].radius_m) << "sphere " << i;
    if (all_same_as_c) all_same_as_c = a[i].centre_m == c[i].centre_m && a[i].radius_m == c[i].radius_m;
  }
  EXPECT_FALSE(all_same_as_c) << "another seed gave the very same spheres";
}

TEST(SpheresFit, ProgressAndBadOptions) {
  int lines = 0;
  sp::FitOptions o = coarse(4);
  o.progress = [&](const std::string& line) {
    ++lines;
    EXPECT_EQ(line.find('\n'), std::string::npos);
  };
  sp::fit_spheres(sp::make_building_mesh(), o);
  EXPECT_GE(lines, o.iterations + 2);
  o.spheres = 0;
  EXPECT_THROW(sp::fit_spheres(sp::make_building_mesh(), o), std::invalid_argument);
  o.spheres = 1025;
  EXPECT_THROW(sp::fit_spheres(sp::make_building_mesh(), o), std::invalid_argument);
  o.spheres = 4;
  o.grid = 2;
  EXPECT_THROW(sp::fit_spheres(sp::make_building_mesh(), o), std::invalid_argument);
}

TEST(SpheresFit, OneSphereAroundACube) {
  // A 2 m cube: its circumscribed sphere is the best single sphere.
  const sp::TriangleMesh c = cube(1.0);
  sp::FitOptions o = coarse(1);
  const std::vector<sp::Sphere> one = sp::fit_spheres(c, o);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_LT(glm::length(one[0].centre_m), 0.05);
  EXPECT_NEAR(one[0].radius_m, std::sqrt(3.0), 0.05);
}

TEST(SpheresFit, MeasureAgainstKnownVolumes) {
  const sp::TriangleMesh c = cube(1.0);
  // Circumscribed sphere: nothing uncovered; outside = sphere - cube; the
  // surface is farthest from the sphere at the faces' centres (sqrt(3) - 1).
  const double r = std::sqrt(3.0);
  sp::FitError e = sp::measure_fit(c, {{glm::dvec3(0.0), r}}, 128);
  EXPECT_NEAR(e.mesh_volume_m3, 8.0, 1e-9);
  EXPECT_NEAR(e.outside_volume_m3, 4.0 / 3.0 * kPi * r * r * r - 8.0, 0.01 * 13.77);
  EXPECT_LT(e.uncovered_volume_m3, 1e-9);
  EXPECT_LE(e.surface_distance_max_m, r - 1.0 + 1e-9);
  EXPECT_GT(e.surface_distance_max_m, r - 1.0 - 0.02);
  // Inscribed sphere: nothing outside; uncovered = cube - sphere; the corners are sqrt(3) - 1 away.
  e = sp::measure_fit(c, {{glm::dvec3(0.0), 1.0}}, 128);
  EXPECT_NEAR(e.uncovered_volume_m3, 8.0 - 4.0 / 3.0 * kPi, 0.01 * 3.81);
  EXPECT_LT(e.outside_volume_m3, 1e-9);
  EXPECT_LT(e.surface_distance_mean_m, r - 1.0);
}

TEST(SpheresFit, UnionSurfaceDistanceIsExact) {
  // Two spheres meeting in a circle of radius sqrt(1.25) in the plane x = 0.
  const std::vector<sp::Sphere> two = {{{-1.0, 0.0, 0.0}, 1.5}, {{1.0, 0.0, 0.0}, 1.5}};
  EXPECT_NEAR(sp::union_surface_distance_m(two, {0.0, 0.0, 0.0}), std::sqrt(1.25), 1e-12);  // on the circle's axis
  EXPECT_NEAR(sp::union_surface_distance_m(two, {0.0, 0.0, 0.1}), std::sqrt(1.25) - 0.1, 1e-12);
  EXPECT_NEAR(sp::union_surface_distance_m(two, {-1.2, 0.0, 0.0}), 1.3, 1e-12);  // a sphere's own surface
  EXPECT_NEAR(sp::union_surface_distance_m(two, {3.0, 0.0, 0.0}), 0.5, 1e-12);   // outside
  // Three spheres about the origin: their radial points and circles' nearest
  // points are covered, so the nearest surface points are where all three meet.
  const std::vector<sp::Sphere> three = {{{1.0, 0.0, 0.0}, 1.2},
                                         {{-0.5, std::sqrt(0.75), 0.0}, 1.2},
                                         {{-0.5, -std::sqrt(0.75), 0.0}, 1.2}};
  EXPECT_NEAR(sp::union_surface_distance_m(three, glm::dvec3(0.0)), std::sqrt(1.44 - 1.0), 1e-9);
}
