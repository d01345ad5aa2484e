// The loader on documents built in the test: defaults, notices, every field,
// syntax errors, and agreement with the schema at every range boundary.
#include <cctype>
#include <filesystem>
#include <fstream>
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

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

json minimal() {
  return json::parse(R"({
    "schema_version": 1,
    "name": "minimal",
    "location": {"latitude_deg": 47.26, "longitude_deg": 11.35, "height_m": 620},
    "utc": "2024-06-21T11:00:00Z",
    "cameras": [{"name": "main", "position": {"enu_m": [0, 0, 300]}, "heading_deg": 0,
                 "pitch_deg": 0, "vertical_fov_deg": 60, "width": 64, "height": 36,
                 "near_m": 1, "far_m": 10000}]
  })");
}

sc::LoadResult load(const json& doc) { return sc::parse_scenario(doc.dump(2), "test.json"); }

}  // namespace

TEST(Loader, MinimalScenarioGetsEveryDefault) {
  const auto r = load(minimal());
  ASSERT_TRUE(r.scenario) << r.error;
  const sc::Scenario& s = *r.scenario;
  EXPECT_EQ(s.schema_version, 1);
  EXPECT_EQ(s.name, "minimal");
  EXPECT_EQ(s.description, "");
  EXPECT_EQ(s.utc, "2024-06-21T11:00:00Z");
  EXPECT_EQ(s.dut1_s, 0.0);
  EXPECT_EQ(s.cameras[0].roll_deg, 0.0);
  EXPECT_EQ(s.atmosphere.visibility_m, 40000.0);
  EXPECT_EQ(s.atmosphere.aerosol_scale_height_m, 1200.0);
  EXPECT_EQ(s.atmosphere.ground_albedo, 0.1);
  EXPECT_FALSE(s.terrain);
  EXPECT_TRUE(s.clouds.empty());
  EXPECT_FALSE(s.fog);
  EXPECT_FALSE(s.lights);
  EXPECT_FALSE(s.night_sky);
  EXPECT_EQ(s.render.depth_convention, sc::DepthConvention::Reversed);
  EXPECT_FALSE(s.render.exposure_ev100);
  EXPECT_EQ(s.render.output, sc::OutputEncoding::LinearHdr);
  EXPECT_TRUE(s.outputs.exr);
  EXPECT_TRUE(s.outputs.png);
  EXPECT_TRUE(s.expectations.finite);
  EXPECT_FALSE(s.expectations.reference);
  EXPECT_TRUE(s.expectations.luminance_checks.empty());
  EXPECT_FALSE(s.expectations.max_frame_ms);
  EXPECT_TRUE(s.not_yet_supported.empty());
}

TEST(Loader, SectionDefaultsFillIn) {
  json d = minimal();
  d["atmosphere"] = json::object();
  d["terrain"] = {{"kind", "hills"}};
  d["render"] = json::object();
  d["outputs"] = {{"png", false}};
  d["night_sky"] = json::object();
  d["lights"] = json::object();
  d["expectations"] = {{"reference", {{"image", "a.png"}, {"min_psnr_db", 30}}}};
  const auto r = load(d);
  ASSERT_TRUE(r.scenario) << r.error;
  const sc::Scenario& s = *r.scenario;
  EXPECT_EQ(s.atmosphere.visibility_m, 40000.0);
  ASSERT_TRUE(s.terrain);
  EXPECT_EQ(s.terrain->seed, 0u);
  EXPECT_EQ(s.terrain->size_m, 20000.0);
  EXPECT_EQ(s.terrain->relief_m, 150.0);
  EXPECT_FALSE(s.terrain->runway);
  EXPECT_EQ(s.terrain->runway_heading_deg, 90.0);
  EXPECT_TRUE(s.outputs.exr);
  EXPECT_FALSE(s.outputs.png);
  EXPECT_TRUE(s.night_sky->stars);
  EXPECT_TRUE(s.night_sky->moon);
  EXPECT_FALSE(s.lights->runway_approach);
  EXPECT_FALSE(s.lights->airport);
  EXPECT_FALSE(s.lights->town);
  EXPECT_TRUE(s.lights->points.empty());
  EXPECT_EQ(s.expectations.reference->metric, "psnr_db");
}

// The airport and town layouts: every field's default; an airport without runways gets the terrain's.
TEST(Loader, AirportAndTownDefaults) {
  json d = minimal();
  d["terrain"] = {{"kind", "flat"}, {"runway_heading_deg", 262}};
  d["lights"] = {{"airport", json::object()}, {"town", json::object()}};
  auto r = load(d);
  ASSERT_TRUE(r.scenario) << r.error;
  const sc::Lights& l = *r.scenario->lights;
  ASSERT_TRUE(l.airport);
  ASSERT_EQ(l.airport->runways.size(), 1u);
  EXPECT_EQ(l.airport->runways[0].centre_enu_m, (std::array<double, 2>{0, 0}));
  EXPECT_EQ(l.airport->runways[0].heading_deg, 262.0);  // the terrain's runway
  EXPECT_EQ(l.airport->runways[0].length_m, 3000.0);
  EXPECT_EQ(l.airport->runways[0].width_m, 45.0);
  EXPECT_EQ(l.airport->taxiway_length_m, 8000.0);
  ASSERT_TRUE(l.town);
  EXPECT_EQ(l.town->centre_enu_m, (std::array<double, 2>{0, 5000}));
  EXPECT_EQ(l.town->lights, 10000u);
  EXPECT_EQ(l.town->lights_per_km2, 1300.0);
  EXPECT_EQ(l.town->seed, 1u);
  // Without terrain: heading 90; a runway given without fields takes each field's default.
  d.erase("terrain");
  d["lights"] = {{"airport", {{"runways", {json::object(), {{"heading_deg", 60}}}}}}};
  r = load(d);
  ASSERT_TRUE(r.scenario) << r.error;
  ASSERT_EQ(r.scenario->lights->airport->runways.size(), 2u);
  EXPECT_EQ(r.scenario->lights->airport->runways[0].heading_deg, 90.0);
  EXPECT_EQ(r.scenario->lights->airport->runways[1].heading_deg, 60.0);
  EXPECT_FALSE(r.scenario->lights->town);
}

