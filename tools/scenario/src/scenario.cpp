// Scenario loader. Every object is read through an ObjectReader built from
// its entry in kShapes, so the accepted field names live in one table that a
// test compares with the schema's "properties".
#include "atmo_scenario/scenario.h"

#include <cctype>
#include <cmath>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "atmo_scenario/openscenario.h"
#include "json_reader.h"

namespace atmo::scenario {

using detail::ObjectReader;
using detail::Range;
using nlohmann::json;

namespace {

const std::vector<ObjectShape> kShapes = {
    {"scenario",
     {"$schema", "schema_version", "name", "description", "location", "utc", "dut1_s", "cameras",
      "atmosphere", "terrain", "clouds", "fog", "lights", "objects", "night_sky", "render", "outputs",
      "expectations", "channels", "flight"}},
    {"geodetic", {"latitude_deg", "longitude_deg", "height_m"}},
    {"position", {"enu_m", "geodetic"}},
    {"camera",
     {"name", "position", "heading_deg", "pitch_deg", "roll_deg", "vertical_fov_deg", "width",
      "height", "near_m", "far_m", "exposure_ev100"}},
    {"atmosphere", {"visibility_m", "aerosol_scale_height_m", "ground_albedo"}},
    {"terrain", {"kind", "seed", "size_m", "relief_m", "runway", "runway_heading_deg"}},
    {"cloud_layer",
     {"type", "coverage_oktas", "base_m", "top_m", "area_m", "seed", "vdb_file", "position", "scale",
      "heading_deg", "density_scale"}},
    {"fog", {"visibility_m", "top_m"}},
    {"lights", {"runway_approach", "airport", "town", "points"}},
    {"airport_lights", {"runways", "taxiway_length_m"}},
    {"airport_runway", {"centre_enu_m", "heading_deg", "length_m", "width_m"}},
    {"town_lights", {"centre_enu_m", "lights", "lights_per_km2", "seed"}},
    {"light_point", {"enu_m", "intensity_cd", "color"}},
    {"object", {"spheres", "mesh", "position_m", "heading_deg", "albedo"}},
    {"night_sky", {"stars", "moon"}},
    {"render", {"depth_convention", "exposure_ev100", "output", "cloud_draw_mode"}},
    {"outputs", {"exr", "png"}},
    {"expectations", {"finite", "reference", "luminance_checks", "max_frame_ms"}},
    {"reference", {"image", "metric", "min_psnr_db"}},
    {"luminance_check", {"name", "u", "v", "min_cd_m2", "max_cd_m2", "camera"}},
    {"channels",
     {"layout", "count", "horizontal_fov_deg", "vertical_fov_deg", "overlap_deg", "width", "height", "near_m",
      "far_m"}},
    {"flight", {"frame_rate_hz", "frames", "keyframes", "events"}},
    {"flight_keyframe", {"t_s", "position", "heading_deg", "pitch_deg"}},
    {"flight_event", {"at_frame", "atmosphere", "clouds"}},
};

const std::vector<std::string>& shape(const char* name) {
  for (const auto& s : kShapes) {
    if (s.name == name) return s.fields;
  }
  throw std::logic_error(std::string("atmo_scenario: no shape ") + name);
}

// Same limits as the schema; keep the two in step.
constexpr std::int64_t kMaxSeed = 9007199254740991;  // 2^53 - 1: exact in any JSON reader
const Range kLatitude = Range::closed(-90, 90);
const Range kLongitude = Range::closed(-180, 180);
const Range kHeight = Range::closed(-1000, 1e7);  // the ABI's eye height (atmo.h)

bool camera_name_ok(const std::string& s) {
  if (s.empty() || s.size() > 64 || !std::isalnum(static_cast<unsigned char>(s[0]))) return false;
  for (char c : s) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  }
  return true;
}

bool png_name_ok(const std::string& s) {
  if (s.size() < 4) return false;
  std::string ext = s.substr(s.size() - 4);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".png";
}

class Loader {
 public:
  explicit Loader(const std::string& file) : errors_(file) {}

  detail::Errors& errors() { return errors_; }

