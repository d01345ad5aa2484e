// The OpenSCENARIO import (tools/scenario openscenario.h): each field's
// mapping, the example files, and each kind of bad input's message.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "atmo_scenario/openscenario.h"

namespace fs = std::filesystem;
namespace sc = atmo::scenario;

namespace {

const fs::path kExamples = fs::path(ATMO_CONFIG_DIR) / "scenarios" / "openscenario";
const fs::path kData = ATMO_OPENSCENARIO_TEST_DATA;
const std::string kEnvPath = "/OpenSCENARIO/Storyboard/Init/Actions/GlobalAction/EnvironmentAction/Environment";

// A scenario whose Init sets `environment` (the Environment's children); `root_extra` goes before the Storyboard.
std::string xosc(const std::string& environment, const std::string& root_extra = "") {
  return "<?xml version=\"1.0\"?>\n<OpenSCENARIO>\n<FileHeader revMajor=\"1\" revMinor=\"2\" description=\"t\"/>\n" +
         root_extra +
         "\n<Storyboard><Init><Actions><GlobalAction><EnvironmentAction>\n<Environment name=\"E\">\n" + environment +
         "\n</Environment>\n</EnvironmentAction></GlobalAction></Actions></Init></Storyboard>\n</OpenSCENARIO>\n";
}

const std::string kNoon = "<TimeOfDay animation=\"false\" dateTime=\"2024-06-21T11:15:00Z\"/>";

sc::Scenario load_ok(const std::string& text, const sc::ImportOptions& options = {}) {
  const sc::LoadResult r = sc::parse_openscenario(text, "t.xosc", options);
  EXPECT_TRUE(r.scenario) << r.error;
  return r.scenario ? *r.scenario : sc::Scenario{};
}

std::string load_error(const std::string& text) {
  const sc::LoadResult r = sc::parse_openscenario(text, "t.xosc");
  EXPECT_FALSE(r.scenario);
  return r.error;
}

bool has_note(const std::vector<sc::Notice>& notes, const std::string& path_end, const std::string& text) {
  for (const sc::Notice& n : notes) {
    const bool path_ok = n.path.size() >= path_end.size() &&
                         n.path.compare(n.path.size() - path_end.size(), path_end.size(), path_end) == 0;
    if (path_ok && n.message.find(text) != std::string::npos) return true;
  }
  return false;
}

std::string notes_text(const sc::Scenario& s) {
  std::string out;
  for (const auto* list : {&s.import_notes, &s.not_yet_supported})
    for (const sc::Notice& n : *list) out += n.path + ": " + n.message + "\n";
  return out;
}

std::string weather(const std::string& attributes, const std::string& children = "") {
  return kNoon + "<Weather " + attributes + ">" + children + "</Weather>";
}

}  // namespace

// --- time ----------------------------------------------------------------------------------------

TEST(OpenScenarioTime, AnOffsetIsTakenOff) {
  const sc::Scenario s = load_ok(xosc("<TimeOfDay animation=\"false\" dateTime=\"2024-06-21T13:15:00+02:00\"/>"));
  EXPECT_EQ(s.utc, "2024-06-21T11:15:00Z");
  const sc::Scenario w = load_ok(xosc("<TimeOfDay animation=\"false\" dateTime=\"2024-06-21T06:15:30.5-05:00\"/>"));
  EXPECT_EQ(w.utc, "2024-06-21T11:15:30.500Z");
}

TEST(OpenScenarioTime, NoTimeZoneIsUtcAndSaidSo) {
  const sc::Scenario s = load_ok(xosc("<TimeOfDay animation=\"false\" dateTime=\"2024-06-21T11:15:00\"/>"));
  EXPECT_EQ(s.utc, "2024-06-21T11:15:00Z");
  EXPECT_TRUE(has_note(s.import_notes, "/TimeOfDay", "no time zone: taken as UTC")) << notes_text(s);
}