TEST(Loader, EveryFieldIsRead) {
  const fs::path file = fs::path(ATMO_SCENARIO_TEST_DATA) / "valid_all_fields.json";
  const auto r = sc::load_scenario_file(file.string());
  ASSERT_TRUE(r.scenario) << r.error;
  const sc::Scenario& s = *r.scenario;
  EXPECT_EQ(s.source_file, file.string());
  EXPECT_EQ(s.utc_posix_s, 1705271400.25);  // 08:30:00.250+10:00
  EXPECT_EQ(s.dut1_s, -0.05);
  ASSERT_EQ(s.cameras.size(), 2u);
  EXPECT_EQ(s.cameras[0].name, "left_eye");
  EXPECT_EQ(s.cameras[0].roll_deg, 5.0);
  EXPECT_EQ(s.cameras[0].near_m, 0.1);
  EXPECT_EQ(s.cameras[1].position.kind, sc::Position::Kind::Geodetic);
  EXPECT_EQ(s.cameras[1].position.geodetic.height_m, 400000.0);
  EXPECT_EQ(s.atmosphere.ground_albedo, 0.25);
  EXPECT_EQ(s.terrain->kind, sc::TerrainKind::Flat);
  EXPECT_EQ(s.terrain->seed, 42u);
  EXPECT_EQ(s.terrain->runway_heading_deg, 160.0);
  ASSERT_EQ(s.clouds.size(), 2u);
  EXPECT_EQ(s.clouds[0].type, sc::CloudType::Stratus);
  EXPECT_EQ(s.clouds[0].coverage_oktas, 6);
  EXPECT_EQ(s.clouds[0].top_m, 900.0);
  EXPECT_EQ(s.clouds[1].type, sc::CloudType::Vdb);
  EXPECT_EQ(s.clouds[1].vdb_file, "clouds/bunny.vdb");
  EXPECT_EQ(s.clouds[1].position.enu_m[2], 1500.0);
  EXPECT_EQ(s.clouds[1].scale, 2.5);
  EXPECT_EQ(s.clouds[1].heading_deg, 30.0);
  EXPECT_EQ(s.clouds[1].density_scale, 2.0);
  EXPECT_EQ(s.clouds[0].area_m, 12000.0);
  EXPECT_EQ(s.clouds[1].seed, 9u);
  EXPECT_EQ(s.fog->visibility_m, 250.0);
  ASSERT_TRUE(s.lights->airport);
  ASSERT_EQ(s.lights->airport->runways.size(), 1u);
  EXPECT_EQ(s.lights->airport->runways[0].centre_enu_m, (std::array<double, 2>{100, -200}));
  EXPECT_EQ(s.lights->airport->runways[0].heading_deg, 160.0);
  EXPECT_EQ(s.lights->airport->runways[0].length_m, 2000.0);
  EXPECT_EQ(s.lights->airport->runways[0].width_m, 30.0);
  EXPECT_EQ(s.lights->airport->taxiway_length_m, 1500.0);
  ASSERT_TRUE(s.lights->town);
  EXPECT_EQ(s.lights->town->centre_enu_m, (std::array<double, 2>{-3000, 4000}));
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_EQ(s.objects[0].spheres, "objects/van.spheres.json");
  EXPECT_EQ(s.objects[0].mesh, "objects/van.obj");
  EXPECT_EQ(s.objects[0].position_m, (std::array<double, 3>{12.5, -40, 0.25}));
  EXPECT_EQ(s.objects[0].heading_deg, -45.0);
  EXPECT_EQ(s.objects[0].albedo, (std::array<double, 3>{0.6, 0.1, 0.05}));
  EXPECT_EQ(s.objects[1].mesh, "objects/hangar.ply");
  EXPECT_EQ(s.objects[1].heading_deg, 0.0);                                    // default
  EXPECT_EQ(s.objects[1].albedo, (std::array<double, 3>{0.5, 0.5, 0.5}));  // default
  EXPECT_EQ(sc::resolve_path(s, s.objects[0].spheres),
            (fs::absolute(fs::path(ATMO_SCENARIO_TEST_DATA) / "objects/van.spheres.json")).lexically_normal().string());
  EXPECT_EQ(s.lights->town->lights, 500u);
  EXPECT_EQ(s.lights->town->lights_per_km2, 800.0);
  EXPECT_EQ(s.lights->town->seed, 7u);
  ASSERT_EQ(s.lights->points.size(), 1u);
  EXPECT_EQ(s.lights->points[0].intensity_cd, 150.0);
  EXPECT_EQ(s.lights->points[0].color, (std::array<double, 3>{1, 1, 1}));
  EXPECT_FALSE(s.night_sky->stars);
  EXPECT_EQ(s.render.depth_convention, sc::DepthConvention::Logarithmic);
  EXPECT_EQ(s.render.exposure_ev100, 13.5);
  EXPECT_EQ(s.render.output, sc::OutputEncoding::DisplaySrgb);
  EXPECT_FALSE(s.outputs.exr);
  EXPECT_FALSE(s.expectations.finite);
  EXPECT_EQ(s.expectations.reference->image, "ref/every_field.PNG");
  EXPECT_EQ(s.expectations.reference->min_psnr_db, 35.0);
  ASSERT_EQ(s.expectations.luminance_checks.size(), 1u);
  EXPECT_EQ(s.expectations.luminance_checks[0].max_cd_m2, 12000.0);
  EXPECT_EQ(s.expectations.max_frame_ms, 16.7);

  std::vector<std::string> paths;
  for (const auto& n : s.not_yet_supported) {
    paths.push_back(n.path);
    EXPECT_TRUE(n.message.find("not implemented yet") != std::string::npos ||
                n.message.find("is not supported") != std::string::npos)
        << n.message;
  }
  // The night sky is drawn (only a moon: false would be reported: the Moon is part of the sky pass).
  // Clouds, fog and lights are drawn too (docs/CLOUDS.md, docs/FOG.md): nothing is left unsupported.
  EXPECT_EQ(paths, std::vector<std::string>{});


  EXPECT_EQ(sc::resolve_path(s, s.expectations.reference->image),
            (file.parent_path() / "ref/every_field.PNG").lexically_normal().string());
  EXPECT_EQ(sc::resolve_path(s, "/abs/x.png"), "/abs/x.png");

  const atmo_test::SchemaValidator v(json::parse(read_text(fs::path(ATMO_CONFIG_DIR) / "scenario.schema.json")));
  EXPECT_TRUE(v.validate(json::parse(read_text(file))).empty());
}