  void scenario(const json& root, Scenario* s) {
    ObjectReader r(errors_, root, "", shape("scenario"), "scenario");
    if (!r.valid()) return;
    r.string("$schema", false, 0);  // editor hint only
    if (const json* v = r.field("schema_version", true, "1")) {
      if (!(v->is_number() && v->get<double>() == kSchemaVersion)) {
        errors_.expected(r.child("schema_version"),
                         "1 (the schema version this loader reads)", *v);
      }
    }
    if (auto v = r.string("name", true, 1, "a non-empty string")) s->name = *v;
    if (auto v = r.string("description", false, 0)) s->description = *v;
    if (const json* v = r.field("location", true, "an object (geodetic point)")) {
      geodetic(*v, r.child("location"), &s->location);
    }
    utc(r, s);
    if (auto v = r.number("dut1_s", Range::closed(-0.9, 0.9), 0.0)) s->dut1_s = *v;  // the ABI's range (atmo.h)
    if (const json* v = r.field("cameras", true, "an array of at least 1 camera")) {
      cameras(*v, r.child("cameras"), s);
    }
    if (const json* v = r.field("atmosphere", false, "")) {
      atmosphere(*v, r.child("atmosphere"), &s->atmosphere);
    }
    if (const json* v = r.field("terrain", false, "")) {
      terrain(*v, r.child("terrain"), &s->terrain.emplace());
    }
    if (const json* v = r.field("clouds", false, "")) {
      clouds(*v, r.child("clouds"), &s->clouds);
    }
    if (const json* v = r.field("fog", false, "")) {
      fog(*v, r.child("fog"), &s->fog.emplace());
    }
    if (const json* v = r.field("lights", false, "")) {
      lights(*v, r.child("lights"), s->terrain, &s->lights.emplace());
    }
    if (const json* v = r.field("objects", false, "")) objects(*v, r.child("objects"), &s->objects);
    if (const json* v = r.field("night_sky", false, "")) {
      night_sky(*v, r.child("night_sky"), &s->night_sky.emplace());
      if (!s->night_sky->moon) {
        s->not_yet_supported.push_back(
            {r.child("night_sky") + "/moon",
             "moon: false is not supported: the Moon is part of the sky pass and is drawn whenever it is up"});
      }
    }
    if (const json* v = r.field("render", false, "")) render(*v, r.child("render"), &s->render);
    if (const json* v = r.field("outputs", false, "")) outputs(*v, r.child("outputs"), &s->outputs);
    if (const json* v = r.field("expectations", false, "")) {
      expectations(*v, r.child("expectations"), s->cameras, &s->expectations);
    }
    if (const json* v = r.field("channels", false, "")) channels(*v, r.child("channels"), &s->channels.emplace());
    if (const json* v = r.field("flight", false, "")) flight(*v, r.child("flight"), &s->flight.emplace());
  }

 private:
  void utc(ObjectReader& r, Scenario* s) {
    static const std::string kWhat =
        "an ISO 8601 time \"YYYY-MM-DDThh:mm:ss[.fff]Z\" (or with a \"+hh:mm\" offset)";
    const json* v = r.field("utc", true, kWhat);
    if (!v) return;
    if (!v->is_string()) {
      errors_.expected(r.child("utc"), kWhat, *v);
      return;
    }
    std::string why;
    if (auto t = parse_iso8601_utc(v->get<std::string>(), &why)) {
      s->utc = v->get<std::string>();
      s->utc_posix_s = *t;
    } else {
      // A shape error would only repeat kWhat; anything else adds to it.
      const bool shape = why.rfind("not of the form", 0) == 0;
      errors_.add(r.child("utc"), "expected " + kWhat + ", found " + detail::describe(*v) +
                                      (shape ? "" : " (" + why + ")"));
    }
  }

  void geodetic(const json& v, const std::string& ptr, GeodeticPoint* g) {
    ObjectReader r(errors_, v, ptr, shape("geodetic"), "geodetic point");
    if (!r.valid()) return;
    if (auto x = r.number("latitude_deg", kLatitude, std::nullopt)) g->latitude_deg = *x;
    if (auto x = r.number("longitude_deg", kLongitude, std::nullopt)) g->longitude_deg = *x;
    if (auto x = r.number("height_m", kHeight, std::nullopt)) g->height_m = *x;
  }

  template <size_t N>
  void vec(const json& v, const std::string& ptr, const Range& range, std::array<double, N>* out) {
    const std::string each = range.text().empty() ? "numbers" : "numbers " + range.text();
    if (!v.is_array() || v.size() != N) {
      errors_.expected(ptr, "an array of " + std::to_string(N) + " " + each, v);
      return;
    }
    for (size_t i = 0; i < N; ++i) {
      if (auto x = detail::read_number(errors_, v[i], ptr + "/" + std::to_string(i), range)) {
        (*out)[i] = *x;
      }
    }
  }