TEST(OpenScenarioTime, AnimationIsNotedForAStill) {
  const sc::Scenario s = load_ok(xosc("<TimeOfDay animation=\"true\" dateTime=\"2024-06-21T11:15:00Z\"/>"));
  EXPECT_TRUE(has_note(s.import_notes, "/TimeOfDay", "a still shows dateTime")) << notes_text(s);
  const sc::Scenario off = load_ok(xosc(kNoon));
  EXPECT_FALSE(has_note(off.import_notes, "/TimeOfDay", "animation"));
}

TEST(OpenScenarioTime, NoTimeOfDayTakesTheDefault) {
  const sc::Scenario s = load_ok(xosc("<Weather/>"));
  EXPECT_EQ(s.utc, sc::kImportDefaultUtc);
  EXPECT_TRUE(has_note(s.import_notes, "/Environment", "no TimeOfDay")) << notes_text(s);
}

// --- clouds --------------------------------------------------------------------------------------

TEST(OpenScenarioClouds, EachOktaCountIsOneLayerOfThatMany) {
  const char* names[] = {"zeroOktas", "oneOktas", "twoOktas",   "threeOktas", "fourOktas",
                         "fiveOktas", "sixOktas", "sevenOktas", "eightOktas", "nineOktas"};
  for (int k = 0; k <= 9; ++k) {
    SCOPED_TRACE(names[k]);
    const sc::Scenario s = load_ok(xosc(weather(std::string("fractionalCloudCover=\"") + names[k] + "\"")));
    if (k == 0) {
      EXPECT_TRUE(s.clouds.empty());
      continue;
    }
    ASSERT_EQ(s.clouds.size(), 1u);
    const sc::CloudLayer& c = s.clouds[0];
    EXPECT_EQ(c.coverage_oktas, std::min(k, 8));  // nine: sky obscured, drawn as eight
    EXPECT_EQ(c.type, k <= 4 ? sc::CloudType::Cumulus : k <= 7 ? sc::CloudType::Stratus : sc::CloudType::Overcast);
    EXPECT_GT(c.top_m, c.base_m);
    EXPECT_GE(c.base_m, 600.0);
  }
}

TEST(OpenScenarioClouds, TheLayerDefaultsAreTheDocumentedOnes) {
  EXPECT_EQ(sc::cloud_layer_for_oktas(3).base_m, 1200.0);
  EXPECT_EQ(sc::cloud_layer_for_oktas(3).top_m, 2200.0);
  EXPECT_EQ(sc::cloud_layer_for_oktas(6).base_m, 1000.0);
  EXPECT_EQ(sc::cloud_layer_for_oktas(6).top_m, 1500.0);
  EXPECT_EQ(sc::cloud_layer_for_oktas(8).base_m, 600.0);
  EXPECT_EQ(sc::cloud_layer_for_oktas(8).top_m, 1100.0);
}

TEST(OpenScenarioClouds, CloudStateOf1_0MapsToOktas) {
  const struct {
    const char* state;
    int oktas;
  } cases[] = {{"free", 0}, {"cloudy", 6}, {"overcast", 8}, {"rainy", 8}, {"skyOff", 0}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.state);
    const sc::Scenario s = load_ok(xosc(weather(std::string("cloudState=\"") + c.state + "\"")));
    EXPECT_EQ(s.clouds.empty() ? 0 : s.clouds[0].coverage_oktas, c.oktas);
  }
  const sc::Scenario rainy = load_ok(xosc(weather("cloudState=\"rainy\"")));
  EXPECT_TRUE(has_note(rainy.not_yet_supported, "/Weather", "without its rain")) << notes_text(rainy);
}

TEST(OpenScenarioClouds, FractionalCloudCoverWinsOverCloudState) {
  const sc::Scenario s = load_ok(xosc(weather("cloudState=\"overcast\" fractionalCloudCover=\"twoOktas\"")));
  ASSERT_EQ(s.clouds.size(), 1u);
  EXPECT_EQ(s.clouds[0].coverage_oktas, 2);
}