TEST(Loader, RelativePathsWithoutADirectoryStayRelative) {
  const auto r = sc::parse_scenario(minimal().dump(), "noon.json");
  ASSERT_TRUE(r.scenario);
  EXPECT_EQ(r.scenario->source_dir, "");
  EXPECT_EQ(sc::resolve_path(*r.scenario, "ref.png"), "ref.png");
}

TEST(Loader, EveryErrorIsReportedOnItsOwnLine) {
  json d = minimal();
  d["cameras"][0]["width"] = 0;
  d["atmosphere"] = {{"ground_albedo", 1.5}, {"colour", "blue"}};
  const auto r = load(d);
  ASSERT_FALSE(r.scenario);
  EXPECT_NE(r.error.find("test.json: /cameras/0/width: expected an integer in [1, 8192], found 0\n"),
            std::string::npos) << r.error;
  EXPECT_NE(r.error.find("test.json: /atmosphere/ground_albedo: expected a number in [0, 1], found 1.5"),
            std::string::npos) << r.error;
  EXPECT_NE(r.error.find("test.json: /atmosphere/colour: unknown field in atmosphere; expected one of: "
                         "visibility_m, aerosol_scale_height_m, ground_albedo"),
            std::string::npos) << r.error;
}

TEST(Loader, PointerEscapesSlashAndTilde) {
  json d = minimal();
  d["outputs"] = {{"a/b~c", true}};
  const auto r = load(d);
  ASSERT_FALSE(r.scenario);
  EXPECT_EQ(r.error.rfind("test.json: /outputs/a~1b~0c: unknown field in outputs", 0), 0u) << r.error;
}

TEST(Loader, WrongSectionTypeIsOneError) {
  json d = minimal();
  d["render"] = "fast";
  const auto r = load(d);
  EXPECT_EQ(r.error, "test.json: /render: expected an object (render), found \"fast\"");
}

TEST(Loader, CloudsAreSupported) {
  json d = minimal();
  d["clouds"] = json::array();
  auto r = load(d);
  ASSERT_TRUE(r.scenario) << r.error;
  EXPECT_TRUE(r.scenario->not_yet_supported.empty());
  d["clouds"] = {{{"type", "cumulus"}, {"coverage_oktas", 3}, {"base_m", 1000}, {"top_m", 2000}, {"area_m", 9000}}};
  r = load(d);
  ASSERT_TRUE(r.scenario) << r.error;
  EXPECT_TRUE(r.scenario->not_yet_supported.empty());
  EXPECT_EQ(r.scenario->clouds[0].area_m, 9000.0);
  d["clouds"] = {{{"type", "vdb"}, {"vdb_file", "a.vdb"}, {"position", {{"enu_m", {0, 0, 0}}}}, {"area_m", 9000}}};
  r = load(d);
  EXPECT_FALSE(r.scenario);
  EXPECT_NE(r.error.find("/clouds/0/area_m: unexpected on a \"vdb\" layer"), std::string::npos) << r.error;
}

TEST(Loader, VdbLayerNeedsFileAndPosition) {
  json d = minimal();
  d["clouds"] = {{{"type", "vdb"}, {"base_m", 100}}};
  const auto r = load(d);
  ASSERT_FALSE(r.scenario);
  EXPECT_NE(r.error.find("test.json: /clouds/0/base_m: unexpected on a \"vdb\" layer"),
            std::string::npos) << r.error;
  EXPECT_NE(r.error.find("test.json: /clouds/0/vdb_file: required field missing"), std::string::npos);
  EXPECT_NE(r.error.find("test.json: /clouds/0/position: required field missing"), std::string::npos);
}

TEST(Loader, PositionNeedsOneKind) {
  json d = minimal();
  d["cameras"][0]["position"] = json::object();
  EXPECT_EQ(load(d).error,
            "test.json: /cameras/0/position: expected exactly one of \"enu_m\" or \"geodetic\", found neither");
}

TEST(Loader, IntegralFloatIsAnInteger) {
  json d = minimal();
  d["cameras"][0]["width"] = 64.0;
  d["schema_version"] = 1.0;
  const auto r = load(d);
  ASSERT_TRUE(r.scenario) << r.error;
  EXPECT_EQ(r.scenario->cameras[0].width, 64);
}

TEST(Loader, MissingFileNamesThePath) {
  const auto r = sc::load_scenario_file("/nonexistent/dir/noon.json");
  ASSERT_FALSE(r.scenario);
  EXPECT_EQ(r.error.rfind("/nonexistent/dir/noon.json: cannot open", 0), 0u) << r.error;
}

// ---------------------------------------------------------------------------
// Syntax errors give line and column.

TEST(LoaderSyntax, LineAndColumn) {
  EXPECT_EQ(sc::parse_scenario("{\n  \"a\": 1,\n  \"b\": }\n", "x.json").error.rfind(
                "x.json: line 3, column 8: JSON syntax error: ", 0),
            0u);
  EXPECT_EQ(sc::parse_scenario("", "x.json").error.rfind("x.json: line 1, column 1: JSON syntax error", 0), 0u);
  EXPECT_EQ(sc::parse_scenario("{\"a\": [1, 2", "x.json").error.rfind("x.json: line 1, column 12: ", 0), 0u)
      << sc::parse_scenario("{\"a\": [1, 2", "x.json").error;
  // A number too large for a double points at its first digit.
  EXPECT_EQ(sc::parse_scenario("{\n\"dut1_s\": 1e400}", "x.json").error.rfind("x.json: line 2, column 11: ", 0),
            0u)
      << sc::parse_scenario("{\n\"dut1_s\": 1e400}", "x.json").error;
  EXPECT_NE(sc::parse_scenario("{} trailing", "x.json").error.find("JSON syntax error"), std::string::npos);
}