  void position(const json& v, const std::string& ptr, Position* p) {
    ObjectReader r(errors_, v, ptr, shape("position"), "position");
    if (!r.valid()) return;
    const json* enu = r.field("enu_m", false, "");
    const json* geo = r.field("geodetic", false, "");
    if (enu && geo) {
      errors_.add(ptr, "expected exactly one of \"enu_m\" or \"geodetic\", found both");
    } else if (!enu && !geo) {
      errors_.add(ptr, "expected exactly one of \"enu_m\" or \"geodetic\", found neither");
    }
    if (enu) {
      p->kind = Position::Kind::Enu;
      vec<3>(*enu, r.child("enu_m"), Range::any(), &p->enu_m);
    }
    if (geo) {
      p->kind = Position::Kind::Geodetic;
      geodetic(*geo, r.child("geodetic"), &p->geodetic);
    }
  }

  void cameras(const json& v, const std::string& ptr, Scenario* s) {
    if (!v.is_array() || v.empty()) {
      errors_.expected(ptr, "an array of at least 1 camera", v);
      return;
    }
    std::set<std::string> names;
    for (size_t i = 0; i < v.size(); ++i) {
      const std::string cp = ptr + "/" + std::to_string(i);
      Camera c;
      ObjectReader r(errors_, v[i], cp, shape("camera"), "camera");
      if (!r.valid()) continue;
      if (auto x = r.string("name", true, 1,
                            "a name of letters, digits, '_' or '-' (at most 64, "
                            "starting with a letter or digit)",
                            camera_name_ok)) {
        c.name = *x;
        if (!names.insert(c.name).second) {
          errors_.add(r.child("name"), "expected a name no other camera has, found \"" +
                                           c.name + "\" again");
        }
      }
      if (const json* p = r.field("position", true, "an object with \"enu_m\" or \"geodetic\"")) {
        position(*p, r.child("position"), &c.position);
      }
      if (auto x = r.number("heading_deg", Range::closed(-360, 360), std::nullopt)) c.heading_deg = *x;
      if (auto x = r.number("pitch_deg", Range::closed(-90, 90), std::nullopt)) c.pitch_deg = *x;
      if (auto x = r.number("roll_deg", Range::closed(-180, 180), 0.0)) c.roll_deg = *x;
      if (auto x = r.number("vertical_fov_deg", Range::open(0, 180), std::nullopt)) {
        c.vertical_fov_deg = *x;
      }
      if (auto x = r.integer("width", 1, 8192, std::nullopt)) c.width = static_cast<int>(*x);
      if (auto x = r.integer("height", 1, 8192, std::nullopt)) c.height = static_cast<int>(*x);
      const auto near_m = r.number("near_m", Range::above(0), std::nullopt);
      const auto far_m = r.number("far_m", Range::above(0), std::nullopt);
      if (near_m) c.near_m = *near_m;
      if (far_m) c.far_m = *far_m;
      if (near_m && far_m && !(*far_m > *near_m)) {
        errors_.expected(r.child("far_m"), "a number > near_m (" + detail::describe(*near_m) + ")",
                         *far_m);
      }
      if (r.field("exposure_ev100", false, "")) {
        c.exposure_ev100 = r.number("exposure_ev100", Range::closed(-20, 30), std::nullopt);
      }
      s->cameras.push_back(std::move(c));
    }
  }

  void atmosphere(const json& v, const std::string& ptr, Atmosphere* a) {
    ObjectReader r(errors_, v, ptr, shape("atmosphere"), "atmosphere");
    if (auto x = r.number("visibility_m", Range::closed(50, 500000), 40000.0)) a->visibility_m = *x;
    if (auto x = r.number("aerosol_scale_height_m", Range::closed(100, 20000), 1200.0)) {
      a->aerosol_scale_height_m = *x;
    }
    if (auto x = r.number("ground_albedo", Range::closed(0, 1), 0.1)) a->ground_albedo = *x;
  }

  void terrain(const json& v, const std::string& ptr, Terrain* t) {
    ObjectReader r(errors_, v, ptr, shape("terrain"), "terrain");
    if (auto x = r.choice("kind", {"hills", "flat", "none"}, std::nullopt)) {
      t->kind = static_cast<TerrainKind>(*x);
    }
    if (auto x = r.integer("seed", 0, kMaxSeed, 0)) t->seed = static_cast<std::uint64_t>(*x);
    if (auto x = r.number("size_m", Range::closed(100, 200000), 20000.0)) t->size_m = *x;
    if (auto x = r.number("relief_m", Range::closed(0, 5000), 150.0)) t->relief_m = *x;
    if (auto x = r.boolean("runway", false)) t->runway = *x;
    if (auto x = r.number("runway_heading_deg", Range::closed(0, 360), 90.0)) {
      t->runway_heading_deg = *x;
    }
  }

