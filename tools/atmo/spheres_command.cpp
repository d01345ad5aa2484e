#include "spheres_command.h"

#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>

#include "mesh.h"
#include "mesh_geometry.h"
#include "sphere_fit.h"
#include "sphere_json.h"

namespace atmo::spheres_cli {

namespace sp = atmo::spheres;

namespace {

int fail(const std::string& message) {
  std::fprintf(stderr, "atmo spheres: %s\n", message.c_str());
  return 1;
}

// 4 significant digits, without an exponent for the large ones.
std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, std::fabs(v) >= 1000.0 ? "%.0f" : "%.4g", v);
  return buf;
}

int make_mesh(const Options& options) {
  sp::TriangleMesh mesh;
  if (options.make == "aircraft") mesh = sp::make_aircraft_mesh();
  else if (options.make == "vehicle") mesh = sp::make_vehicle_mesh();
  else mesh = sp::make_building_mesh();  // main.cpp only lets these three through
  sp::write_obj(mesh, options.out_path);
  int shells = 0;
  sp::triangle_shells(mesh, &shells);
  const sp::Bounds b = mesh.vertices.empty() ? sp::Bounds{} : sp::mesh_bounds(mesh);
  const glm::dvec3 size = b.size_m();
  std::printf("wrote %s: %s, %zu vertices, %zu triangles, %d closed shells, %.2f x %.2f x %.2f m\n",
              options.out_path.c_str(), options.make.c_str(), mesh.vertices.size(), mesh.triangles.size(), shells,
              size.x, size.y, size.z);
  return 0;
}

}  // namespace

int run_spheres(const Options& options) {
  try {
    if (!options.make.empty()) return make_mesh(options);

    const sp::TriangleMesh mesh = sp::read_mesh(options.mesh_path);
    const std::string problem = sp::closed_mesh_problem(mesh);
    if (!problem.empty())  // the fit still bounds it, but "inside" is what its winding says
      std::fprintf(stderr, "atmo spheres: warning: %s: %s\n", options.mesh_path.c_str(), problem.c_str());
    std::fprintf(stderr, "atmo spheres: %s: %zu vertices, %zu triangles\n", options.mesh_path.c_str(),
                 mesh.vertices.size(), mesh.triangles.size());

    sp::FitOptions fit;
    fit.spheres = options.spheres;
    fit.grid = options.grid;
    fit.seed = options.seed;
    fit.progress = [](const std::string& line) {
      std::fprintf(stderr, "atmo spheres: %s\n", line.c_str());
      std::fflush(stderr);
    };
    const std::vector<sp::Sphere> spheres = sp::fit_spheres(mesh, fit);
    const sp::FitError e = sp::measure_fit(mesh, spheres, options.measure_grid);

    const double size = sp::mesh_bounds(mesh).longest_side_m();
    const double v = e.mesh_volume_m3 > 0.0 ? e.mesh_volume_m3 : 1.0;
    std::printf("%zu spheres for %s (longest side %.3g m, volume %s m^3; measured on %d rows along it)\n",
                spheres.size(), options.mesh_path.c_str(), size, number(e.mesh_volume_m3).c_str(), options.measure_grid);
    std::printf("outside volume   %10s m^3  (%.1f %% of the mesh volume)\n", number(e.outside_volume_m3).c_str(),
                100.0 * e.outside_volume_m3 / v);
    std::printf("uncovered volume %10s m^3  (%.4f %% of the mesh volume)\n", number(e.uncovered_volume_m3).c_str(),
                100.0 * e.uncovered_volume_m3 / v);
    std::printf("surface distance mean %.3g m (%.2f %% of the longest side), max %.3g m (%.2f %%)\n",
                e.surface_distance_mean_m, 100.0 * e.surface_distance_mean_m / size, e.surface_distance_max_m,
                100.0 * e.surface_distance_max_m / size);

    sp::SphereSet set;
    set.mesh = std::filesystem::path(options.mesh_path).filename().string();
    set.spheres = spheres;
    set.fit = e;
    sp::write_sphere_set(set, options.out_path);
    std::printf("wrote %s\n", options.out_path.c_str());
    return 0;
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}

}  // namespace atmo::spheres_cli