TEST(LoaderSyntax, DuplicateKeyAtDepth) {
  const auto r = sc::parse_scenario(R"({"cameras": [{"name": "a"}, {"name": "b", "name": "c"}]})", "x.json");
  EXPECT_EQ(r.error, "x.json: /cameras/1/name: duplicate key (each field may appear once)");
}

// A flight and its channels: values as written, the defaults, the frame count from the keyframes.
TEST(Loader, ChannelsAndFlight) {
  json d = minimal();
  d["channels"] = {{"horizontal_fov_deg", 60}, {"vertical_fov_deg", 35}, {"overlap_deg", 6}, {"width", 160}, {"height", 90}};
  d["flight"] = json::parse(R"({
    "frame_rate_hz": 0.02,
    "keyframes": [
      {"t_s": 0, "position": {"enu_m": [0, 0, 1500]}, "heading_deg": 200},
      {"t_s": 950, "position": {"geodetic": {"latitude_deg": 47.3, "longitude_deg": 11.4, "height_m": 2000}},
       "heading_deg": 260, "pitch_deg": 5}
    ],
    "events": [
      {"at_frame": 5, "atmosphere": {"visibility_m": 8000}},
      {"at_frame": 10, "clouds": [{"type": "cumulus", "coverage_oktas": 3, "base_m": 1400, "top_m": 2600, "seed": 4}]},
      {"at_frame": 12, "clouds": []}
    ]
  })");
  const auto r = load(d);
  ASSERT_TRUE(r.scenario) << r.error;
  const sc::Scenario& s = *r.scenario;
  ASSERT_TRUE(s.channels);
  EXPECT_EQ(s.channels->layout, sc::ChannelLayout::Wrap);
  EXPECT_EQ(s.channels->count, 3);
  EXPECT_EQ(s.channels->horizontal_fov_deg, 60.0);
  EXPECT_EQ(s.channels->vertical_fov_deg, 35.0);
  EXPECT_EQ(s.channels->overlap_deg, 6.0);
  EXPECT_EQ(s.channels->width, 160);
  EXPECT_EQ(s.channels->height, 90);
  EXPECT_EQ(s.channels->near_m, 1.0);
  EXPECT_EQ(s.channels->far_m, 100000.0);
  ASSERT_TRUE(s.flight);
  EXPECT_EQ(s.flight->frame_rate_hz, 0.02);
  EXPECT_EQ(s.flight->frames, 20);  // floor(950 * 0.02) + 1
  ASSERT_EQ(s.flight->keyframes.size(), 2u);
  EXPECT_EQ(s.flight->keyframes[0].position.kind, sc::Position::Kind::Enu);
  EXPECT_EQ(s.flight->keyframes[0].pitch_deg, 0.0);
  EXPECT_EQ(s.flight->keyframes[1].position.kind, sc::Position::Kind::Geodetic);
  EXPECT_EQ(s.flight->keyframes[1].heading_deg, 260.0);
  EXPECT_EQ(s.flight->keyframes[1].pitch_deg, 5.0);
  ASSERT_EQ(s.flight->events.size(), 3u);
  EXPECT_EQ(s.flight->events[0].at_frame, 5);
  ASSERT_TRUE(s.flight->events[0].atmosphere);
  EXPECT_EQ(s.flight->events[0].atmosphere->visibility_m, 8000.0);
  EXPECT_EQ(s.flight->events[0].atmosphere->aerosol_scale_height_m, 1200.0);  // a whole section: the default
  EXPECT_FALSE(s.flight->events[0].clouds);
  ASSERT_TRUE(s.flight->events[1].clouds);
  ASSERT_EQ(s.flight->events[1].clouds->size(), 1u);
  EXPECT_EQ((*s.flight->events[1].clouds)[0].seed, 4u);
  ASSERT_TRUE(s.flight->events[2].clouds);
  EXPECT_TRUE(s.flight->events[2].clouds->empty());
  EXPECT_FALSE(load(minimal()).scenario->flight);
  EXPECT_FALSE(load(minimal()).scenario->channels);

  d["flight"]["frames"] = 7;
  const auto given = load(d);
  ASSERT_TRUE(given.scenario) << given.error;
  EXPECT_EQ(given.scenario->flight->frames, 7);
}

// The rules only the loader can check, each named by its pointer.
TEST(Loader, ChannelsAndFlightCrossFieldRules) {
  json d = minimal();
  d["channels"] = {{"horizontal_fov_deg", 60}, {"vertical_fov_deg", 35}, {"overlap_deg", 60}, {"width", 16}, {"height", 9}};
  EXPECT_EQ(load(d).error, "test.json: /channels/overlap_deg: expected a number < horizontal_fov_deg (60), found 60");
  d["channels"]["overlap_deg"] = 5;
  d["channels"]["near_m"] = 10;
  d["channels"]["far_m"] = 10;
  EXPECT_EQ(load(d).error, "test.json: /channels/far_m: expected a number > near_m (10), found 10");
  d.erase("channels");
  d["flight"] = json::parse(R"({"frame_rate_hz": 30, "keyframes": [
      {"t_s": 1, "position": {"enu_m": [0, 0, 1]}, "heading_deg": 0},
      {"t_s": 1, "position": {"enu_m": [0, 0, 1]}, "heading_deg": 0}]})");
  EXPECT_EQ(load(d).error,
            "test.json: /flight/keyframes/1/t_s: expected a number > the previous keyframe's t_s (1), found 1");
  d["flight"]["keyframes"][1]["t_s"] = 40000;
  EXPECT_EQ(load(d).error,
            "test.json: /flight/keyframes: expected keyframes spanning at most 10^6 frames at frame_rate_hz, found "
            "1200001 (give \"frames\")");
  d["flight"]["events"] = json::parse(R"([{"at_frame": 3}])");
  d["flight"]["keyframes"][1]["t_s"] = 2;
  EXPECT_EQ(load(d).error,
            "test.json: /flight/events/0: expected at least one of \"atmosphere\" or \"clouds\", found neither");
}

// ---------------------------------------------------------------------------
// Loader and schema accept the same documents at every boundary.