// --- fog -----------------------------------------------------------------------------------------

TEST(OpenScenarioFog, VisualRangeIsTheAirsVisibility) {
  const sc::Scenario s = load_ok(xosc(weather("", "<Fog visualRange=\"3000\"/>")));
  EXPECT_EQ(s.atmosphere.visibility_m, 3000.0);
  EXPECT_FALSE(s.fog);
  EXPECT_EQ(load_ok(xosc(weather("", "<Fog visualRange=\"20\"/>"))).atmosphere.visibility_m, 50.0);
  const sc::Scenario far = load_ok(xosc(weather("", "<Fog visualRange=\"1e6\"/>")));
  EXPECT_EQ(far.atmosphere.visibility_m, 500000.0);
  EXPECT_TRUE(has_note(far.import_notes, "/Fog", "clamped to 500000 m")) << notes_text(far);
  EXPECT_EQ(load_ok(xosc(kNoon)).atmosphere.visibility_m, 40000.0);  // no Fog: the plugin's default
}

TEST(OpenScenarioFog, ABoundingBoxMakesAGroundFogLayerUpToItsTop) {
  const std::string box =
      "<Fog visualRange=\"250\"><BoundingBox><Center x=\"10\" y=\"0\" z=\"40\"/>"
      "<Dimensions width=\"500\" length=\"800\" height=\"60\"/></BoundingBox></Fog>";
  const sc::Scenario s = load_ok(xosc(weather("", box)));
  ASSERT_TRUE(s.fog);
  EXPECT_EQ(s.fog->visibility_m, 250.0);
  EXPECT_EQ(s.fog->top_m, 70.0);
  EXPECT_EQ(s.atmosphere.visibility_m, 40000.0);
  EXPECT_TRUE(has_note(s.import_notes, "/Fog", "width and length are not used")) << notes_text(s);
}

TEST(OpenScenarioFog, ABoxBelowTheGroundIsAnError) {
  const std::string box =
      "<Fog visualRange=\"250\"><BoundingBox><Center x=\"0\" y=\"0\" z=\"-50\"/>"
      "<Dimensions width=\"500\" length=\"800\" height=\"60\"/></BoundingBox></Fog>";
  EXPECT_NE(load_error(xosc(weather("", box))).find("/Weather/Fog/BoundingBox: expected the fog's top"),
            std::string::npos);
}

// --- Sun, place, camera --------------------------------------------------------------------------

TEST(OpenScenarioSun, TheEphemerisWinsAndTheDifferenceIsNoted) {
  // Munich, 11:15 UTC at the solstice: the Sun due south, 65.3 deg up.
  const sc::Scenario s = load_ok(xosc(weather("", "<Sun azimuth=\"3.1416\" elevation=\"1.1397\" illuminance=\"1e5\"/>")));
  EXPECT_TRUE(has_note(s.import_notes, "/Weather/Sun", "apart: the ephemeris is drawn")) << notes_text(s);
  EXPECT_TRUE(has_note(s.not_yet_supported, "/Weather/Sun", "illuminance 100000 lx")) << notes_text(s);
  // The camera faces the ephemeris's Sun: due south (179.7 deg, rounded).
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].heading_deg, 180.0);
  // A Sun the file puts in the north is 115 deg from the ephemeris's; it is still the ephemeris that is drawn.
  const sc::Scenario north = load_ok(xosc(weather("", "<Sun azimuth=\"0\" elevation=\"0\" intensity=\"1e5\"/>")));
  EXPECT_TRUE(has_note(north.import_notes, "/Weather/Sun", "115 deg apart")) << notes_text(north);
  EXPECT_EQ(north.cameras[0].heading_deg, 180.0);
}

