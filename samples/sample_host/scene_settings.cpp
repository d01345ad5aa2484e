#include "scene_settings.h"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "atmo_host_scene/depth_setup.h"
#include "atmo_host_scene/terrain.h"
#include "core/astro/iso8601.h"

namespace atmo::sample {

bool parse_utc(const std::string& text, double* posix_s, std::string* error) {
  char* end = nullptr;
  const double number = std::strtod(text.c_str(), &end);
  if (!text.empty() && end && *end == '\0' && text.find('-', 1) == std::string::npos) {
    if (!std::isfinite(number)) {
      if (error) *error = "'" + text + "' is not a finite number of POSIX seconds";
      return false;
    }
    *posix_s = number;
    return true;
  }
  const auto t = core::astro::parse_iso8601_posix(text, error);
  if (t) *posix_s = *t;
  return t.has_value();
}

std::string format_utc(double posix_s) { return core::astro::format_iso8601_posix(posix_s); }

const char* cloud_type_name(AtmoCloudLayerType type) {
  switch (type) {
    case ATMO_CLOUD_CUMULUS: return "cumulus";
    case ATMO_CLOUD_STRATUS: return "stratus";
    case ATMO_CLOUD_OVERCAST: return "overcast";
    case ATMO_CLOUD_CIRRUS: return "cirrus";
    case ATMO_CLOUD_VDB_FILE: return "vdb";
    case ATMO_CLOUD_LAYER_TYPE_COUNT: break;
  }
  return nullptr;
}

const char* cloud_draw_mode_name(uint32_t mode) {
  switch (mode) {
    case ATMO_CLOUD_DRAW_AUTO: return "auto";
    case ATMO_CLOUD_DRAW_IMPOSTORS: return "impostors";
    case ATMO_CLOUD_DRAW_DIRECT: return "direct";
    case ATMO_CLOUD_DRAW_LAYER: return "layer";
  }
  return nullptr;
}

const char* cloud_quality_name(uint32_t quality) {
  switch (quality) {
    case ATMO_CLOUD_QUALITY_DEFAULT: return "default";
    case ATMO_CLOUD_QUALITY_LOW: return "low";
    case ATMO_CLOUD_QUALITY_MEDIUM: return "medium";
    case ATMO_CLOUD_QUALITY_HIGH: return "high";
    case ATMO_CLOUD_QUALITY_FULL: return "full";
  }
  return nullptr;
}

namespace {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  size_t start = 0;
  for (size_t end; (end = text.find(separator, start)) != std::string::npos; start = end + 1)
    parts.push_back(text.substr(start, end - start));
  parts.push_back(text.substr(start));
  return parts;
}

// The whole of text as a finite number; false with *error naming what.
bool parse_number(const std::string& text, const char* what, double* out, std::string* error) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || !end || *end != '\0' || !std::isfinite(v)) {
    *error = std::string(what) + " '" + text + "' is not a finite number";
    return false;
  }
  *out = v;
  return true;
}

// The whole of text as a whole number in [0, max].
bool parse_unsigned(const std::string& text, const char* what, uint64_t max, uint64_t* out, std::string* error) {
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  if (text.empty() || text[0] < '0' || text[0] > '9' || !end || *end != '\0' || errno == ERANGE || v > max) {
    *error = std::string(what) + " '" + text + "' is not a whole number from 0 to " + std::to_string(max);
    return false;
  }
  *out = v;
  return true;
}

}  // namespace