struct Mutation {
  const char* pointer;
  json value;  // null: remove the field
  bool valid;
};

// gtest would otherwise print json as a container, recursing without end.
void PrintTo(const Mutation& m, std::ostream* os) {
  *os << m.pointer << " = " << (m.value.is_null() ? "(removed)" : m.value.dump());
}

class Boundary : public ::testing::TestWithParam<Mutation> {};

TEST_P(Boundary, LoaderAndSchemaAgree) {
  const Mutation& m = GetParam();
  json d = minimal();
  const json::json_pointer p(m.pointer);
  if (m.value.is_null()) {
    d[p.parent_pointer()].erase(p.back());
  } else {
    d[p] = m.value;
  }
  static const atmo_test::SchemaValidator v(
      json::parse(read_text(fs::path(ATMO_CONFIG_DIR) / "scenario.schema.json")));
  const auto schema_errors = v.validate(d);
  const auto r = load(d);
  EXPECT_EQ(r.scenario.has_value(), m.valid) << m.pointer << " = " << m.value << "\n" << r.error;
  EXPECT_EQ(schema_errors.empty(), m.valid) << m.pointer << " = " << m.value << "\n"
                                            << ::testing::PrintToString(schema_errors);
  if (!m.valid && !r.scenario) {
    EXPECT_NE(r.error.find(std::string("test.json: ") + m.pointer), std::string::npos) << r.error;
  }
}

