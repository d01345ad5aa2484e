// The shipped scenarios, the malformed examples and the schema itself.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "atmo_scenario/scenario.h"
#include "schema_validator.h"

namespace fs = std::filesystem;
using nlohmann::json;
namespace sc = atmo::scenario;

namespace {

const fs::path kConfig = ATMO_CONFIG_DIR;
const fs::path kData = ATMO_SCENARIO_TEST_DATA;

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

json schema_json() { return json::parse(read_text(kConfig / "scenario.schema.json")); }

std::vector<std::string> json_files(const fs::path& dir, const std::string& prefix) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.path().extension() == ".json" && name.rfind(prefix, 0) == 0) out.push_back(name);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> lines(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

std::string test_name(std::string file) {
  file = file.substr(0, file.size() - 5);  // ".json"
  for (char& c : file) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return file;
}

// NOAA's solar position (accurate to ~0.01 deg): enough to check that a
// scenario called "sunset" really has the sun near the horizon.
double sun_elevation_deg(double lat_deg, double lon_deg, double posix_s) {
  const double d2r = 3.14159265358979323846 / 180.0;
  const double jd = posix_s / 86400.0 + 2440587.5;
  const double T = (jd - 2451545.0) / 36525.0;
  const double L0 = std::fmod(280.46646 + T * (36000.76983 + T * 0.0003032), 360.0);
  const double M = (357.52911 + T * (35999.05029 - 0.0001537 * T)) * d2r;
  const double C = std::sin(M) * (1.914602 - T * (0.004817 + 0.000014 * T)) +
                   std::sin(2 * M) * (0.019993 - 0.000101 * T) + std::sin(3 * M) * 0.000289;
  const double omega = (125.04 - 1934.136 * T) * d2r;
  const double lambda = (L0 + C - 0.00569 - 0.00478 * std::sin(omega)) * d2r;
  const double eps0 = 23.0 + (26.0 + (21.448 - T * (46.815 + T * (0.00059 - T * 0.001813))) / 60.0) / 60.0;
  const double eps = (eps0 + 0.00256 * std::cos(omega)) * d2r;
  const double dec = std::asin(std::sin(eps) * std::sin(lambda));
  const double ra = std::atan2(std::cos(eps) * std::sin(lambda), std::cos(lambda));
  const double D = jd - 2451545.0;
  const double gmst = std::fmod(280.46061837 + 360.98564736629 * D + 0.000387933 * T * T, 360.0);
  const double H = (gmst + lon_deg) * d2r - ra;
  const double lat = lat_deg * d2r;
  return std::asin(std::sin(lat) * std::sin(dec) + std::cos(lat) * std::cos(dec) * std::cos(H)) / d2r;
}

}  // namespace

// ---------------------------------------------------------------------------
// Shipped scenarios

const std::vector<std::string> kShipped = {
    "airport_night_clear.json", "airport_night_fog_rvr550.json", "airport_night_haze_5km.json",
    "apron_objects_low_sun.json", "apron_objects_noon.json",
    "cirrus_overhead.json", "civil_twilight.json", "cumulus_8_oktas_horizon.json", "cumulus_flythrough.json", "high_altitude_12km.json", "moonlit_night.json",
    "noon_clear.json",     "orbit_night_5000km.json", "overcast_dusk.json",      "overcast_low_sun.json",
    "runway_fog_night.json", "sunset_haze.json", "vdb_cloud.json"};

TEST(ShippedScenarios, AreExactlyTheDocumentedEighteen) {
  EXPECT_EQ(json_files(kConfig / "scenarios", ""), kShipped);
}

class ShippedScenario : public ::testing::TestWithParam<std::string> {};