bool parse_cloud_layer(const std::string& text, CloudLayerSettings* out, std::string* error) {
  const std::vector<std::string> parts = split(text, ':');
  const auto fail = [&](const std::string& why) {
    *error = "'" + text + "': " + why;
    return false;
  };
  if (parts.size() < 4 || parts.size() > 6) return fail("expected TYPE:OKTAS:BASE_M:TOP_M[:AREA_KM[:SEED]]");
  CloudLayerSettings layer;
  bool known = false;
  for (int t = ATMO_CLOUD_CUMULUS; t < ATMO_CLOUD_VDB_FILE; ++t) {
    if (parts[0] == cloud_type_name(static_cast<AtmoCloudLayerType>(t))) {
      layer.type = static_cast<AtmoCloudLayerType>(t);
      known = true;
    }
  }
  if (!known) return fail("type '" + parts[0] + "' is not cumulus, stratus, overcast or cirrus (a VDB file: --vdb)");
  std::string why;
  uint64_t oktas = 0;
  if (!parse_unsigned(parts[1], "oktas", INT32_MAX, &oktas, &why) ||
      !parse_number(parts[2], "base", &layer.base_m, &why) || !parse_number(parts[3], "top", &layer.top_m, &why) ||
      (parts.size() > 4 && !parse_number(parts[4], "area", &layer.area_size_km, &why)) ||
      (parts.size() > 5 && !parse_unsigned(parts[5], "seed", UINT64_MAX, &layer.seed, &why)))
    return fail(why);
  layer.coverage_oktas = static_cast<int>(oktas);
  *out = layer;
  return true;
}

bool parse_vdb_layer(const std::string& text, CloudLayerSettings* out, std::string* error) {
  const size_t colon = text.rfind(':');
  CloudLayerSettings layer;
  layer.type = ATMO_CLOUD_VDB_FILE;
  layer.base_m = 0.0;  // the file's heights are kept: its origin on the airfield's datum
  layer.vdb_path = text.substr(0, colon);
  if (colon != std::string::npos) layer.vdb_grid = text.substr(colon + 1);
  if (layer.vdb_path.empty()) {
    *error = "'" + text + "': expected FILE[:GRID]";
    return false;
  }
  *out = layer;
  return true;
}

const char* lights_choice_name(LightsChoice choice) {
  switch (choice) {
    case LightsChoice::None: return "none";
    case LightsChoice::Runway: return "runway";
    case LightsChoice::Airport: return "airport";
    case LightsChoice::AirportTown: return "airport+town";
  }
  return "?";
}

bool parse_lights_choice(const std::string& text, LightsChoice* out, std::string* error) {
  for (LightsChoice c : kLightsChoices) {
    if (text == lights_choice_name(c)) {
      *out = c;
      return true;
    }
  }
  *error = "'" + text + "' is not none, runway, airport or airport+town";
  return false;
}

host_scene::AirportSpec sample_airport() {
  const host_scene::TerrainOptions terrain;
  host_scene::AirportSpec a;
  host_scene::RunwaySpec first;
  first.centre_enu_m = {0.0, 0.0};
  first.heading_deg = terrain.runway_heading_deg;
  first.length_m = terrain.runway_length_m;
  first.width_m = terrain.runway_width_m;
  // The bench's crossing runway (900 m east, 1 200 m north of runway 36's
  // centre, heading 60) in this runway's frame: 1 200 m along it, 900 m right.
  const double h = glm::radians(terrain.runway_heading_deg);
  const glm::dvec2 along(std::sin(h), std::cos(h)), right(std::cos(h), -std::sin(h));
  host_scene::RunwaySpec second;
  second.centre_enu_m = along * 1200.0 + right * 900.0;
  second.heading_deg = std::fmod(terrain.runway_heading_deg + 60.0, 360.0);
  second.length_m = 2500.0;
  a.runways = {first, second};
  a.taxiway_length_m = 9000.0;
  return a;
}

host_scene::TownSpec sample_town(uint32_t lights) {
  const host_scene::TerrainOptions terrain;
  const double h = glm::radians(terrain.runway_heading_deg);
  host_scene::TownSpec t;
  t.centre_enu_m = glm::dvec2(std::sin(h), std::cos(h)) * 6000.0;
  t.lights = lights;
  t.lights_per_km2 = 1300.0;
  return t;
}

namespace {
uint32_t airport_light_count() {
  static const uint32_t n = static_cast<uint32_t>(host_scene::airport_lights(sample_airport()).size());
  return n;
}
}  // namespace

uint32_t default_town_lights() { return 15000u - airport_light_count(); }

uint32_t max_town_lights() { return ATMO_LIGHTS_MAX - airport_light_count(); }