// Built at run time: json literals are not constant expressions.
std::vector<Mutation> boundary_cases() {
  const json obj = json::object();
  return {
      {"/schema_version", 0, false},
      {"/schema_version", "1", false},
      {"/name", "", false},
      {"/name", 5, false},
      {"/description", "text", true},
      {"/description", 1, false},
      {"/$schema", "anything", true},
      {"/location/latitude_deg", 90, true},
      {"/location/latitude_deg", -90.0001, false},
      {"/location/longitude_deg", -180, true},
      {"/location/longitude_deg", 180.5, false},
      {"/location/height_m", -1000, true},
      {"/location/height_m", -1001, false},
      {"/location/height_m", 10000000, true},
      {"/location/height_m", 10000001, false},
      {"/location/altitude_m", 5, false},
      {"/utc", "2024-06-21T11:00:00.5Z", true},
      {"/utc", "2024-06-21T11:00:00+14:00", true},
      {"/utc", "2024-06-21T11:00:00-00:00", true},
      {"/utc", "2024-06-21t11:00:00Z", false},
      {"/utc", "2024-06-21T11:00:00", false},
      {"/utc", "2024-6-21T11:00:00Z", false},
      {"/utc", 1718967600, false},
      {"/dut1_s", 0.9, true},
      {"/dut1_s", -0.9, true},
      {"/dut1_s", 0.901, false},
      {"/dut1_s", -0.901, false},
      {"/dut1_s", -1, false},
      {"/cameras", obj, false},
      {"/cameras/0/name", "cam_1-b", true},
      {"/cameras/0/name", "-cam", false},
      {"/cameras/0/name", "a b", false},
      {"/cameras/0/name", std::string(64, 'a'), true},
      {"/cameras/0/name", std::string(65, 'a'), false},
      {"/cameras/0/position", {{"geodetic", {{"latitude_deg", 1}, {"longitude_deg", 2}, {"height_m", 3}}}}, true},
      {"/cameras/0/position", {{"geodetic", {{"latitude_deg", 1}, {"longitude_deg", 2}}}}, false},
      {"/cameras/0/position", {{"enu_m", {1, 2}}}, false},
      {"/cameras/0/position", {{"enu_m", {1, 2, 3, 4}}}, false},
      {"/cameras/0/position", {{"enu_m", {1, 2, 3}}, {"extra", 1}}, false},
      {"/cameras/0/heading_deg", 360, true},
      {"/cameras/0/heading_deg", -360.5, false},
      {"/cameras/0/pitch_deg", -90, true},
      {"/cameras/0/pitch_deg", 90.1, false},
      {"/cameras/0/pitch_deg", nullptr, false},
      {"/cameras/0/roll_deg", 180, true},
      {"/cameras/0/roll_deg", -181, false},
      {"/cameras/0/vertical_fov_deg", 0, false},
      {"/cameras/0/vertical_fov_deg", 179.9, true},
      {"/cameras/0/vertical_fov_deg", 180, false},
      {"/cameras/0/width", 8192, true},
      {"/cameras/0/width", 8193, false},
      {"/cameras/0/height", 1, true},
      {"/cameras/0/height", 0, false},
      {"/cameras/0/height", true, false},
      {"/cameras/0/near_m", 0, false},
      {"/cameras/0/near_m", 0.001, true},
      {"/cameras/0/far_m", -5, false},
      {"/atmosphere", {{"visibility_m", 50}}, true},
      {"/atmosphere", {{"visibility_m", 49.9}}, false},
      {"/atmosphere", {{"visibility_m", 500000}}, true},
      {"/atmosphere", {{"visibility_m", 500001}}, false},
      {"/atmosphere", {{"aerosol_scale_height_m", 99}}, false},
      {"/atmosphere", {{"aerosol_scale_height_m", 20000}}, true},
      {"/atmosphere", {{"ground_albedo", 0}}, true},
      {"/atmosphere", {{"ground_albedo", -0.01}}, false},
      {"/atmosphere", {{"ground_albedo", "0.1"}}, false},
      {"/terrain", obj, false},
      {"/terrain", {{"kind", "none"}, {"seed", 9007199254740991LL}}, true},
      {"/terrain", {{"kind", "none"}, {"seed", 9007199254740992LL}}, false},
      {"/terrain", {{"kind", "none"}, {"seed", -1}}, false},
      {"/terrain", {{"kind", "none"}, {"seed", 1.5}}, false},
      {"/terrain", {{"kind", "flat"}, {"size_m", 100}, {"relief_m", 0}}, true},
      {"/terrain", {{"kind", "flat"}, {"size_m", 99}}, false},
      {"/terrain", {{"kind", "flat"}, {"relief_m", 5001}}, false},
      {"/terrain", {{"kind", "flat"}, {"runway", "yes"}}, false},
      {"/terrain", {{"kind", "flat"}, {"runway_heading_deg", 360.1}}, false},
      {"/clouds", obj, false},
      {"/clouds", {{{"type", "cirrus"}, {"coverage_oktas", 8}, {"base_m", 8000}, {"top_m", 20000}}}, true},
      {"/clouds", {{{"type", "cirrus"}, {"coverage_oktas", 9}, {"base_m", 8000}, {"top_m", 9000}}}, false},
      {"/clouds", {{{"type", "cirrus"}, {"coverage_oktas", 2}, {"base_m", 8000}, {"top_m", 20001}}}, false},
      {"/clouds", {{{"type", "overcast"}, {"coverage_oktas", 8}, {"base_m", 300}}}, false},
      {"/clouds", {{{"type", "fog"}, {"coverage_oktas", 8}, {"base_m", 0}, {"top_m", 10}}}, false},
      {"/clouds", {{{"type", "vdb"}, {"vdb_file", "a.vdb"}, {"position", {{"enu_m", {0, 0, 0}}}}}}, true},
      {"/clouds", {{{"type", "vdb"}, {"vdb_file", "a.vdb"}, {"position", {{"enu_m", {0, 0, 0}}}}, {"scale", 0}}}, false},
      {"/clouds", {{{"type", "vdb"}, {"vdb_file", ""}, {"position", {{"enu_m", {0, 0, 0}}}}}}, false},
      {"/clouds", {{{"type", "stratus"}, {"coverage_oktas", 8}, {"base_m", 300}, {"top_m", 600}, {"scale", 2}}}, false},
      {"/fog", {{"visibility_m", 10}, {"top_m", 3000}}, true},
      {"/fog", {{"visibility_m", 9}, {"top_m", 100}}, false},
      {"/fog", {{"visibility_m", 5001}, {"top_m", 100}}, false},
      {"/fog", {{"visibility_m", 100}}, false},
      {"/lights", {{"points", {{{"enu_m", {0, 0, 1}}, {"intensity_cd", 0}}}}}, false},
      {"/lights", {{"points", {{{"intensity_cd", 10}}}}}, false},
      {"/lights", {{"points", {{{"enu_m", {0, 0, 1}}, {"intensity_cd", 1}, {"color", {0, 0, 0}}}}}}, true},
      {"/lights", {{"points", {{{"enu_m", {0, 0, 1}}, {"intensity_cd", 1}, {"color", {1, 1}}}}}}, false},
      {"/lights", {{"runway_approach", 1}}, false},
      {"/lights", {{"airport", obj}, {"town", obj}}, true},
      {"/lights", {{"airport", {{"runways", json::array()}}}}, false},
      {"/lights", {{"airport", {{"runways", json::array({obj, obj, obj, obj, obj, obj, obj, obj})}}}}, true},
      {"/lights", {{"airport", {{"runways", json::array({obj, obj, obj, obj, obj, obj, obj, obj, obj})}}}}, false},
      {"/lights", {{"airport", {{"runways", {{{"length_m", 300}, {"width_m", 100}}}}}}}, true},
      {"/lights", {{"airport", {{"runways", {{{"length_m", 299}}}}}}}, false},
      {"/lights", {{"airport", {{"runways", {{{"length_m", 6001}}}}}}}, false},
      {"/lights", {{"airport", {{"runways", {{{"width_m", 9.9}}}}}}}, false},
      {"/lights", {{"airport", {{"runways", {{{"heading_deg", 360}}}}}}}, true},
      {"/lights", {{"airport", {{"runways", {{{"heading_deg", -1}}}}}}}, false},
      {"/lights", {{"airport", {{"runways", {{{"centre_enu_m", {1, 2, 3}}}}}}}}, false},
      {"/lights", {{"airport", {{"runways", {{{"centre", {1, 2}}}}}}}}, false},
      {"/lights", {{"airport", {{"taxiway_length_m", 0}}}}, true},
      {"/lights", {{"airport", {{"taxiway_length_m", 50001}}}}, false},
      {"/lights", {{"town", {{"lights", 65536}, {"lights_per_km2", 10}}}}, true},
      {"/lights", {{"town", {{"lights", 0}}}}, false},
      {"/lights", {{"town", {{"lights", 65537}}}}, false},
      {"/lights", {{"town", {{"lights", 10.5}}}}, false},
      {"/lights", {{"town", {{"lights_per_km2", 9}}}}, false},
      {"/lights", {{"town", {{"lights_per_km2", 100001}}}}, false},
      {"/lights", {{"town", {{"seed", -1}}}}, false},
      {"/lights", {{"town", {{"centre_enu_m", {"0", 5000}}}}}, false},
      {"/objects", obj, false},
      {"/objects", json::array(), true},
      {"/objects", {{{"spheres", "a.spheres.json"}, {"mesh", "a.obj"}, {"position_m", {1, 2, 0}}}}, true},
      {"/objects", {{{"mesh", "a.obj"}, {"position_m", {1, 2, 0}}}}, false},
      {"/objects", {{{"spheres", "a.spheres.json"}, {"position_m", {1, 2, 0}}}}, false},
      {"/objects", {{{"spheres", "a.spheres.json"}, {"mesh", "a.obj"}}}, false},
      {"/objects", {{{"spheres", ""}, {"mesh", "a.obj"}, {"position_m", {1, 2, 0}}}}, false},
      {"/objects", {{{"spheres", "a.spheres.json"}, {"mesh", 3}, {"position_m", {1, 2, 0}}}}, false},
      {"/objects", {{{"spheres", "s"}, {"mesh", "m"}, {"position_m", {1, 2}}}}, false},
      {"/objects", {{{"spheres", "s"}, {"mesh", "m"}, {"position_m", {1, 2, 0}}, {"heading_deg", -360}}}, true},
      {"/objects", {{{"spheres", "s"}, {"mesh", "m"}, {"position_m", {1, 2, 0}}, {"heading_deg", 360.5}}}, false},
      {"/objects", {{{"spheres", "s"}, {"mesh", "m"}, {"position_m", {1, 2, 0}}, {"albedo", {0, 0, 1}}}}, true},
      {"/objects", {{{"spheres", "s"}, {"mesh", "m"}, {"position_m", {1, 2, 0}}, {"albedo", {0, -0.1, 1}}}}, false},
      {"/objects", {{{"spheres", "s"}, {"mesh", "m"}, {"position_m", {1, 2, 0}}, {"albedo", {0.5, 0.5}}}}, false},
      {"/objects", {{{"spheres", "s"}, {"mesh", "m"}, {"position_m", {1, 2, 0}}, {"colour", {1, 1, 1}}}}, false},
      {"/objects", json::array({json::array()}), false},
      {"/night_sky", {{"stars", "yes"}}, false},
      {"/night_sky", {{"planets", true}}, false},
      {"/render", {{"depth_convention", "standard"}, {"output", "display_srgb"}}, true},
      {"/render", {{"depth_convention", "Reversed"}}, false},
      {"/render", {{"output", "srgb"}}, false},
      {"/render", {{"exposure_ev100", -20}}, true},
      {"/render", {{"exposure_ev100", 30.5}}, false},
      {"/render", {{"exposure_ev100", "auto"}}, false},
      {"/outputs", {{"exr", 0}}, false},
      {"/expectations", {{"finite", "true"}}, false},
      {"/expectations", {{"max_frame_ms", 0}}, false},
      {"/expectations", {{"max_frame_ms", 0.5}}, true},
      {"/expectations", {{"reference", {{"image", "r.png"}}}}, false},
      {"/expectations", {{"reference", {{"image", "r.png"}, {"min_psnr_db", 0}}}}, false},
      {"/expectations", {{"reference", {{"image", "r.png"}, {"min_psnr_db", 30}, {"metric", "ssim"}}}}, false},
      {"/expectations", {{"luminance_checks", {{{"name", "a"}, {"u", 1}, {"v", 0}, {"min_cd_m2", 0}, {"max_cd_m2", 0}}}}}, true},
      {"/expectations", {{"luminance_checks", {{{"name", "a"}, {"u", 1.1}, {"v", 0}, {"min_cd_m2", 0}, {"max_cd_m2", 1}}}}}, false},
      {"/expectations", {{"luminance_checks", {{{"name", ""}, {"u", 1}, {"v", 0}, {"min_cd_m2", 0}, {"max_cd_m2", 1}}}}}, false},
      {"/expectations", {{"luminance_checks", {{{"name", "a"}, {"u", 1}, {"v", 0}, {"min_cd_m2", -1}, {"max_cd_m2", 1}}}}}, false},
      {"/expectations", {{"luminance_checks", {{{"name", "a"}, {"u", 1}, {"min_cd_m2", 0}, {"max_cd_m2", 1}}}}}, false},
      {"/expectations", {{"luminance_checks", obj}}, false},
      {"/extra_section", obj, false},
      // Display channels and a flight (samples/channels, docs/MULTI_CHANNEL.md).
      {"/channels", {{"horizontal_fov_deg", 60}, {"vertical_fov_deg", 40}, {"width", 160}, {"height", 90}}, true},
      {"/channels", {{"horizontal_fov_deg", 60}, {"vertical_fov_deg", 40}, {"width", 160}}, false},
      {"/channels", {{"layout", "dome"}, {"horizontal_fov_deg", 60}, {"vertical_fov_deg", 40}, {"width", 16}, {"height", 9}}, false},
      {"/channels", {{"count", 64}, {"horizontal_fov_deg", 179.9}, {"vertical_fov_deg", 40}, {"width", 16}, {"height", 9}}, true},
      {"/channels", {{"count", 65}, {"horizontal_fov_deg", 60}, {"vertical_fov_deg", 40}, {"width", 16}, {"height", 9}}, false},
      {"/channels", {{"count", 0}, {"horizontal_fov_deg", 60}, {"vertical_fov_deg", 40}, {"width", 16}, {"height", 9}}, false},
      {"/channels", {{"horizontal_fov_deg", 180}, {"vertical_fov_deg", 40}, {"width", 16}, {"height", 9}}, false},
      {"/channels", {{"horizontal_fov_deg", 60}, {"vertical_fov_deg", 0}, {"width", 16}, {"height", 9}}, false},
      {"/channels", {{"horizontal_fov_deg", 60}, {"vertical_fov_deg", 40}, {"overlap_deg", -1}, {"width", 16}, {"height", 9}}, false},
      {"/channels", {{"horizontal_fov_deg", 60}, {"vertical_fov_deg", 40}, {"overlap_deg", 0}, {"width", 16}, {"height", 9}}, true},
      {"/channels", {{"horizontal_fov_deg", 60}, {"vertical_fov_deg", 40}, {"width", 8193}, {"height", 9}}, false},
      {"/channels", {{"horizontal_fov_deg", 60}, {"vertical_fov_deg", 40}, {"width", 16}, {"height", 9}, {"near_m", 0}}, false},
      {"/channels", {{"horizontal_fov_deg", 60}, {"vertical_fov_deg", 40}, {"width", 16}, {"height", 9}, {"fov", 1}}, false},
      {"/flight", {{"frame_rate_hz", 30}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}}}}}, true},
      {"/flight", {{"frame_rate_hz", 0}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}}}}}, false},
      {"/flight", {{"frame_rate_hz", 1000}, {"frames", 1000000}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}}}}}, true},
      {"/flight", {{"frame_rate_hz", 1000.5}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}}}}}, false},
      {"/flight", {{"frame_rate_hz", 30}, {"frames", 0}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}}}}}, false},
      {"/flight", {{"frame_rate_hz", 30}, {"keyframes", json::array()}}, false},
      {"/flight", {{"frame_rate_hz", 30}}, false},
      {"/flight", {{"frame_rate_hz", 30}, {"keyframes", {{{"t_s", -1}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}}}}}, false},
      {"/flight", {{"frame_rate_hz", 30}, {"keyframes", {{{"t_s", 0}, {"heading_deg", 0}}}}}, false},
      {"/flight", {{"frame_rate_hz", 30}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}}}}}, false},
      {"/flight", {{"frame_rate_hz", 30}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}, {"pitch_deg", 90.5}}}}}, false},
      {"/flight", {{"frame_rate_hz", 30}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}, {"roll_deg", 0}}}}}, false},
      {"/flight", {{"frame_rate_hz", 30}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}}}},
                   {"events", {{{"at_frame", 5}, {"atmosphere", {{"visibility_m", 5000}}}},
                               {{"at_frame", 10}, {"clouds", {{{"type", "cumulus"}, {"coverage_oktas", 4}, {"base_m", 1200}, {"top_m", 2500}}}}},
                               {{"at_frame", 11}, {"clouds", json::array()}}}}}, true},
      {"/flight", {{"frame_rate_hz", 30}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}}}},
                   {"events", {{{"at_frame", 5}}}}}, false},
      {"/flight", {{"frame_rate_hz", 30}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}}}},
                   {"events", {{{"at_frame", -1}, {"atmosphere", obj}}}}}, false},
      {"/flight", {{"frame_rate_hz", 30}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}}}},
                   {"events", {{{"at_frame", 1}, {"atmosphere", {{"visibility_m", 10}}}}}}}, false},
      {"/flight", {{"frame_rate_hz", 30}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}}}},
                   {"events", {{{"at_frame", 1}, {"clouds", {{{"type", "cumulus"}}}}}}}}, false},
      {"/flight", {{"frame_rate_hz", 30}, {"keyframes", {{{"t_s", 0}, {"position", {{"enu_m", {0, 0, 1}}}}, {"heading_deg", 0}}}},
                   {"events", {{{"at_frame", 1}, {"fog", obj}}}}}, false},
  };
}