TEST_P(ShippedScenario, LoadsWithoutError) {
  const auto r = sc::load_scenario_file((kConfig / "scenarios" / GetParam()).string());
  ASSERT_TRUE(r.scenario) << r.error;
  EXPECT_TRUE(r.error.empty());
  EXPECT_FALSE(r.scenario->cameras.empty());
  EXPECT_TRUE(r.scenario->expectations.finite);
  // Every shipped scenario is checked against physics and a regression image.
  EXPECT_FALSE(r.scenario->expectations.luminance_checks.empty());
  ASSERT_TRUE(r.scenario->expectations.reference);
  // The reference exists for every camera (a camera suffix when there are several).
  std::string ref = sc::resolve_path(*r.scenario, r.scenario->expectations.reference->image);
  for (const sc::Camera& cam : r.scenario->cameras) {
    std::string path = ref;
    if (r.scenario->cameras.size() > 1) path.insert(path.rfind('.'), "_" + cam.name);
    EXPECT_TRUE(std::filesystem::exists(path)) << path;
  }
}

TEST_P(ShippedScenario, SchemaAcceptsIt) {
  const atmo_test::SchemaValidator v(schema_json());
  const auto errors = v.validate(json::parse(read_text(kConfig / "scenarios" / GetParam())));
  EXPECT_TRUE(errors.empty()) << ::testing::PrintToString(errors);
}

TEST_P(ShippedScenario, SmallEnoughForTheTestSuite) {
  const auto r = sc::load_scenario_file((kConfig / "scenarios" / GetParam()).string());
  ASSERT_TRUE(r.scenario) << r.error;
  for (const auto& c : r.scenario->cameras) {
    if (GetParam() == "noon_clear.json") {
      EXPECT_EQ(c.width, 1280);
      EXPECT_EQ(c.height, 720);
    } else {
      EXPECT_LE(c.width * c.height, 640 * 360) << c.name;
    }
  }
}

// The sun must be where the scenario's name says.
TEST_P(ShippedScenario, SunElevationMatchesTheName) {
  struct Band {
    const char* file;
    double lo, hi;
  };
  static const Band kBands[] = {
      {"noon_clear.json", 50, 90},         {"sunset_haze.json", 0, 4},
      {"civil_twilight.json", -6, -2},     {"moonlit_night.json", -90, -18},
      {"runway_fog_night.json", -90, -18}, {"cumulus_flythrough.json", 30, 90},
      {"high_altitude_12km.json", 20, 90}, {"overcast_dusk.json", 0, 4},
      {"overcast_low_sun.json", 4, 10},
      {"cumulus_8_oktas_horizon.json", 30, 90}, {"cirrus_overhead.json", 30, 90},
      {"vdb_cloud.json", 30, 90},
      {"airport_night_fog_rvr550.json", -90, -18}, {"airport_night_haze_5km.json", -90, -18},
      {"airport_night_clear.json", -90, -18},
      {"apron_objects_noon.json", 50, 90},       {"apron_objects_low_sun.json", 6, 10},
      // Behind the Earth from the camera 5000 km up: below the horizon's dip there, acos(R / (R + h)) = 55.9°.
      {"orbit_night_5000km.json", -90, -56}};
  const auto r = sc::load_scenario_file((kConfig / "scenarios" / GetParam()).string());
  ASSERT_TRUE(r.scenario) << r.error;
  const auto& s = *r.scenario;
  const double e = sun_elevation_deg(s.location.latitude_deg, s.location.longitude_deg, s.utc_posix_s);
  const Band* band = nullptr;
  for (const auto& b : kBands) {
    if (GetParam() == b.file) band = &b;
  }
  ASSERT_NE(band, nullptr) << "add " << GetParam() << " to kBands";
  EXPECT_GE(e, band->lo);
  EXPECT_LE(e, band->hi);
}

INSTANTIATE_TEST_SUITE_P(Config, ShippedScenario, ::testing::ValuesIn(kShipped),
                         [](const auto& info) { return test_name(info.param); });