bool parse_rvr(const std::string& text, double* rvr_m, std::string* error) {
  if (text == "none" || text == "0") {
    *rvr_m = 0.0;
    return true;
  }
  double v = 0.0;
  std::string why;
  if (!parse_number(text, "RVR", &v, &why) || v < kRvrMinM || v > kRvrMaxM) {
    char range[96];
    std::snprintf(range, sizeof range, "is not 'none' or metres from %.0f to %.0f", kRvrMinM, kRvrMaxM);
    *error = "'" + text + "' " + range;
    return false;
  }
  *rvr_m = v;
  return true;
}

const char* objects_choice_name(ObjectsChoice choice) {
  switch (choice) {
    case ObjectsChoice::None: return "none";
    case ObjectsChoice::Apron: return "apron";
  }
  return "?";
}

bool parse_objects_choice(const std::string& text, ObjectsChoice* out, std::string* error) {
  for (ObjectsChoice c : {ObjectsChoice::None, ObjectsChoice::Apron}) {
    if (text == objects_choice_name(c)) {
      *out = c;
      return true;
    }
  }
  *error = "'" + text + "' is not none or apron";
  return false;
}

const std::vector<ApronObject>& apron_objects() {
  // The runway runs east-west through the datum, 45 m wide; the apron lies 60-170 m north of its axis.
  static const std::vector<ApronObject> objects = {
      {"aircraft", {0.0, 105.0}, 180.0, {0.75, 0.75, 0.75}},  // nose to the runway
      {"vehicle", {24.0, 92.0}, 0.0, {0.6, 0.1, 0.08}},      // parked beside its right wing
      {"vehicle", {-20.0, 72.0}, 90.0, {0.15, 0.3, 0.6}},    // drives: apron_vehicle_pose
      {"building", {-70.0, 150.0}, 90.0, {0.45, 0.45, 0.42}}};
  return objects;
}

ApronObject apron_vehicle_pose(uint64_t frame_number) {
  ApronObject v = apron_objects()[kApronMovingVehicle];
  const double phase = 2.0 * 3.14159265358979323846 * static_cast<double>(frame_number % 240u) / 240.0;
  v.position_enu_m.x = -20.0 + 40.0 * std::sin(phase);
  v.heading_deg = std::cos(phase) >= 0.0 ? 90.0 : 270.0;  // the way it drives
  return v;
}

host_scene::CameraPose apron_view() {
  host_scene::CameraPose pose;
  pose.position_enu_m = glm::dvec3(32.0, 62.0, 3.5);
  pose.heading_deg = 318.0;
  pose.pitch_deg = -4.0;
  return pose;
}

host_scene::CameraPose approach_path(double t) {
  const host_scene::TerrainOptions runway;  // heading 90: landing eastwards
  const double touchdown = -0.5 * runway.runway_length_m + 300.0;
  const double distance = 6000.0 + 300.0 + (1000.0 - 6000.0) * t;  // to the touchdown point
  const double glide = glm::radians(3.0);
  host_scene::CameraPose pose;
  const double h = glm::radians(runway.runway_heading_deg);
  pose.position_enu_m = glm::dvec3(std::sin(h) * (touchdown - distance), std::cos(h) * (touchdown - distance),
                                   std::tan(glide) * distance + 3.0);
  // Curvature: stay on the glide path above the dropped ground.
  pose.position_enu_m.z -= host_scene::curvature_drop_m(pose.position_enu_m.x, pose.position_enu_m.y);
  pose.heading_deg = runway.runway_heading_deg;
  pose.pitch_deg = -3.0;
  return pose;
}

bool fall_back_depth_convention(SceneSettings* settings) {
  if (host_scene::depth_convention_supported(settings->depth_convention)) return false;
  std::fprintf(stderr, "atmo sample renderer: %s depth needs glClipControl; using standard depth\n",
               host_scene::to_string(settings->depth_convention));
  settings->depth_convention = host_scene::DepthConvention::Standard;
  return true;
}

}  // namespace atmo::sample