// Names like "cameras_0_width_48_rejected": readable in ctest, unique by index.
INSTANTIATE_TEST_SUITE_P(Fields, Boundary, ::testing::ValuesIn(boundary_cases()),
                         [](const ::testing::TestParamInfo<Mutation>& info) {
                           std::string name;
                           for (const char* c = info.param.pointer + 1; *c; ++c) {
                             name += std::isalnum(static_cast<unsigned char>(*c)) ? *c : '_';
                           }
                           return name + "_" + std::to_string(info.index) +
                                  (info.param.valid ? "_accepted" : "_rejected");
                         });

// At most ATMO_OCCLUDER_OBJECTS_MAX objects, as set_occluders takes; the error names the array.
TEST(Loader, ObjectsAreAtMostWhatSetOccludersTakes) {
  json d = minimal();
  const json object = {{"spheres", "s.json"}, {"mesh", "m.obj"}, {"position_m", {0, 0, 0}}};
  d["objects"] = json::array();
  for (size_t i = 0; i < sc::kMaxObjects; ++i) d["objects"].push_back(object);
  auto r = load(d);
  ASSERT_TRUE(r.scenario) << r.error;
  EXPECT_EQ(r.scenario->objects.size(), sc::kMaxObjects);
  d["objects"].push_back(object);
  r = load(d);
  EXPECT_EQ(r.error, "test.json: /objects: expected an array of at most 4096 objects, found an array of 4097");
}