TEST(ShippedScenarios, NotYetSupportedSectionsAreReported) {
  auto paths = [](const std::string& file) {
    std::vector<std::string> p;
    const auto r = sc::load_scenario_file((kConfig / "scenarios" / file).string());
    if (r.scenario) {
      for (const auto& n : r.scenario->not_yet_supported) p.push_back(n.path);
    }
    return p;
  };
  EXPECT_EQ(paths("noon_clear.json"), std::vector<std::string>{});
  EXPECT_EQ(paths("moonlit_night.json"), std::vector<std::string>{});
  EXPECT_EQ(paths("runway_fog_night.json"), std::vector<std::string>{});  // fog and lights are drawn (docs/FOG.md)
  EXPECT_EQ(paths("airport_night_fog_rvr550.json"), std::vector<std::string>{});  // the airport and the town too
  EXPECT_EQ(paths("cumulus_flythrough.json"), std::vector<std::string>{});
}

TEST(ShippedScenarios, NoonClearIsTheDescribedDefault) {
  const auto r = sc::load_scenario_file((kConfig / "scenarios" / "noon_clear.json").string());
  ASSERT_TRUE(r.scenario) << r.error;
  const auto& s = *r.scenario;
  EXPECT_NEAR(s.location.latitude_deg, 47.26, 1e-9);
  EXPECT_NEAR(s.location.longitude_deg, 11.35, 1e-9);
  EXPECT_EQ(s.utc_posix_s, 1718967600.0);  // 2024-06-21T11:00:00Z
  ASSERT_EQ(s.cameras.size(), 1u);
  const auto& c = s.cameras[0];
  EXPECT_EQ(c.position.kind, sc::Position::Kind::Enu);
  EXPECT_EQ(c.position.enu_m[2], 300.0);
  EXPECT_LT(c.pitch_deg, 0.0);
  EXPECT_GT(c.pitch_deg + c.vertical_fov_deg / 2, 0.0);  // the horizon is in view
  EXPECT_EQ(c.vertical_fov_deg, 60.0);
  ASSERT_TRUE(s.terrain);
  EXPECT_EQ(s.terrain->kind, sc::TerrainKind::Hills);
}

// The flights of config/scenarios/flights (atmo-channels, docs/MULTI_CHANNEL.md; not among the scenarios
// `atmo render` draws in the suite): they load, the schema accepts them, and each has channels and a flight.
TEST(FlightScenarios, LoadAndTheSchemaAcceptsThem) {
  const std::vector<std::string> files = json_files(kConfig / "scenarios" / "flights", "");
  ASSERT_EQ(files, std::vector<std::string>{"channels_flight.json"});
  const atmo_test::SchemaValidator v(schema_json());
  for (const std::string& f : files) {
    const fs::path path = kConfig / "scenarios" / "flights" / f;
    const auto r = sc::load_scenario_file(path.string());
    ASSERT_TRUE(r.scenario) << r.error;
    EXPECT_TRUE(r.scenario->channels) << f;
    ASSERT_TRUE(r.scenario->flight) << f;
    EXPECT_EQ(r.scenario->flight->frames, 120) << f;
    EXPECT_FALSE(r.scenario->flight->events.empty()) << f;
    const auto errors = v.validate(json::parse(read_text(path)));
    EXPECT_TRUE(errors.empty()) << f << ": " << ::testing::PrintToString(errors);
  }
}

// ---------------------------------------------------------------------------
// Malformed examples: each gives one error line naming the file and the
// exact JSON pointer (or line and column for syntax errors).

struct Malformed {
  const char* file;
  const char* where;     // JSON pointer, "line L, column C" or "(root)"
  const char* contains;  // part of the message
  bool schema_rejects;   // false: a rule only the loader can check
};