TEST(OpenScenarioPlace, TheDefaultPlaceAndTheCommandLine) {
  const sc::Scenario s = load_ok(xosc(kNoon));
  EXPECT_EQ(s.location.latitude_deg, sc::kImportDefaultLatitudeDeg);
  EXPECT_EQ(s.location.longitude_deg, sc::kImportDefaultLongitudeDeg);
  sc::ImportOptions o;
  o.latitude_deg = -33.9;
  o.longitude_deg = 151.2;
  o.width = 96;
  o.height = 54;
  const sc::Scenario sydney = load_ok(xosc(kNoon), o);
  EXPECT_EQ(sydney.location.latitude_deg, -33.9);
  EXPECT_EQ(sydney.location.longitude_deg, 151.2);
  EXPECT_EQ(sydney.cameras[0].width, 96);
  EXPECT_EQ(sydney.cameras[0].height, 54);
  EXPECT_TRUE(has_note(sydney.import_notes, "/Environment", "from --lat/--lon")) << notes_text(sydney);
}

TEST(OpenScenarioPlace, TheGeoReferenceOfTheLogicFileRelativeToTheScenario) {
  const fs::path dir = fs::temp_directory_path() / ("atmo_xosc_" + std::to_string(::getpid()));
  fs::create_directories(dir / "roads");
  std::ofstream(dir / "roads" / "r.xodr")
      << "<OpenDRIVE><header><geoReference><![CDATA[ +proj=tmerc +lat_0=35.5 +lon_0=-106.25 +k=1 ]]>"
         "</geoReference></header></OpenDRIVE>";
  std::ofstream(dir / "utm.xodr") << "<OpenDRIVE><header><geoReference>+proj=utm +zone=32 +ellps=WGS84"
                                     "</geoReference></header></OpenDRIVE>";
  const auto with_road = [&](const std::string& file) {
    return xosc(kNoon, "<RoadNetwork><LogicFile filepath=\"" + file + "\"/></RoadNetwork>");
  };
  const sc::LoadResult r = sc::parse_openscenario(with_road("roads/r.xodr"), (dir / "s.xosc").string());
  ASSERT_TRUE(r.scenario) << r.error;
  EXPECT_EQ(r.scenario->location.latitude_deg, 35.5);
  EXPECT_EQ(r.scenario->location.longitude_deg, -106.25);
  // --lat/--lon win over it.
  sc::ImportOptions o;
  o.latitude_deg = 10.0;
  o.longitude_deg = 20.0;
  const sc::LoadResult over = sc::parse_openscenario(with_road("roads/r.xodr"), (dir / "s.xosc").string(), o);
  ASSERT_TRUE(over.scenario) << over.error;
  EXPECT_EQ(over.scenario->location.latitude_deg, 10.0);
  // Unreadable (missing, no lat_0/lon_0): the default, and why.
  for (const char* bad : {"roads/missing.xodr", "utm.xodr"}) {
    SCOPED_TRACE(bad);
    const sc::LoadResult d = sc::parse_openscenario(with_road(bad), (dir / "s.xosc").string());
    ASSERT_TRUE(d.scenario) << d.error;
    EXPECT_EQ(d.scenario->location.latitude_deg, sc::kImportDefaultLatitudeDeg);
    EXPECT_TRUE(has_note(d.scenario->import_notes, "/LogicFile", "the default place (Munich) is used"))
        << notes_text(*d.scenario);
  }
  fs::remove_all(dir);
}

TEST(OpenScenarioPlace, ProjOrigin) {
  double lat = 0, lon = 0;
  EXPECT_TRUE(sc::proj_origin("+proj=tmerc +lat_0=48.5 +lon_0=-9.25 +x_0=0", &lat, &lon));
  EXPECT_EQ(lat, 48.5);
  EXPECT_EQ(lon, -9.25);
  EXPECT_FALSE(sc::proj_origin("+proj=utm +zone=32", &lat, &lon));
  EXPECT_FALSE(sc::proj_origin("+proj=tmerc +lat_0=95 +lon_0=0", &lat, &lon));
  EXPECT_FALSE(sc::proj_origin("+proj=tmerc +lat_0=abc +lon_0=0", &lat, &lon));
}