  void clouds(const json& v, const std::string& ptr, std::vector<CloudLayer>* layers) {
    if (!v.is_array()) {
      errors_.expected(ptr, "an array of cloud layers", v);
      return;
    }
    for (size_t i = 0; i < v.size(); ++i) {
      CloudLayer c;
      ObjectReader r(errors_, v[i], ptr + "/" + std::to_string(i), shape("cloud_layer"),
                     "cloud layer");
      if (!r.valid()) continue;
      const auto type =
          r.choice("type", {"cumulus", "stratus", "overcast", "cirrus", "vdb"}, std::nullopt);
      if (type) c.type = static_cast<CloudType>(*type);
      const bool vdb = type && c.type == CloudType::Vdb;
      const bool layer = type && !vdb;
      if (auto x = r.integer("seed", 0, kMaxSeed, 0)) c.seed = static_cast<std::uint64_t>(*x);

      // Layer fields: required for procedural types, refused for vdb.
      if (vdb) {
        for (const char* k : {"coverage_oktas", "base_m", "top_m", "area_m"}) {
          if (r.field(k, false, "")) {
            errors_.add(r.child(k), "unexpected on a \"vdb\" layer: coverage_oktas, base_m, "
                                    "top_m and area_m are for procedural layers only");
          }
        }
      } else {
        // With no valid type, read them leniently: the type error is enough.
        const std::optional<std::int64_t> no_int = layer ? std::nullopt : std::optional<std::int64_t>(0);
        const std::optional<double> no_num = layer ? std::nullopt : std::optional<double>(0.0);
        const auto oktas = r.integer("coverage_oktas", 0, 8, no_int);
        const auto base = r.number("base_m", Range::closed(0, 20000), no_num);
        const auto top = r.number("top_m", Range::closed(0, 20000), no_num);
        if (oktas) c.coverage_oktas = static_cast<int>(*oktas);
        if (base) c.base_m = *base;
        if (top) c.top_m = *top;
        if (auto a = r.number("area_m", Range::closed(500, 400000), 0.0)) c.area_m = *a;
        if (layer && base && top && !(*top > *base)) {
          errors_.expected(r.child("top_m"), "a number > base_m (" + detail::describe(*base) + ")",
                           *top);
        }
      }
      // Volume fields: required for vdb, refused for procedural types.
      if (layer) {
        for (const char* k : {"vdb_file", "position", "scale", "heading_deg", "density_scale"}) {
          if (r.field(k, false, "")) {
            errors_.add(r.child(k), std::string("unexpected on a \"") + to_string(c.type) +
                                        "\" layer: vdb_file, position, scale, heading_deg and density_scale "
                                        "are for type \"vdb\" only");
          }
        }
      } else {
        if (auto x = r.string("vdb_file", vdb, 1, "a non-empty path to a .vdb file")) c.vdb_file = *x;
        if (const json* p = r.field("position", vdb, "an object with \"enu_m\" or \"geodetic\"")) {
          position(*p, r.child("position"), &c.position);
        }
        if (auto x = r.number("scale", Range::above(0), 1.0)) c.scale = *x;
        if (auto x = r.number("heading_deg", Range::closed(0, 360), 0.0)) c.heading_deg = *x;
        if (auto x = r.number("density_scale", Range::above(0), 1.0)) c.density_scale = *x;
      }
      layers->push_back(std::move(c));
    }
  }

  void fog(const json& v, const std::string& ptr, Fog* f) {
    ObjectReader r(errors_, v, ptr, shape("fog"), "fog");
    if (auto x = r.number("visibility_m", Range::closed(10, 5000), std::nullopt)) f->visibility_m = *x;
    if (auto x = r.number("top_m", Range{0.0, 3000.0, true, false}, std::nullopt)) f->top_m = *x;
  }

