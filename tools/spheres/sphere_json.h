// sphere_json.h — the sphere-set file ("atmo-spheres-1"):
//
//   {"format": "atmo-spheres-1", "mesh": "aircraft.obj", "frame": "object: m, x forward, y left, z up",
//    "spheres": [{"centre_m": [x, y, z], "radius_m": r}, ...],
//    "fit": {"spheres": 32, "mesh_volume_m3": ..., "outside_volume_m3": ..., "uncovered_volume_m3": ...,
//            "surface_distance_mean_m": ..., "surface_distance_max_m": ...}}
//
// "mesh" is the mesh's file name, beside the sphere file; "fit" (optional)
// is measure_fit's result (written to 6 significant digits). Written centres
// are rounded to 1 um and radii rounded up to the next um plus 1 um, so a
// written set still holds what it held.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sphere_fit.h"

namespace atmo::spheres {

inline constexpr const char* kSphereFormat = "atmo-spheres-1";
inline constexpr const char* kObjectFrame = "object: m, x forward, y left, z up";

struct SphereSet {
  std::string mesh;
  std::string frame = kObjectFrame;
  std::vector<Sphere> spheres;
  std::optional<FitError> fit;
};

// Throws std::invalid_argument for a sphere that is not finite or has a negative radius.
std::string sphere_set_json(const SphereSet& set);
void write_sphere_set(const SphereSet& set, const std::string& path);

// Validates the format tag, the fields' types, finite numbers and radii >= 0.
// Throws std::runtime_error naming `name` (the file) and the field, e.g.
// "spheres.json: spheres[3].radius_m: ...".
SphereSet parse_sphere_set(const std::string& text, const std::string& name);
SphereSet read_sphere_set(const std::string& path);

}  // namespace atmo::spheres