// --- accepted, not drawn -------------------------------------------------------------------------

TEST(OpenScenarioNotDrawn, PrecipitationWindPressureTemperatureDomeImage) {
  const sc::Scenario s = load_ok(xosc(
      weather("atmosphericPressure=\"95000\" temperature=\"263.15\"",
              "<Precipitation precipitationType=\"snow\" precipitationIntensity=\"2.5\"/>"
              "<Wind direction=\"1.5\" speed=\"12\"/><DomeImage azimuthOffset=\"0\"><DomeFile filepath=\"d.hdr\"/></DomeImage>") +
      "<RoadCondition frictionScaleFactor=\"0.4\"/>"));
  EXPECT_TRUE(has_note(s.not_yet_supported, "/Weather/Precipitation", "snow 2.5 mm/h")) << notes_text(s);
  EXPECT_TRUE(has_note(s.not_yet_supported, "/Weather/Wind", "wind 12 m/s")) << notes_text(s);
  EXPECT_TRUE(has_note(s.not_yet_supported, "/Weather", "atmosphericPressure 95000 Pa")) << notes_text(s);
  EXPECT_TRUE(has_note(s.not_yet_supported, "/Weather", "temperature 263.15 K")) << notes_text(s);
  EXPECT_TRUE(has_note(s.not_yet_supported, "/Weather/DomeImage", "dome image")) << notes_text(s);
  EXPECT_TRUE(has_note(s.import_notes, "/RoadCondition", "ignored")) << notes_text(s);
  // Dry: nothing to say.
  const sc::Scenario dry = load_ok(xosc(weather("", "<Precipitation precipitationType=\"dry\"/>")));
  EXPECT_TRUE(dry.not_yet_supported.empty()) << notes_text(dry);
}

// --- structure: parameters, catalogs, versions ---------------------------------------------------

TEST(OpenScenarioStructure, ParametersAreResolved) {
  const sc::Scenario s = load_ok(
      xosc(weather("fractionalCloudCover=\"$cover\"", "<Fog visualRange=\"$range\"/>"),
           "<ParameterDeclarations><ParameterDeclaration name=\"cover\" parameterType=\"string\" value=\"threeOktas\"/>"
           "<ParameterDeclaration name=\"range\" parameterType=\"double\" value=\"1234\"/></ParameterDeclarations>"));
  ASSERT_EQ(s.clouds.size(), 1u);
  EXPECT_EQ(s.clouds[0].coverage_oktas, 3);
  EXPECT_EQ(s.atmosphere.visibility_m, 1234.0);
}