  void lights(const json& v, const std::string& ptr, const std::optional<Terrain>& terrain, Lights* l) {
    ObjectReader r(errors_, v, ptr, shape("lights"), "lights");
    if (auto x = r.boolean("runway_approach", false)) l->runway_approach = *x;
    if (const json* a = r.field("airport", false, "")) {
      airport(*a, r.child("airport"), terrain, &l->airport.emplace());
    }
    if (const json* t = r.field("town", false, "")) town(*t, r.child("town"), &l->town.emplace());
    const json* points = r.field("points", false, "");
    if (!points) return;
    if (!points->is_array()) {
      errors_.expected(r.child("points"), "an array of light points", *points);
      return;
    }
    for (size_t i = 0; i < points->size(); ++i) {
      LightPoint p;
      ObjectReader pr(errors_, (*points)[i], r.child("points") + "/" + std::to_string(i),
                      shape("light_point"), "light point");
      if (!pr.valid()) continue;
      if (const json* e = pr.field("enu_m", true, "an array of 3 numbers")) {
        vec<3>(*e, pr.child("enu_m"), Range::any(), &p.enu_m);
      }
      if (auto x = pr.number("intensity_cd", Range::above(0), std::nullopt)) p.intensity_cd = *x;
      if (const json* c = pr.field("color", false, "")) {
        vec<3>(*c, pr.child("color"), Range::closed(0, 1), &p.color);
      }
      l->points.push_back(p);
    }
  }

  // Limits: real runways (ICAO codes 1-4 run ~800-5 500 m long, 18-60 m wide) with a margin; the layout's
  // taxiways sit 180 m beside the first runway.
  void airport(const json& v, const std::string& ptr, const std::optional<Terrain>& terrain, AirportLights* a) {
    ObjectReader r(errors_, v, ptr, shape("airport_lights"), "airport lights");
    if (!r.valid()) return;
    if (auto x = r.number("taxiway_length_m", Range::closed(0, 50000), 8000.0)) a->taxiway_length_m = *x;
    const json* runways = r.field("runways", false, "");
    if (!runways) {
      // The terrain's runway (terrain.cpp: centred on the origin, 3000 x 45 m, along its heading).
      AirportRunway on_terrain;
      on_terrain.heading_deg = terrain ? terrain->runway_heading_deg : 90.0;
      a->runways.push_back(on_terrain);
      return;
    }
    if (!runways->is_array() || runways->empty() || runways->size() > 8) {
      errors_.expected(r.child("runways"), "an array of 1 to 8 runways", *runways);
      return;
    }
    for (size_t i = 0; i < runways->size(); ++i) {
      AirportRunway w;
      ObjectReader rr(errors_, (*runways)[i], r.child("runways") + "/" + std::to_string(i), shape("airport_runway"),
                      "runway");
      if (!rr.valid()) continue;
      if (const json* c = rr.field("centre_enu_m", false, "")) {
        vec<2>(*c, rr.child("centre_enu_m"), Range::any(), &w.centre_enu_m);
      }
      if (auto x = rr.number("heading_deg", Range::closed(0, 360), 90.0)) w.heading_deg = *x;
      if (auto x = rr.number("length_m", Range::closed(300, 6000), 3000.0)) w.length_m = *x;
      if (auto x = rr.number("width_m", Range::closed(10, 100), 45.0)) w.width_m = *x;
      a->runways.push_back(w);
    }
  }

  void town(const json& v, const std::string& ptr, TownLights* t) {
    ObjectReader r(errors_, v, ptr, shape("town_lights"), "town lights");
    if (!r.valid()) return;
    if (const json* c = r.field("centre_enu_m", false, "")) {
      vec<2>(*c, r.child("centre_enu_m"), Range::any(), &t->centre_enu_m);
    }
    // At most what set_lights takes in all (ATMO_LIGHTS_MAX).
    if (auto x = r.integer("lights", 1, 65536, 10000)) t->lights = static_cast<std::uint32_t>(*x);
    if (auto x = r.number("lights_per_km2", Range::closed(10, 100000), 1300.0)) t->lights_per_km2 = *x;
    if (auto x = r.integer("seed", 0, kMaxSeed, 1)) t->seed = static_cast<std::uint64_t>(*x);
  }

  void objects(const json& v, const std::string& ptr, std::vector<SceneObject>* out) {
    if (!v.is_array() || v.size() > kMaxObjects) {
      errors_.expected(ptr, "an array of at most " + std::to_string(kMaxObjects) + " objects", v);
      return;
    }
    for (size_t i = 0; i < v.size(); ++i) {
      SceneObject o;
      ObjectReader r(errors_, v[i], ptr + "/" + std::to_string(i), shape("object"), "object");
      if (!r.valid()) continue;
      if (auto x = r.string("spheres", true, 1, "a path to a sphere-set file (\"atmo-spheres-1\")")) o.spheres = *x;
      if (auto x = r.string("mesh", true, 1, "a path to an OBJ or PLY mesh")) o.mesh = *x;
      if (const json* p = r.field("position_m", true, "an array of 3 numbers (east, north, up)")) {
        vec<3>(*p, r.child("position_m"), Range::any(), &o.position_m);
      }
      if (auto x = r.number("heading_deg", Range::closed(-360, 360), 0.0)) o.heading_deg = *x;
      if (const json* a = r.field("albedo", false, "")) vec<3>(*a, r.child("albedo"), Range::closed(0, 1), &o.albedo);
      out->push_back(std::move(o));
    }
  }