const Malformed kMalformed[] = {
    {"bad_both_positions.json", "/cameras/0/position", "found both", true},
    {"bad_calendar_date.json", "/utc", "2023-02 has 28 days", false},
    {"bad_camera_name.json", "/cameras/0/name", "found \"../main\"", true},
    {"bad_cloud_top_below_base.json", "/clouds/0/top_m", "expected a number > base_m (800), found 600", false},
    {"bad_duplicate_camera_name.json", "/cameras/1/name", "found \"main\" again", false},
    {"bad_duplicate_key.json", "/location/height_m", "duplicate key", false},
    {"bad_empty_cameras.json", "/cameras", "expected an array of at least 1 camera, found an array of 0", true},
    {"bad_enu_item.json", "/cameras/0/position/enu_m/1", "expected a number, found \"north\"", true},
    {"bad_enum.json", "/terrain/kind", "expected one of \"hills\", \"flat\", \"none\", found \"mountains\"", true},
    {"bad_far_before_near.json", "/cameras/0/far_m", "expected a number > near_m (1), found 0.5", false},
    {"bad_fog_out_of_range.json", "/fog/top_m", "expected a number in (0, 3000], found 0", true},
    {"bad_fractional_width.json", "/cameras/0/width", "expected an integer in [1, 8192], found 64.5", true},
    {"bad_light_color.json", "/lights/points/0/color/1", "expected a number in [0, 1], found 2", true},
    {"bad_airport_runway_length.json", "/lights/airport/runways/1/length_m", "expected a number in [300, 6000], found 100", true},
    {"bad_town_lights.json", "/lights/town/lights", "expected an integer in [1, 65536], found 70000", true},
    {"bad_luminance_check_bounds.json", "/expectations/luminance_checks/0/max_cd_m2", "expected a number >= min_cd_m2 (500), found 100", false},
    {"bad_object_albedo.json", "/objects/2/albedo/1", "expected a number in [0, 1], found 1.5", true},
    {"bad_missing_camera_field.json", "/cameras/0/height", "required field missing: expected an integer in [1, 8192]", true},
    {"bad_missing_required.json", "/utc", "required field missing", true},
    {"bad_out_of_range.json", "/cameras/0/vertical_fov_deg", "expected a number in (0, 180), found 270", true},
    {"bad_reference_not_png.json", "/expectations/reference/image", "found \"noon.jpg\"", true},
    {"bad_root_not_object.json", "(root)", "expected an object (scenario), found an array of 2", true},
    {"bad_schema_version.json", "/schema_version", "found 2", true},
    {"bad_syntax_error.json", "line 4, column 3", "JSON syntax error", false},
    {"bad_type.json", "/cameras/0/width", "expected an integer in [1, 8192], found \"640\"", true},
    {"bad_unknown_field.json", "/atmosphere/visibilty_m", "unknown field in atmosphere (did you mean \"visibility_m\"?)", true},
    {"bad_utc_format.json", "/utc", "expected an ISO 8601 time \"YYYY-MM-DDThh:mm:ss[.fff]Z\" (or with a \"+hh:mm\" offset), found \"2024-06-21 11:00:00\"", true},
    {"bad_vdb_field_on_cumulus.json", "/clouds/0/vdb_file", "unexpected on a \"cumulus\" layer", true},
};

void PrintTo(const Malformed& m, std::ostream* os) { *os << m.file; }

class MalformedScenario : public ::testing::TestWithParam<Malformed> {};

TEST_P(MalformedScenario, ErrorNamesFileAndPointer) {
  const Malformed& m = GetParam();
  const std::string path = (kData / m.file).string();
  const auto r = sc::load_scenario_file(path);
  ASSERT_FALSE(r.scenario);
  const auto l = lines(r.error);
  ASSERT_EQ(l.size(), 1u) << r.error;
  const std::string head = path + ": " + m.where + ": ";
  EXPECT_EQ(l[0].rfind(head, 0), 0u) << "error: " << l[0] << "\nexpected to start with: " << head;
  EXPECT_NE(l[0].find(m.contains), std::string::npos) << l[0];
  EXPECT_NE(l[0].find(m.file), std::string::npos);
}