TEST(OpenScenarioStructure, TheExamplesLoadThroughTheScenarioLoader) {
  const sc::LoadResult noon = sc::load_scenario_file((kExamples / "clear_noon_drive.xosc").string());
  ASSERT_TRUE(noon.scenario) << noon.error;
  EXPECT_TRUE(noon.scenario->clouds.empty());
  EXPECT_EQ(noon.scenario->cameras.size(), 1u);
  EXPECT_EQ(noon.scenario->cameras[0].width, sc::kImportDefaultWidth);

  const sc::LoadResult fog = sc::load_scenario_file((kExamples / "overcast_foggy_morning.xosc").string());
  ASSERT_TRUE(fog.scenario) << fog.error;
  EXPECT_EQ(fog.scenario->location.latitude_deg, 52.52);  // roads/berlin_straight.xodr
  EXPECT_EQ(fog.scenario->utc, "2024-11-05T07:30:00Z");
  ASSERT_TRUE(fog.scenario->fog);
  EXPECT_EQ(fog.scenario->fog->visibility_m, 300.0);  // $fogRange
  EXPECT_EQ(fog.scenario->fog->top_m, 100.0);
  ASSERT_EQ(fog.scenario->clouds.size(), 1u);
  EXPECT_EQ(fog.scenario->clouds[0].type, sc::CloudType::Overcast);

  // The catalog entry, with the reference's parameter value over the entry's default (fourOktas).
  const sc::LoadResult dusk = sc::load_scenario_file((kExamples / "dusk_six_oktas_rain.xosc").string());
  ASSERT_TRUE(dusk.scenario) << dusk.error;
  EXPECT_EQ(dusk.scenario->location.latitude_deg, 53.551);
  ASSERT_EQ(dusk.scenario->clouds.size(), 1u);
  EXPECT_EQ(dusk.scenario->clouds[0].coverage_oktas, 6);
  EXPECT_EQ(dusk.scenario->atmosphere.visibility_m, 8000.0);
  EXPECT_TRUE(has_note(dusk.scenario->not_yet_supported, "/Precipitation", "rain 4 mm/h"))
      << notes_text(*dusk.scenario);

  // The catalog file on its own: its first Environment.
  const sc::LoadResult catalog = sc::load_scenario_file((kExamples / "catalogs" / "environments.xosc").string());
  ASSERT_TRUE(catalog.scenario) << catalog.error;
  EXPECT_EQ(catalog.scenario->clouds.at(0).coverage_oktas, 4);
}

TEST(OpenScenarioStructure, The1_0Spellings) {
  const sc::LoadResult r = sc::load_scenario_file((kData / "legacy_1_0_cloudy.xosc").string());
  ASSERT_TRUE(r.scenario) << r.error;
  const sc::Scenario& s = *r.scenario;
  EXPECT_EQ(s.utc, "2020-03-20T09:00:00Z");
  EXPECT_EQ(s.clouds.at(0).coverage_oktas, 6);  // cloudy
  EXPECT_EQ(s.atmosphere.visibility_m, 2500.0);  // "$range", declared as "$range"
  EXPECT_TRUE(has_note(s.not_yet_supported, "/Precipitation", "snow intensity 0.3")) << notes_text(s);
  EXPECT_TRUE(has_note(s.not_yet_supported, "/Sun", "illuminance 50000 lx")) << notes_text(s);
  EXPECT_TRUE(has_note(s.import_notes, "/LogicFile", "cannot open")) << notes_text(s);
}

TEST(OpenScenarioStructure, OnlyTheFirstEnvironmentActionIsShown) {
  const std::string story =
      "<Story name=\"s\"><Act name=\"a\"><ManeuverGroup maximumExecutionCount=\"1\" name=\"g\"><Actors "
      "selectTriggeringEntities=\"false\"/><Maneuver name=\"m\"><Event name=\"e\" priority=\"overwrite\"><Action "
      "name=\"x\"><GlobalAction><EnvironmentAction><Environment name=\"Later\"><Weather "
      "fractionalCloudCover=\"eightOktas\"/></Environment></EnvironmentAction></GlobalAction></Action></Event>"
      "</Maneuver></ManeuverGroup></Act></Story>";
  std::string text = xosc(weather("fractionalCloudCover=\"oneOktas\""));
  text.insert(text.find("</Storyboard>"), story);
  const sc::Scenario s = load_ok(text);
  EXPECT_EQ(s.clouds.at(0).coverage_oktas, 1);
  EXPECT_TRUE(has_note(s.import_notes, "/EnvironmentAction", "1 later EnvironmentAction(s) ignored")) << notes_text(s);
}

// --- errors --------------------------------------------------------------------------------------