  void night_sky(const json& v, const std::string& ptr, NightSky* n) {
    ObjectReader r(errors_, v, ptr, shape("night_sky"), "night_sky");
    if (auto x = r.boolean("stars", true)) n->stars = *x;
    if (auto x = r.boolean("moon", true)) n->moon = *x;
  }

  void render(const json& v, const std::string& ptr, Render* rd) {
    ObjectReader r(errors_, v, ptr, shape("render"), "render");
    if (auto x = r.choice("depth_convention", {"standard", "reversed", "logarithmic"}, 1)) {
      rd->depth_convention = static_cast<DepthConvention>(*x);
    }
    if (r.field("exposure_ev100", false, "")) {
      rd->exposure_ev100 = r.number("exposure_ev100", Range::closed(-20, 30), std::nullopt);
    }
    if (auto x = r.choice("output", {"linear_hdr", "display_srgb"}, 0)) {
      rd->output = static_cast<OutputEncoding>(*x);
    }
    if (auto x = r.choice("cloud_draw_mode", {"auto", "direct", "layer", "impostors"}, 0)) {
      rd->cloud_draw_mode = static_cast<CloudDrawMode>(*x);
    }
  }

  void outputs(const json& v, const std::string& ptr, Outputs* o) {
    ObjectReader r(errors_, v, ptr, shape("outputs"), "outputs");
    if (auto x = r.boolean("exr", true)) o->exr = *x;
    if (auto x = r.boolean("png", true)) o->png = *x;
  }

  void expectations(const json& v, const std::string& ptr, const std::vector<Camera>& cameras, Expectations* e) {
    ObjectReader r(errors_, v, ptr, shape("expectations"), "expectations");
    if (!r.valid()) return;
    if (auto x = r.boolean("finite", true)) e->finite = *x;
    if (const json* ref = r.field("reference", false, "")) {
      Reference& out = e->reference.emplace();
      ObjectReader rr(errors_, *ref, r.child("reference"), shape("reference"), "reference");
      if (auto x = rr.string("image", true, 1, "a path to a .png file, relative to the scenario",
                             png_name_ok)) {
        out.image = *x;
      }
      if (rr.choice("metric", {"psnr_db"}, 0)) out.metric = "psnr_db";
      if (auto x = rr.number("min_psnr_db", Range::above(0), std::nullopt)) out.min_psnr_db = *x;
    }
    if (const json* checks = r.field("luminance_checks", false, "")) {
      luminance_checks(*checks, r.child("luminance_checks"), cameras, &e->luminance_checks);
    }
    if (r.field("max_frame_ms", false, "")) {
      e->max_frame_ms = r.number("max_frame_ms", Range::above(0), std::nullopt);
    }
  }

  void luminance_checks(const json& v, const std::string& ptr, const std::vector<Camera>& cameras,
                        std::vector<LuminanceCheck>* out) {
    if (!v.is_array()) {
      errors_.expected(ptr, "an array of luminance checks", v);
      return;
    }
    for (size_t i = 0; i < v.size(); ++i) {
      LuminanceCheck c;
      ObjectReader r(errors_, v[i], ptr + "/" + std::to_string(i), shape("luminance_check"),
                     "luminance check");
      if (!r.valid()) continue;
      if (auto x = r.string("name", true, 1, "a non-empty string")) c.name = *x;
      if (auto x = r.number("u", Range::closed(0, 1), std::nullopt)) c.u = *x;
      if (auto x = r.number("v", Range::closed(0, 1), std::nullopt)) c.v = *x;
      const auto lo = r.number("min_cd_m2", Range::at_least(0), std::nullopt);
      const auto hi = r.number("max_cd_m2", Range::at_least(0), std::nullopt);
      if (lo) c.min_cd_m2 = *lo;
      if (hi) c.max_cd_m2 = *hi;
      if (lo && hi && *hi < *lo) {
        errors_.expected(r.child("max_cd_m2"),
                         "a number >= min_cd_m2 (" + detail::describe(*lo) + ")", *hi);
      }
      if (auto x = r.string("camera", false, 1, "a camera's name")) {
        const bool named =
            std::any_of(cameras.begin(), cameras.end(), [&](const Camera& cam) { return cam.name == *x; });
        std::string names;
        for (const Camera& cam : cameras) names += (names.empty() ? "" : ", ") + cam.name;
        if (named)
          c.camera = *x;
        else
          errors_.expected(r.child("camera"), "the name of one of the cameras (" + names + ")", json(*x));
      }
      out->push_back(std::move(c));
    }
  }