// The schema rejects the same files, except rules a schema cannot state.
TEST_P(MalformedScenario, SchemaAgrees) {
  const Malformed& m = GetParam();
  const json doc = json::parse(read_text(kData / m.file), nullptr, false);
  if (doc.is_discarded()) {
    EXPECT_FALSE(m.schema_rejects);
    return;
  }
  const atmo_test::SchemaValidator v(schema_json());
  EXPECT_EQ(!v.validate(doc).empty(), m.schema_rejects);
}

INSTANTIATE_TEST_SUITE_P(Data, MalformedScenario, ::testing::ValuesIn(kMalformed),
                         [](const auto& info) { return test_name(info.param.file); });

TEST(MalformedScenarios, EveryDataFileHasACase) {
  std::vector<std::string> listed;
  for (const auto& m : kMalformed) listed.push_back(m.file);
  std::sort(listed.begin(), listed.end());
  EXPECT_EQ(json_files(kData, "bad_"), listed);
}

TEST(MalformedScenarios, ErrorIsFromTheLabelGiven) {
  const auto r = sc::parse_scenario(read_text(kData / "bad_out_of_range.json"), "noon.json");
  EXPECT_EQ(r.error, "noon.json: /cameras/0/vertical_fov_deg: expected a number in (0, 180), found 270");
}

// ---------------------------------------------------------------------------
// The schema

TEST(Schema, IsValidJsonOfDraft2020_12) {
  const json s = schema_json();
  EXPECT_EQ(s.at("$schema"), "https://json-schema.org/draft/2020-12/schema");
  EXPECT_EQ(s.at("type"), "object");
  EXPECT_EQ(s.at("additionalProperties"), false);
  EXPECT_EQ(s.at("properties").at("schema_version").at("const"), 1);
  const auto& req = s.at("required");
  EXPECT_NE(std::find(req.begin(), req.end(), "schema_version"), req.end());
}

TEST(Schema, UsesOnlyKeywordsTheTestValidatorImplements) {
  const atmo_test::SchemaValidator v(schema_json());
  EXPECT_TRUE(v.unknown_keywords().empty()) << ::testing::PrintToString(v.unknown_keywords());
}

TEST(Schema, TopLevelPropertiesAreExactlyWhatTheLoaderHandles) {
  std::set<std::string> schema_keys, loader_keys;
  const json schema = schema_json();  // items() must not outlive it
  for (const auto& [k, v] : schema.at("properties").items()) schema_keys.insert(k);
  for (const auto& k : sc::top_level_fields()) loader_keys.insert(k);
  EXPECT_EQ(schema_keys, loader_keys);
}

// Every object definition in the schema has a loader shape with the same
// field names, and every loader shape has a schema definition.
TEST(Schema, EveryObjectMatchesALoaderShape) {
  const json s = schema_json();
  std::set<std::string> schema_objects = {"scenario"};
  for (const auto& [name, def] : s.at("$defs").items()) {
    if (def.contains("properties")) schema_objects.insert(name);
  }
  std::set<std::string> loader_objects;
  for (const auto& shape : sc::object_shapes()) {
    EXPECT_TRUE(loader_objects.insert(shape.name).second) << "duplicate shape " << shape.name;
    const json& def = shape.name == "scenario" ? s : s.at("$defs").value(shape.name, json());
    ASSERT_TRUE(def.is_object() && def.contains("properties")) << "no $defs/" << shape.name;
    std::set<std::string> schema_fields, loader_fields(shape.fields.begin(), shape.fields.end());
    for (const auto& [k, v] : def.at("properties").items()) schema_fields.insert(k);
    EXPECT_EQ(schema_fields, loader_fields) << shape.name;
    EXPECT_EQ(def.value("additionalProperties", json(true)), false) << shape.name;
  }
  EXPECT_EQ(schema_objects, loader_objects);
}