TEST(OpenScenarioErrors, MalformedXmlNamesLineAndColumn) {
  const sc::LoadResult r = sc::load_scenario_file((kData / "bad_malformed.xosc").string());
  ASSERT_FALSE(r.scenario);
  // The unclosed Weather (line 6) meets </Environment> at line 7, column 7.
  EXPECT_NE(r.error.find("bad_malformed.xosc: line 7, column 7: XML syntax error: Start-end tags mismatch"),
            std::string::npos)
      << r.error;
  EXPECT_NE(load_error("").find("t.xosc: line 1, column 1: XML syntax error: No document element found"),
            std::string::npos);
}

TEST(OpenScenarioErrors, EachBadAttributeIsNamedWithItsValue) {
  const struct {
    std::string environment, message;
  } cases[] = {
      {weather("", "<Fog visualRange=\"-3\"/>"),
       kEnvPath + "/Weather/Fog@visualRange: expected a distance in metres > 0, found \"-3\""},
      {weather("", "<Fog visualRange=\"0\"/>"), "/Weather/Fog@visualRange: expected a distance in metres > 0, found \"0\""},
      {weather("", "<Fog/>"), "/Weather/Fog@visualRange: missing (required)"},
      {weather("fractionalCloudCover=\"tenOktas\""),
       "/Weather@fractionalCloudCover: expected one of zeroOktas, oneOktas, twoOktas, threeOktas, fourOktas, fiveOktas, "
       "sixOktas, sevenOktas, eightOktas, nineOktas, found \"tenOktas\""},
      {weather("cloudState=\"sunny\""), "/Weather@cloudState: expected one of free, cloudy, overcast, rainy, skyOff"},
      {weather("temperature=\"warm\""), "/Weather@temperature: expected a temperature in K in [170, 340], found \"warm\""},
      {weather("temperature=\"15\""), "/Weather@temperature: expected a temperature in K in [170, 340], found \"15\""},
      {weather("atmosphericPressure=\"1013\""), "/Weather@atmosphericPressure: expected a pressure in Pa"},
      {weather("", "<Sun azimuth=\"7\" elevation=\"0.5\"/>"),
       "/Weather/Sun@azimuth: expected an azimuth in rad in [0, 2 pi], found \"7\""},
      {weather("", "<Sun azimuth=\"1\" elevation=\"nan\"/>"), "/Weather/Sun@elevation: expected an elevation in rad"},
      {weather("", "<Sun azimuth=\"1\" elevation=\"0.2\" illuminance=\"-1\"/>"), "/Weather/Sun@illuminance: expected"},
      {weather("", "<Precipitation precipitationType=\"hail\"/>"),
       "/Weather/Precipitation@precipitationType: expected one of dry, rain, snow, found \"hail\""},
      {weather("", "<Wind direction=\"1\" speed=\"-2\"/>"), "/Weather/Wind@speed: expected a speed in m/s >= 0"},
      {"<TimeOfDay animation=\"false\" dateTime=\"2024-13-01T12:00:00+01:00\"/>",
       "/TimeOfDay@dateTime: expected a date and time"},
      {"<TimeOfDay animation=\"false\" dateTime=\"noon\"/>", "/TimeOfDay@dateTime: expected a date and time"},
      {"<TimeOfDay animation=\"maybe\" dateTime=\"2024-01-01T12:00:00Z\"/>",
       "/TimeOfDay@animation: expected one of false, true, 0, 1, found \"maybe\""},
      {"<TimeOfDay animation=\"false\"/>", "/TimeOfDay@dateTime: missing (required)"},
      {weather("", "<Fog visualRange=\"$nope\"/>"), "/Weather/Fog@visualRange: no parameter \"nope\" is declared"},
      {weather("", "<Fog visualRange=\"${$a * 2}\"/>"), "/Weather/Fog@visualRange: parameter expressions"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.environment);
    const std::string error = load_error(xosc(c.environment));
    EXPECT_EQ(error.rfind("t.xosc: line ", 0), 0u) << error;
    EXPECT_NE(error.find(c.message), std::string::npos) << error;
  }
}