  void channels(const json& v, const std::string& ptr, Channels* c) {
    ObjectReader r(errors_, v, ptr, shape("channels"), "channels");
    if (!r.valid()) return;
    if (auto x = r.choice("layout", {"wrap"}, 0)) c->layout = static_cast<ChannelLayout>(*x);
    if (auto x = r.integer("count", 1, 64, 3)) c->count = static_cast<int>(*x);
    const auto hfov = r.number("horizontal_fov_deg", Range::open(0, 180), std::nullopt);
    if (hfov) c->horizontal_fov_deg = *hfov;
    if (auto x = r.number("vertical_fov_deg", Range::open(0, 180), std::nullopt)) c->vertical_fov_deg = *x;
    const auto overlap = r.number("overlap_deg", Range{0.0, 180.0, false, true}, 0.0);
    if (overlap) c->overlap_deg = *overlap;
    if (hfov && overlap && !(*overlap < *hfov)) {
      errors_.expected(r.child("overlap_deg"),
                       "a number < horizontal_fov_deg (" + detail::describe(*hfov) + ")", *overlap);
    }
    if (auto x = r.integer("width", 1, 8192, std::nullopt)) c->width = static_cast<int>(*x);
    if (auto x = r.integer("height", 1, 8192, std::nullopt)) c->height = static_cast<int>(*x);
    const auto near_m = r.number("near_m", Range::above(0), 1.0);
    const auto far_m = r.number("far_m", Range::above(0), 100000.0);
    if (near_m) c->near_m = *near_m;
    if (far_m) c->far_m = *far_m;
    if (near_m && far_m && !(*far_m > *near_m)) {
      errors_.expected(r.child("far_m"), "a number > near_m (" + detail::describe(*near_m) + ")", *far_m);
    }
  }

  void flight(const json& v, const std::string& ptr, Flight* f) {
    ObjectReader r(errors_, v, ptr, shape("flight"), "flight");
    if (!r.valid()) return;
    if (auto x = r.number("frame_rate_hz", Range{0.0, 1000.0, true, false}, std::nullopt)) f->frame_rate_hz = *x;
    const bool frames_given = r.field("frames", false, "") != nullptr;
    const auto frames = r.integer("frames", 1, 1000000, 0);
    if (const json* k = r.field("keyframes", true, "an array of at least 1 keyframe")) {
      keyframes(*k, r.child("keyframes"), &f->keyframes);
    }
    if (frames_given && frames) {
      f->frames = *frames;
    } else if (!frames_given && !f->keyframes.empty()) {
      const double last = f->keyframes.back().t_s * f->frame_rate_hz;
      f->frames = static_cast<std::int64_t>(std::floor(last + 1e-9)) + 1;
      if (f->frames > 1000000) {
        errors_.add(r.child("keyframes"), "expected keyframes spanning at most 10^6 frames at frame_rate_hz, found " +
                                              std::to_string(f->frames) + " (give \"frames\")");
      }
    }
    if (const json* e = r.field("events", false, "")) events(*e, r.child("events"), &f->events);
  }

  void keyframes(const json& v, const std::string& ptr, std::vector<FlightKeyframe>* out) {
    if (!v.is_array() || v.empty()) {
      errors_.expected(ptr, "an array of at least 1 keyframe", v);
      return;
    }
    std::optional<double> previous_t;
    for (size_t i = 0; i < v.size(); ++i) {
      FlightKeyframe k;
      ObjectReader r(errors_, v[i], ptr + "/" + std::to_string(i), shape("flight_keyframe"), "flight keyframe");
      if (!r.valid()) continue;
      if (auto x = r.number("t_s", Range::at_least(0), std::nullopt)) {
        k.t_s = *x;
        if (previous_t && !(*x > *previous_t)) {
          errors_.expected(r.child("t_s"),
                           "a number > the previous keyframe's t_s (" + detail::describe(*previous_t) + ")", *x);
        }
        previous_t = *x;
      }
      if (const json* p = r.field("position", true, "an object with \"enu_m\" or \"geodetic\"")) {
        position(*p, r.child("position"), &k.position);
      }
      if (auto x = r.number("heading_deg", Range::closed(-360, 360), std::nullopt)) k.heading_deg = *x;
      if (auto x = r.number("pitch_deg", Range::closed(-90, 90), 0.0)) k.pitch_deg = *x;
      out->push_back(std::move(k));
    }
  }