// A malformed object names its element and index.
TEST(Loader, ObjectErrorsNameTheElement) {
  json d = minimal();
  const json ok = {{"spheres", "s.json"}, {"mesh", "m.obj"}, {"position_m", {0, 0, 0}}};
  d["objects"] = {ok, ok, ok};
  d["objects"][2]["albedo"] = {0.5, 1.5, 0.5};
  EXPECT_EQ(load(d).error, "test.json: /objects/2/albedo/1: expected a number in [0, 1], found 1.5");
  d["objects"][2].erase("albedo");
  d["objects"][1].erase("mesh");
  EXPECT_EQ(load(d).error,
            "test.json: /objects/1/mesh: required field missing: expected a path to an OBJ or PLY mesh");
  d["objects"][1]["mesh"] = "m.obj";
  d["objects"][0]["position_m"] = {0, "north", 0};
  EXPECT_EQ(load(d).error, "test.json: /objects/0/position_m/1: expected a number, found \"north\"");
}

TEST(Loader, MoonOffIsReportedAndCameraExposureIsRead) {
  json d = minimal();
  d["night_sky"] = {{"moon", false}};
  d["cameras"][0]["exposure_ev100"] = 12.0;
  const auto r = load(d);
  ASSERT_TRUE(r.scenario) << r.error;
  ASSERT_EQ(r.scenario->not_yet_supported.size(), 1u);
  EXPECT_EQ(r.scenario->not_yet_supported[0].path, "/night_sky/moon");
  ASSERT_TRUE(r.scenario->cameras[0].exposure_ev100);
  EXPECT_EQ(*r.scenario->cameras[0].exposure_ev100, 12.0);
  // Out of range: refused with the camera's pointer.
  d["cameras"][0]["exposure_ev100"] = 40.0;
  const auto bad = load(d);
  EXPECT_FALSE(bad.scenario);
  EXPECT_NE(bad.error.find("/cameras/0/exposure_ev100"), std::string::npos) << bad.error;
}

// A luminance check names the one camera it applies to; a name that is not
// a camera's is an error naming the field and the cameras there are.
TEST(Loader, LuminanceCheckCameraMustBeACamera) {
  json d = minimal();
  const std::string camera = d["cameras"][0]["name"];
  d["expectations"] = {{"luminance_checks",
                        {{{"name", "a"}, {"u", 0.5}, {"v", 0.5}, {"min_cd_m2", 0}, {"max_cd_m2", 1}, {"camera", camera}},
                         {{"name", "b"}, {"u", 0.5}, {"v", 0.5}, {"min_cd_m2", 0}, {"max_cd_m2", 1}}}}};
  auto r = load(d);
  ASSERT_TRUE(r.scenario) << r.error;
  EXPECT_EQ(r.scenario->expectations.luminance_checks[0].camera, camera);
  EXPECT_EQ(r.scenario->expectations.luminance_checks[1].camera, "");
  d["expectations"]["luminance_checks"][0]["camera"] = "nope";
  r = load(d);
  ASSERT_FALSE(r.scenario);
  EXPECT_NE(r.error.find("test.json: /expectations/luminance_checks/0/camera: expected the name of one of the "
                         "cameras (" + camera + "), found \"nope\""),
            std::string::npos)
      << r.error;
}