TEST(OpenScenarioErrors, AParameterValueIsShownBesideItsName) {
  const std::string error =
      load_error(xosc(weather("", "<Fog visualRange=\"$r\"/>"),
                      "<ParameterDeclarations><ParameterDeclaration name=\"r\" parameterType=\"double\" "
                      "value=\"-5\"/></ParameterDeclarations>"));
  EXPECT_NE(error.find("expected a distance in metres > 0, found \"$r\" (= \"-5\")"), std::string::npos) << error;
}

TEST(OpenScenarioErrors, TheLineAndColumnAreTheElements) {
  const std::string text = xosc(weather("", "\n   <Fog visualRange=\"-3\"/>"));
  // The Fog element's '<' : count its line in the text.
  const size_t at = text.find("<Fog");
  const size_t line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
  const size_t column = at - text.rfind('\n', at);
  EXPECT_EQ(load_error(text).rfind("t.xosc: line " + std::to_string(line) + ", column " + std::to_string(column) + ": ", 0),
            0u)
      << load_error(text);
}

TEST(OpenScenarioErrors, StructureErrors) {
  EXPECT_NE(load_error("<Scenario/>").find("t.xosc: line 1, column 1: /Scenario: expected the root element OpenSCENARIO, found \"Scenario\""),
            std::string::npos);
  EXPECT_NE(load_error("<OpenSCENARIO><FileHeader revMajor=\"1\" revMinor=\"2\"/></OpenSCENARIO>")
                .find("/OpenSCENARIO: no Environment found"),
            std::string::npos);
  EXPECT_NE(load_error("<OpenSCENARIO><FileHeader revMajor=\"2\" revMinor=\"0\"/></OpenSCENARIO>")
                .find("/OpenSCENARIO/FileHeader@revMajor: expected 1 (OpenSCENARIO 1.x), found \"2\""),
            std::string::npos);
  const std::string unresolved = load_error(
      "<OpenSCENARIO><FileHeader revMajor=\"1\" revMinor=\"2\"/><Storyboard><Init><Actions><GlobalAction>"
      "<EnvironmentAction><CatalogReference catalogName=\"C\" entryName=\"x\"/></EnvironmentAction></GlobalAction>"
      "</Actions></Init></Storyboard></OpenSCENARIO>");
  EXPECT_NE(unresolved.find("/EnvironmentAction/CatalogReference: cannot resolve catalog \"C\" entry \"x\": no "
                            "CatalogLocations/EnvironmentCatalog/Directory"),
            std::string::npos)
      << unresolved;
  const sc::LoadResult missing = sc::load_scenario_file((kData / "bad_catalog_reference.xosc").string());
  ASSERT_FALSE(missing.scenario);
  EXPECT_NE(missing.error.find("cannot resolve catalog \"Environments\" entry \"NoSuchEnvironment\": not found in the 1 "
                               ".xosc file(s) of"),
            std::string::npos)
      << missing.error;
  EXPECT_NE(sc::load_scenario_file("/nonexistent/a.xosc").error.find("/nonexistent/a.xosc: cannot open: "),
            std::string::npos);
}

TEST(OpenScenarioErrors, DevicesAndDeepNestingAreSafe) {
  // A logic file that is a device: not read (it would never end), the default place.
  const sc::Scenario s = load_ok(xosc(kNoon, "<RoadNetwork><LogicFile filepath=\"/dev/zero\"/></RoadNetwork>"));
  EXPECT_TRUE(has_note(s.import_notes, "/LogicFile", "/dev/zero: not a regular file")) << notes_text(s);
  // 200 000 nested elements: searched without recursion.
  std::string deep = "<OpenSCENARIO><FileHeader revMajor=\"1\" revMinor=\"2\"/>";
  for (int i = 0; i < 200000; ++i) deep += "<a>";
  for (int i = 0; i < 200000; ++i) deep += "</a>";
  deep += "</OpenSCENARIO>";
  EXPECT_NE(load_error(deep).find("no Environment found"), std::string::npos);
}