  void events(const json& v, const std::string& ptr, std::vector<FlightEvent>* out) {
    if (!v.is_array()) {
      errors_.expected(ptr, "an array of flight events", v);
      return;
    }
    for (size_t i = 0; i < v.size(); ++i) {
      FlightEvent e;
      const std::string ep = ptr + "/" + std::to_string(i);
      ObjectReader r(errors_, v[i], ep, shape("flight_event"), "flight event");
      if (!r.valid()) continue;
      if (auto x = r.integer("at_frame", 0, 1000000000, std::nullopt)) e.at_frame = *x;
      const json* a = r.field("atmosphere", false, "");
      const json* c = r.field("clouds", false, "");
      if (!a && !c) errors_.add(ep, "expected at least one of \"atmosphere\" or \"clouds\", found neither");
      if (a) atmosphere(*a, r.child("atmosphere"), &e.atmosphere.emplace());
      if (c) clouds(*c, r.child("clouds"), &e.clouds.emplace());
      out->push_back(std::move(e));
    }
  }

  detail::Errors errors_;
};

}  // namespace

const std::vector<ObjectShape>& object_shapes() { return kShapes; }

const std::vector<std::string>& top_level_fields() { return shape("scenario"); }

LoadResult parse_scenario(const std::string& json_text, const std::string& file_label) {
  LoadResult result;
  json root;
  std::string syntax;
  if (!detail::parse_json(json_text, &root, &syntax)) {
    result.error = file_label + ": " + syntax;
    return result;
  }
  Scenario s;
  s.source_file = file_label;
  s.source_dir = std::filesystem::path(file_label).parent_path().string();
  Loader loader(file_label);
  loader.scenario(root, &s);
  if (!loader.errors().empty()) {
    result.error = loader.errors().joined();
    return result;
  }
  result.scenario = std::move(s);
  return result;
}

bool is_openscenario_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".xosc";
}

LoadResult load_scenario_file(const std::string& path, const ImportOptions& options) {
  if (is_openscenario_path(path)) return load_openscenario_file(path, options);
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    return {std::nullopt, path + ": cannot open: " + (err ? std::strerror(err) : "unknown error")};
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return {std::nullopt, path + ": read error"};
  return parse_scenario(text.str(), path);
}

double cloud_layer_area_m(const Scenario& scenario, const CloudLayer& layer) {
  if (layer.area_m > 0.0) return layer.area_m;
  return scenario.terrain ? scenario.terrain->size_m : 20000.0;
}

std::string resolve_path(const Scenario& scenario, const std::string& relative) {
  const std::filesystem::path p(relative);
  if (p.is_absolute() || scenario.source_dir.empty()) return relative;
  // Absolute: the plugin resolves relative paths against its asset root, not the working directory.
  return std::filesystem::absolute(std::filesystem::path(scenario.source_dir) / p).lexically_normal().string();
}

const char* to_string(TerrainKind k) {
  switch (k) {
    case TerrainKind::Hills: return "hills";
    case TerrainKind::Flat: return "flat";
    case TerrainKind::None: return "none";
  }
  return "?";
}

const char* to_string(CloudType t) {
  switch (t) {
    case CloudType::Cumulus: return "cumulus";
    case CloudType::Stratus: return "stratus";
    case CloudType::Overcast: return "overcast";
    case CloudType::Cirrus: return "cirrus";
    case CloudType::Vdb: return "vdb";
  }
  return "?";
}

const char* to_string(DepthConvention c) {
  switch (c) {
    case DepthConvention::Standard: return "standard";
    case DepthConvention::Reversed: return "reversed";
    case DepthConvention::Logarithmic: return "logarithmic";
  }
  return "?";
}

const char* to_string(ChannelLayout l) {
  switch (l) {
    case ChannelLayout::Wrap: return "wrap";
  }
  return "?";
}

const char* to_string(OutputEncoding e) {
  switch (e) {
    case OutputEncoding::LinearHdr: return "linear_hdr";
    case OutputEncoding::DisplaySrgb: return "display_srgb";
  }
  return "?";
}

}  // namespace atmo::scenario
