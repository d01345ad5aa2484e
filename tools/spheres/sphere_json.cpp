#include "sphere_json.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace atmo::spheres {

namespace {

using Json = nlohmann::ordered_json;

constexpr double kMicrometre = 1e-6;

[[noreturn]] void fail(const std::string& name, const std::string& field, const std::string& what) {
  throw std::runtime_error(name + ": " + field + ": " + what);
}

std::string describe(const Json& j) {
  std::string text = j.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return text;
}

double finite_number(const Json& j, const std::string& name, const std::string& field) {
  if (!j.is_number()) fail(name, field, "expected a number, got " + describe(j));
  const double v = j.get<double>();
  if (!std::isfinite(v)) fail(name, field, "expected a finite number, got " + describe(j));
  return v;
}

const Json& member(const Json& object, const char* key, const std::string& name, const std::string& field) {
  const auto it = object.find(key);
  if (it == object.end()) fail(name, field, "missing");
  return *it;
}

std::string text_member(const Json& object, const char* key, const std::string& name) {
  const Json& j = member(object, key, name, key);
  if (!j.is_string()) fail(name, key, "expected a string, got " + describe(j));
  return j.get<std::string>();
}

// Numbers are printed here rather than by the JSON library, whose shortest
// form is not always the shortest: micrometres as fixed decimals, the fit's
// measurements to 6 significant digits.
std::string micrometres(long long um) {
  const char* sign = um < 0 ? "-" : "";
  const unsigned long long a = static_cast<unsigned long long>(um < 0 ? -um : um);
  char buf[48];
  std::snprintf(buf, sizeof buf, "%s%llu.%06llu", sign, a / 1000000ull, a % 1000000ull);
  std::string text = buf;
  while (text.back() == '0') text.pop_back();
  if (text.back() == '.') text.pop_back();
  return text == "-0" ? "0" : text;
}

std::string significant(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

std::string sphere_set_json(const SphereSet& set) {
  // One sphere a line: readable, and diffs show which sphere moved.
  std::ostringstream out;
  out << "{\n  \"format\": " << Json(kSphereFormat).dump() << ",\n  \"mesh\": " << Json(set.mesh).dump()
      << ",\n  \"frame\": " << Json(set.frame).dump() << ",\n  \"spheres\": [";
  for (size_t i = 0; i < set.spheres.size(); ++i) {
    const Sphere& s = set.spheres[i];
    const bool sane = std::fabs(s.centre_m.x) < 1e9 && std::fabs(s.centre_m.y) < 1e9 && std::fabs(s.centre_m.z) < 1e9 &&
                      s.radius_m >= 0.0 && s.radius_m < 1e9;  // also false for NaN
    if (!sane) throw std::invalid_argument("sphere " + std::to_string(i) + ": not a finite sphere of radius >= 0 within 1e9 m");
    // Centres to the nearest um; the radius up to the next um plus 1 um covers
    // the centre's shift (at most sqrt(3)/2 um).
    const glm::dvec3 c = glm::round(s.centre_m / kMicrometre);
    const double r = std::ceil(s.radius_m / kMicrometre) + 1.0;
    out << (i ? ",\n    " : "\n    ") << "{\"centre_m\": [" << micrometres(static_cast<long long>(c.x)) << ", "
        << micrometres(static_cast<long long>(c.y)) << ", " << micrometres(static_cast<long long>(c.z))
        << "], \"radius_m\": " << micrometres(static_cast<long long>(r)) << "}";
  }
  out << (set.spheres.empty() ? "]" : "\n  ]");
  if (set.fit) {
    const FitError& f = *set.fit;
    for (double v : {f.mesh_volume_m3, f.outside_volume_m3, f.uncovered_volume_m3, f.surface_distance_mean_m,
                     f.surface_distance_max_m})
      if (!std::isfinite(v)) throw std::invalid_argument("fit: a measurement is not finite");
    out << ",\n  \"fit\": {\"spheres\": " << set.spheres.size()
        << ", \"mesh_volume_m3\": " << significant(f.mesh_volume_m3)
        << ", \"outside_volume_m3\": " << significant(f.outside_volume_m3)
        << ", \"uncovered_volume_m3\": " << significant(f.uncovered_volume_m3)
        << ",\n          \"surface_distance_mean_m\": " << significant(f.surface_distance_mean_m)
        << ", \"surface_distance_max_m\": " << significant(f.surface_distance_max_m) << "}";
  }
  out << "\n}\n";
  return out.str();
}

void write_sphere_set(const SphereSet& set, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error(path + ": cannot write: " + std::strerror(errno));
  out << sphere_set_json(set);
  out.close();
  if (!out) throw std::runtime_error(path + ": write error");
}

SphereSet parse_sphere_set(const std::string& text, const std::string& name) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // syntax, or a number out of double's range
    throw std::runtime_error(name + ": not JSON: " + e.what());
  }
  if (!j.is_object()) throw std::runtime_error(name + ": expected a JSON object, got " + describe(j));
  SphereSet set;
  const std::string format = text_member(j, "format", name);
  if (format != kSphereFormat)
    fail(name, "format", "expected \"" + std::string(kSphereFormat) + "\", got \"" + format + "\"");
  set.mesh = text_member(j, "mesh", name);
  set.frame = text_member(j, "frame", name);
  const Json& spheres = member(j, "spheres", name, "spheres");
  if (!spheres.is_array()) fail(name, "spheres", "expected an array, got " + describe(spheres));
  for (size_t i = 0; i < spheres.size(); ++i) {
    const std::string field = "spheres[" + std::to_string(i) + "]";
    const Json& s = spheres[i];
    if (!s.is_object()) fail(name, field, "expected an object, got " + describe(s));
    const Json& c = member(s, "centre_m", name, field + ".centre_m");
    if (!c.is_array() || c.size() != 3) fail(name, field + ".centre_m", "expected [x, y, z], got " + describe(c));
    Sphere sphere;
    for (int k = 0; k < 3; ++k)
      sphere.centre_m[k] = finite_number(c[static_cast<size_t>(k)], name, field + ".centre_m[" + std::to_string(k) + "]");
    sphere.radius_m = finite_number(member(s, "radius_m", name, field + ".radius_m"), name, field + ".radius_m");
    if (sphere.radius_m < 0.0) fail(name, field + ".radius_m", "expected a radius >= 0, got " + describe(s["radius_m"]));
    set.spheres.push_back(sphere);
  }
  const auto fit = j.find("fit");
  if (fit != j.end()) {
    if (!fit->is_object()) fail(name, "fit", "expected an object, got " + describe(*fit));
    const Json& count = member(*fit, "spheres", name, "fit.spheres");
    if (!count.is_number_integer() || count.get<long long>() != static_cast<long long>(set.spheres.size()))
      fail(name, "fit.spheres", "expected the number of spheres (" + std::to_string(set.spheres.size()) + "), got " +
                                    describe(count));
    FitError f;
    const std::pair<const char*, double*> fields[] = {{"mesh_volume_m3", &f.mesh_volume_m3},
                                                      {"outside_volume_m3", &f.outside_volume_m3},
                                                      {"uncovered_volume_m3", &f.uncovered_volume_m3},
                                                      {"surface_distance_mean_m", &f.surface_distance_mean_m},
                                                      {"surface_distance_max_m", &f.surface_distance_max_m}};
    for (const auto& [key, value] : fields) {
      const std::string field = std::string("fit.") + key;
      *value = finite_number(member(*fit, key, name, field), name, field);
      if (*value < 0.0) fail(name, field, "expected a value >= 0, got " + describe((*fit)[key]));
    }
    set.fit = f;
  }
  return set;
}

SphereSet read_sphere_set(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_sphere_set(text.str(), path);
}

}  // namespace atmo::spheres
