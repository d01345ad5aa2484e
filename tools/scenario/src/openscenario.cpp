// OpenSCENARIO import (openscenario.h): pugixml reads the file; the first
// Environment found is mapped onto a Scenario with one default camera.
// Internally the first error throws ImportError, carrying the finished line.
#include "atmo_scenario/openscenario.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <pugixml.hpp>

#include "atmo_scenario/units.h"
#include "core/astro/sky_bodies.h"

namespace atmo::scenario {

namespace fs = std::filesystem;

namespace {

constexpr double kPi = units::kPi;

struct ImportError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string format_number(double v, int digits = 6) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string in_quotes(const std::string& s) { return "\"" + s + "\""; }

// "line L, column C" of a byte offset (columns count bytes, from 1).
std::string line_column(const std::string& text, std::ptrdiff_t offset) {
  const size_t end = std::min(static_cast<size_t>(std::max<std::ptrdiff_t>(offset, 0)), text.size());
  size_t line = 1, line_start = 0;
  for (size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(end - line_start + 1);
}

// Larger files are refused: a scenario, road or catalog file is kilobytes to a few megabytes.
constexpr std::uintmax_t kMaxFileBytes = 256u << 20;

// Regular files only: a path written in the file may name a device (/dev/zero) or a directory.
std::optional<std::string> read_file(const std::string& path, std::string* error) {
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_regular_file(path, ec)) {
    *error = path + ": not a regular file";
    return std::nullopt;
  }
  if (const std::uintmax_t bytes = fs::file_size(path, ec); !ec && bytes > kMaxFileBytes) {
    *error = path + ": " + std::to_string(bytes) + " bytes, more than " + std::to_string(kMaxFileBytes) + " allowed";
    return std::nullopt;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    *error = path + ": cannot open: " + (err ? std::strerror(err) : "unknown error");
    return std::nullopt;
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) {
    *error = path + ": read error";
    return std::nullopt;
  }
  return text.str();
}

// One parsed XML file: its label (the path as given) and text for messages.
struct Document {
  std::string label;
  std::string text;
  pugi::xml_document xml;
};

// nullptr and *error ("<label>: line L, column C: XML syntax error: ...") when malformed.
std::unique_ptr<Document> parse_xml(std::string text, const std::string& label, std::string* error) {
  auto doc = std::make_unique<Document>();
  doc->label = label;
  doc->text = std::move(text);
  const pugi::xml_parse_result r =
      doc->xml.load_buffer(doc->text.data(), doc->text.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!r) {
    *error = label + ": " + line_column(doc->text, r.offset) + ": XML syntax error: " + r.description();
    return nullptr;
  }
  return doc;
}

std::string element_path(pugi::xml_node n) {
  std::string path;
  for (; n && n.type() == pugi::node_element; n = n.parent()) path = "/" + std::string(n.name()) + path;
  return path;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

// A whole string as a finite double (xsd:double's spellings of infinity and NaN are refused: no finite size).
std::optional<double> to_number(const std::string& s) {
  if (s.empty()) return std::nullopt;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(v)) return std::nullopt;
  // strtod also reads hexadecimal and "inf"/"nan": XML numbers are decimal.
  if (s.find_first_of("xXiInN") != std::string::npos) return std::nullopt;
  return v;
}

struct Interval {
  double lo, hi;
  bool lo_open = false;
  bool contains(double v) const { return (lo_open ? v > lo : v >= lo) && v <= hi; }
};

class Importer {
 public:
  Importer(const ImportOptions& options, Scenario* s) : options_(options), s_(s) {}

  void run(std::unique_ptr<Document> main) {
    main_ = main.get();
    docs_.push_back(std::move(main));
    const pugi::xml_node root = main_->xml.document_element();
    if (std::string(root.name()) != "OpenSCENARIO") {
      fail(root, "", "expected the root element OpenSCENARIO, found " + in_quotes(root.name()));
    }
    header(root);
    declare_parameters(root.child("ParameterDeclarations"));
    const pugi::xml_node environment = find_environment(root);
    s_->source_file = main_->label;
    s_->source_dir = fs::path(main_->label).parent_path().string();
    place(root, environment);
    time_of_day(environment);
    weather(environment);
    if (const pugi::xml_node road = environment.child("RoadCondition")) {
      note(road, "ignored: the road's friction and wetness are the vehicle simulation's, not the atmosphere's");
    }
    default_scene();
    sun(environment.child("Weather").child("Sun"));
  }

 private:
  // --- errors and attributes ---------------------------------------------------------------------

  const Document& doc_of(pugi::xml_node n) const {
    for (const auto& d : docs_) {
      if (n.root() == d->xml.root()) return *d;
    }
    return *main_;
  }

  [[noreturn]] void fail(pugi::xml_node n, const std::string& attribute, const std::string& message) const {
    const Document& d = doc_of(n);
    // offset_debug points at the element's name; the column names its '<'.
    throw ImportError(d.label + ": " + line_column(d.text, n.offset_debug() - 1) + ": " + element_path(n) +
                      (attribute.empty() ? "" : "@" + attribute) + ": " + message);
  }

  [[noreturn]] void fail_value(pugi::xml_node n, const std::string& attribute, const std::string& expected,
                               const std::string& raw, const std::string& value) const {
    const std::string found = raw == value ? in_quotes(raw) : in_quotes(raw) + " (= " + in_quotes(value) + ")";
    fail(n, attribute, "expected " + expected + ", found " + found);
  }

  void note(pugi::xml_node n, const std::string& message) {
    s_->import_notes.push_back({element_path(n), message});
  }
  void not_drawn(pugi::xml_node n, const std::string& message) {
    s_->not_yet_supported.push_back({element_path(n), "accepted, not drawn: " + message});
  }

  // The attribute's text, a "$name" parameter reference resolved; nullopt when absent.
  std::optional<std::string> text(pugi::xml_node n, const char* attribute, bool required = false,
                                  std::string* raw_out = nullptr) const {
    const pugi::xml_attribute a = n.attribute(attribute);
    if (!a) {
      if (required) fail(n, attribute, "missing (required)");
      return std::nullopt;
    }
    const std::string raw = trim(a.value());
    if (raw_out) *raw_out = raw;
    if (raw.rfind("${", 0) == 0) fail(n, attribute, "parameter expressions (" + in_quotes(raw) + ") are not supported");
    if (raw.empty() || raw[0] != '$') return raw;
    const auto p = parameters_.find(raw.substr(1));
    if (p == parameters_.end()) fail(n, attribute, "no parameter " + in_quotes(raw.substr(1)) + " is declared");
    return p->second;
  }

  std::optional<double> number(pugi::xml_node n, const char* attribute, const Interval& range,
                               const std::string& expected, bool required = false) const {
    std::string raw;
    const auto t = text(n, attribute, required, &raw);
    if (!t) return std::nullopt;
    const auto v = to_number(*t);
    if (!v || !range.contains(*v)) fail_value(n, attribute, expected, raw, *t);
    return v;
  }

  std::optional<size_t> choice(pugi::xml_node n, const char* attribute, const std::vector<std::string>& options,
                               bool required = false) const {
    std::string raw;
    const auto t = text(n, attribute, required, &raw);
    if (!t) return std::nullopt;
    const auto it = std::find(options.begin(), options.end(), *t);
    if (it == options.end()) {
      std::string list;
      for (const std::string& o : options) list += (list.empty() ? "" : ", ") + o;
      fail_value(n, attribute, "one of " + list, raw, *t);
    }
    return static_cast<size_t>(it - options.begin());
  }

  std::optional<bool> boolean(pugi::xml_node n, const char* attribute, bool required = false) const {
    const auto i = choice(n, attribute, {"false", "true", "0", "1"}, required);
    if (!i) return std::nullopt;
    return *i % 2 == 1;
  }

  // --- structure ---------------------------------------------------------------------------------

  void header(pugi::xml_node root) {
    const pugi::xml_node h = root.child("FileHeader");
    if (!h) fail(root, "", "expected a FileHeader element, found none");
    const auto major = number(h, "revMajor", {1, 1}, "1 (OpenSCENARIO 1.x)");
    const auto minor = number(h, "revMinor", {0, 1e6}, "a minor version >= 0");
    version_ = "OpenSCENARIO " + format_number(major.value_or(1)) + "." + format_number(minor.value_or(0));
    s_->name = fs::path(main_->label).stem().string();
    const std::string description = trim(h.attribute("description").value());
    s_->description = version_ + " environment" + (description.empty() ? "" : ": " + description);
  }

  void declare_parameters(pugi::xml_node declarations) {
    for (pugi::xml_node p : declarations.children("ParameterDeclaration")) {
      std::string name = trim(p.attribute("name").value());
      if (!name.empty() && name[0] == '$') name.erase(0, 1);  // 1.0 examples write the '$' in the name
      if (name.empty()) fail(p, "name", "expected a parameter name, found none");
      if (!p.attribute("value")) fail(p, "value", "missing (required)");
      parameters_[name] = trim(p.attribute("value").value());
    }
  }

  // The first EnvironmentAction in document order (the Init's come before the Story's), else the first
  // Environment of a Catalog.
  pugi::xml_node find_environment(pugi::xml_node root) {
    std::vector<pugi::xml_node> actions;
    find_all(root, "EnvironmentAction", &actions);
    if (!actions.empty()) {
      if (actions.size() > 1) {
        note(actions[1], std::to_string(actions.size() - 1) +
                             " later EnvironmentAction(s) ignored: a still shows the first (" +
                             element_path(actions[0]) + ")");
      }
      const pugi::xml_node action = actions[0];
      if (const pugi::xml_node e = action.child("Environment")) return e;
      if (const pugi::xml_node ref = action.child("CatalogReference")) return resolve_catalog(root, ref);
      fail(action, "", "expected an Environment or a CatalogReference, found neither");
    }
    for (pugi::xml_node catalog : root.children("Catalog")) {
      if (const pugi::xml_node e = catalog.child("Environment")) {
        note(e, "a catalog file: its first Environment is shown");
        declare_parameters(e.child("ParameterDeclarations"));
        return e;
      }
    }
    fail(root, "", "no Environment found: expected GlobalAction/EnvironmentAction or a Catalog of Environments");
  }

  // Every element called `name` below `top`, in document order; without recursion, so any depth of nesting
  // is safe.
  static void find_all(pugi::xml_node top, const char* name, std::vector<pugi::xml_node>* out) {
    pugi::xml_node n = top.first_child();
    while (n && n != top) {
      if (n.type() == pugi::node_element && std::strcmp(n.name(), name) == 0) out->push_back(n);
      if (n.first_child()) {
        n = n.first_child();
        continue;
      }
      while (n && n != top && !n.next_sibling()) n = n.parent();
      if (n && n != top) n = n.next_sibling();
    }
  }

  // CatalogReference catalogName/entryName, looked up in the *.xosc files of
  // CatalogLocations/EnvironmentCatalog/Directory@path (relative to the scenario file).
  pugi::xml_node resolve_catalog(pugi::xml_node root, pugi::xml_node ref) {
    const std::string catalog = *text(ref, "catalogName", true);
    const std::string entry = *text(ref, "entryName", true);
    const std::string what = "catalog " + in_quotes(catalog) + " entry " + in_quotes(entry);
    const pugi::xml_node dir = root.child("CatalogLocations").child("EnvironmentCatalog").child("Directory");
    if (!dir) fail(ref, "", "cannot resolve " + what + ": no CatalogLocations/EnvironmentCatalog/Directory");
    const fs::path base = fs::path(main_->label).parent_path();
    const fs::path path = base / *text(dir, "path", true);
    std::error_code ec;
    std::vector<fs::path> files;
    for (fs::directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec)) {
      std::string ext = it->path().extension().string();
      for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (ext == ".xosc" && it->is_regular_file(ec)) files.push_back(it->path());
    }
    if (ec) fail(dir, "path", "cannot resolve " + what + ": " + path.string() + ": " + ec.message());
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) {
      std::string error;
      const auto body = read_file(f.string(), &error);
      if (!body) fail(ref, "", "cannot resolve " + what + ": " + error);
      auto doc = parse_xml(*body, f.string(), &error);
      if (!doc) throw ImportError(error);
      for (pugi::xml_node c : doc->xml.document_element().children("Catalog")) {
        if (trim(c.attribute("name").value()) != catalog) continue;
        for (pugi::xml_node e : c.children("Environment")) {
          if (trim(e.attribute("name").value()) != entry) continue;
          declare_parameters(e.child("ParameterDeclarations"));  // the entry's defaults, then the reference's values
          for (pugi::xml_node a : ref.child("ParameterAssignments").children("ParameterAssignment")) {
            std::string name = *text(a, "parameterRef", true);
            if (!name.empty() && name[0] == '$') name.erase(0, 1);
            parameters_[name] = trim(a.attribute("value").value());
          }
          note(ref, "the Environment is " + what + " from " + f.string());
          docs_.push_back(std::move(doc));
          return e;
        }
      }
    }
    fail(ref, "", "cannot resolve " + what + ": not found in the " + std::to_string(files.size()) +
                      " .xosc file(s) of " + path.string());
  }

  // --- place -------------------------------------------------------------------------------------

  void place(pugi::xml_node root, pugi::xml_node environment) {
    double lat = kImportDefaultLatitudeDeg, lon = kImportDefaultLongitudeDeg;
    std::string from = "the default place (Munich)";
    const pugi::xml_node logic = root.child("RoadNetwork").child("LogicFile");
    const bool both_given = options_.latitude_deg && options_.longitude_deg;
    if (logic && !both_given) {
      const std::string file = *text(logic, "filepath", true);
      const fs::path path = fs::path(file).is_absolute() ? fs::path(file)
                                                          : fs::path(main_->label).parent_path() / file;
      std::string why;
      if (geo_reference(path.string(), &lat, &lon, &why)) {
        from = "the geoReference of " + path.string();
      } else {
        note(logic, why + ": " + from + " is used");
      }
    }
    if (options_.latitude_deg) lat = *options_.latitude_deg;
    if (options_.longitude_deg) lon = *options_.longitude_deg;
    if (both_given) from = "--lat/--lon";
    else if (options_.latitude_deg || options_.longitude_deg) from += ", with --lat/--lon";
    s_->location = {lat, lon, 0.0};
    note(environment, "place: " + format_number(lat, 8) + ", " + format_number(lon, 8) + ", height 0 m, from " +
                          from);
  }

  // +lat_0/+lon_0 of the OpenDRIVE header's geoReference; false and *why when it cannot be read.
  static bool geo_reference(const std::string& path, double* lat, double* lon, std::string* why) {
    std::string error;
    const auto body = read_file(path, &error);
    if (!body) {
      *why = error;
      return false;
    }
    const auto doc = parse_xml(*body, path, &error);
    if (!doc) {
      *why = error;
      return false;
    }
    const pugi::xml_node g = doc->xml.child("OpenDRIVE").child("header").child("geoReference");
    if (!g) {
      *why = path + ": no OpenDRIVE/header/geoReference";
      return false;
    }
    const std::string proj = trim(g.text().get());
    if (!proj_origin(proj, lat, lon)) {
      *why = path + ": geoReference " + in_quotes(proj) + " has no +lat_0 and +lon_0 in range";
      return false;
    }
    return true;
  }

  // --- time --------------------------------------------------------------------------------------

  void time_of_day(pugi::xml_node environment) {
    const pugi::xml_node t = environment.child("TimeOfDay");
    std::string utc = kImportDefaultUtc;
    std::optional<double> posix;
    if (!t) {
      note(environment, std::string("no TimeOfDay: ") + kImportDefaultUtc + " is shown");
    } else {
      if (boolean(t, "animation", true).value_or(false)) {
        note(t, "animation=\"true\": the time would run with the simulation; a still shows dateTime");
      }
      std::string raw;
      utc = *text(t, "dateTime", true, &raw);
      // xsd:dateTime's time zone is optional; without one the time is taken as UTC.
      const size_t tpos = utc.find('T');
      const bool zoned = tpos != std::string::npos && utc.find_first_of("Z+-", tpos) != std::string::npos;
      if (tpos != std::string::npos && !zoned) {
        utc += "Z";
        note(t, "dateTime " + in_quotes(raw) + " has no time zone: taken as UTC");
      }
      std::string why;
      posix = parse_iso8601_utc(utc, &why);
      if (!posix) {
        const std::string echo = "'" + utc + "': ";  // the parser quotes the text; found "..." shows it already
        if (why.rfind(echo, 0) == 0) why.erase(0, echo.size());
        fail_value(t, "dateTime", "a date and time \"YYYY-MM-DDThh:mm:ss[.f][Z|+hh:mm|-hh:mm]\" (" + why + ")",
                   raw, utc);
      }
    }
    if (!posix) posix = parse_iso8601_utc(utc, nullptr);  // the default (fail_value does not return)
    s_->utc_posix_s = *posix;
    s_->utc = format_iso8601_utc(s_->utc_posix_s);
  }

  // --- weather -----------------------------------------------------------------------------------

  void weather(pugi::xml_node environment) {
    const pugi::xml_node w = environment.child("Weather");
    if (!w) return;
    static const std::vector<std::string> kOktas = {"zeroOktas", "oneOktas",   "twoOktas",   "threeOktas",
                                                    "fourOktas", "fiveOktas",  "sixOktas",   "sevenOktas",
                                                    "eightOktas", "nineOktas"};
    std::optional<int> oktas;
    std::string cover_text;
    if (const auto i = choice(w, "fractionalCloudCover", kOktas)) {
      oktas = static_cast<int>(*i);
      cover_text = "fractionalCloudCover " + kOktas[*i];
    }
    // 1.0's cloudState (deprecated since 1.1): read when fractionalCloudCover is absent.
    static const std::vector<std::string> kStates = {"free", "cloudy", "overcast", "rainy", "skyOff"};
    if (const auto i = choice(w, "cloudState", kStates); i && !oktas) {
      static const int kStateOktas[] = {0, 6, 8, 8, 0};
      oktas = kStateOktas[*i];
      cover_text = "cloudState " + kStates[*i];
      if (kStates[*i] == "skyOff") note(w, "cloudState skyOff: no clouds; the sky is still drawn");
      if (kStates[*i] == "rainy") not_drawn(w, "cloudState rainy: an overcast deck, without its rain");
    }
    if (oktas && *oktas > 0) {
      CloudLayer layer = cloud_layer_for_oktas(std::min(*oktas, 8));
      s_->clouds.push_back(layer);
      note(w, cover_text + ": " + std::to_string(layer.coverage_oktas) + " oktas of " + to_string(layer.type) +
                  ", base " + format_number(layer.base_m) + " m, top " + format_number(layer.top_m) + " m" +
                  (*oktas == 9 ? " (nine oktas: sky obscured, drawn as an overcast deck)" : ""));
    }
    if (const auto p = number(w, "atmosphericPressure", {80000, 120000}, "a pressure in Pa in [80000, 120000]")) {
      not_drawn(w, "atmosphericPressure " + format_number(*p) +
                       " Pa: the plugin's air is the standard atmosphere (refraction too)");
    }
    if (const auto t = number(w, "temperature", {170, 340}, "a temperature in K in [170, 340]")) {
      not_drawn(w, "temperature " + format_number(*t) + " K: the plugin's air is the standard atmosphere");
    }
    fog(w.child("Fog"));
    precipitation(w.child("Precipitation"));
    if (const pugi::xml_node wind = w.child("Wind")) {
      const auto dir = number(wind, "direction", {0, 2 * kPi}, "a direction in rad in [0, 2 pi]", true);
      const auto speed = number(wind, "speed", {0, 1e6}, "a speed in m/s >= 0", true);
      // direction: where the wind blows to, as a heading from the x axis (east), counter-clockwise.
      not_drawn(wind, "wind " + format_number(*speed) + " m/s, direction " + format_number(*dir, 4) +
                          " rad: the plugin's clouds do not drift");
    }
    if (const pugi::xml_node dome = w.child("DomeImage")) {
      not_drawn(dome, "a dome image: the plugin draws its own sky");
    }
  }

  // visualRange is the air's meteorological visibility (MOR); a BoundingBox makes it a ground fog layer
  // up to the box's top instead (the plugin's fog has no horizontal edge).
  void fog(pugi::xml_node f) {
    if (!f) return;
    const double range = *number(f, "visualRange", {0, 1e12, true}, "a distance in metres > 0", true);
    const pugi::xml_node box = f.child("BoundingBox");
    if (!box) {
      const double mor = std::clamp(range, 50.0, 500000.0);
      s_->atmosphere.visibility_m = mor;
      note(f, "visualRange " + format_number(range) + " m: the air's meteorological visibility (MOR)" +
                  (mor != range ? ", clamped to " + format_number(mor) + " m (the plugin's [50, 500000])" : ""));
      return;
    }
    const pugi::xml_node centre = box.child("Center");
    const pugi::xml_node size = box.child("Dimensions");
    if (!centre) fail(box, "", "expected a Center element, found none");
    if (!size) fail(box, "", "expected a Dimensions element, found none");
    const Interval any{-1e12, 1e12};
    const double z = *number(centre, "z", any, "a height in metres", true);
    number(centre, "x", any, "a coordinate in metres", true);
    number(centre, "y", any, "a coordinate in metres", true);
    const Interval positive{0, 1e12, true};
    number(size, "width", positive, "a size in metres > 0", true);
    number(size, "length", positive, "a size in metres > 0", true);
    const double height = *number(size, "height", positive, "a size in metres > 0", true);
    const double top = z + height / 2;
    if (!(top > 0)) {
      fail(box, "", "expected the fog's top (Center@z + Dimensions@height / 2) above the ground (0), found " +
                        format_number(top) + " m");
    }
    Fog& fog = s_->fog.emplace();
    fog.visibility_m = std::clamp(range, 10.0, 5000.0);
    fog.top_m = std::min(top, 3000.0);
    note(f, "visualRange " + format_number(range) + " m in a BoundingBox: a ground fog layer of visibility " +
                format_number(fog.visibility_m) + " m up to " + format_number(fog.top_m) +
                " m (the box's top; its width and length are not used: the plugin's fog has no edge)" +
                (fog.visibility_m != range || fog.top_m != top ? ", clamped to the plugin's [10, 5000] m, top <= 3000 m"
                                                               : ""));
  }

  void precipitation(pugi::xml_node p) {
    if (!p) return;
    static const std::vector<std::string> kTypes = {"dry", "rain", "snow"};
    const size_t type = *choice(p, "precipitationType", kTypes, true);
    std::string amount;
    if (const auto mm = number(p, "precipitationIntensity", {0, 1e6}, "an intensity in mm/h >= 0")) {
      amount = " " + format_number(*mm) + " mm/h";
    } else if (const auto i = number(p, "intensity", {0, 1}, "an intensity in [0, 1]")) {  // 1.0
      amount = " intensity " + format_number(*i);
    }
    if (type != 0) not_drawn(p, kTypes[type] + amount + ": the plugin draws no precipitation");
  }

  // --- scene -------------------------------------------------------------------------------------

  // What an OpenSCENARIO file has no word for: a flat ground with a road (the host terrain's runway, its
  // lights off: an empty "lights" block) ahead, and one camera at eye height on it facing the Sun's
  // azimuth (the ephemeris's), looking 5 deg up, automatic exposure.
  void default_scene() {
    Terrain& t = s_->terrain.emplace();
    t.kind = TerrainKind::Flat;
    t.seed = 1;
    s_->lights.emplace();
    const auto bodies = sky();
    Camera c;
    c.name = "main";
    c.position.kind = Position::Kind::Enu;
    c.position.enu_m = {0.0, 0.0, 2.0};
    const double azimuth = std::atan2(bodies.sun_enu.x, bodies.sun_enu.y) * 180 / kPi;
    c.heading_deg = std::round(azimuth < 0 ? azimuth + 360 : azimuth);
    c.pitch_deg = 5.0;
    t.runway_heading_deg = std::fmod(c.heading_deg, 360.0);
    c.vertical_fov_deg = 60.0;
    c.width = options_.width.value_or(kImportDefaultWidth);
    c.height = options_.height.value_or(kImportDefaultHeight);
    c.near_m = 0.5;
    c.far_m = 100000.0;
    s_->cameras.push_back(c);
    s_->outputs.exr = false;  // a look at the weather: the PNG
  }

  core::SkyBodies sky() const {
    std::string error;
    const core::Geodetic eye{s_->location.latitude_deg, s_->location.longitude_deg, s_->location.height_m + 2.0};
    auto bodies = core::compute_sky_bodies(s_->utc_posix_s, s_->dut1_s, eye, &error);
    if (!bodies) throw ImportError(main_->label + ": the ephemeris: " + error);
    core::apply_refraction(&*bodies, eye.height_m);
    return *bodies;
  }

  // The Sun is where the ephemeris puts it for the date and place (the plugin has no input for its
  // direction); the file's Sun is compared with it and the difference noted.
  void sun(pugi::xml_node n) {
    if (!n) return;
    const double az = *number(n, "azimuth", {0, 2 * kPi}, "an azimuth in rad in [0, 2 pi]", true);
    const double el = *number(n, "elevation", {-kPi / 2, kPi / 2}, "an elevation in rad in [-pi/2, pi/2]", true);
    std::optional<double> lux = number(n, "illuminance", {0, 1e7}, "an illuminance in lux >= 0");
    if (!lux) lux = number(n, "intensity", {0, 1e7}, "an illuminance in lux >= 0");  // before 1.2
    const glm::dvec3 file(std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el));
    const glm::dvec3 e = sky().sun_enu;
    double e_az = std::atan2(e.x, e.y) * 180 / kPi;
    if (e_az < 0) e_az += 360;
    const double diff = std::acos(std::clamp(glm::dot(file, e), -1.0, 1.0)) * 180 / kPi;
    note(n, "Sun azimuth " + format_number(az * 180 / kPi, 4) + " deg, elevation " + format_number(el * 180 / kPi, 3) +
                " deg; the ephemeris for " + s_->utc + " here: azimuth " + format_number(e_az, 4) + " deg, elevation " +
                format_number(std::asin(std::clamp(e.z, -1.0, 1.0)) * 180 / kPi, 3) + " deg, " +
                format_number(diff, 3) + " deg apart: the ephemeris is drawn");
    if (lux) not_drawn(n, "illuminance " + format_number(*lux) + " lx: the Sun's light comes from the ephemeris and the air");
  }

  const ImportOptions& options_;
  Scenario* s_;
  Document* main_ = nullptr;
  std::vector<std::unique_ptr<Document>> docs_;
  std::map<std::string, std::string> parameters_;
  std::string version_;
};

}  // namespace

CloudLayer cloud_layer_for_oktas(int oktas) {
  CloudLayer c;
  c.coverage_oktas = std::clamp(oktas, 0, 8);
  c.seed = 1;
  if (c.coverage_oktas <= 4) {
    c.type = CloudType::Cumulus;
    c.base_m = 1200.0;
    c.top_m = 2200.0;
  } else if (c.coverage_oktas <= 7) {
    c.type = CloudType::Stratus;
    c.base_m = 1000.0;
    c.top_m = 1500.0;
  } else {
    c.type = CloudType::Overcast;
    c.base_m = 600.0;
    c.top_m = 1100.0;
  }
  return c;
}

bool proj_origin(const std::string& proj, double* latitude_deg, double* longitude_deg) {
  std::optional<double> lat, lon;
  std::istringstream in(proj);
  for (std::string token; in >> token;) {
    const auto eq = token.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = token.substr(0, eq);
    const auto v = to_number(token.substr(eq + 1));
    if (key == "+lat_0") lat = v;
    if (key == "+lon_0") lon = v;
  }
  if (!lat || !lon || std::fabs(*lat) > 90 || std::fabs(*lon) > 180) return false;
  *latitude_deg = *lat;
  *longitude_deg = *lon;
  return true;
}

LoadResult parse_openscenario(const std::string& xml_text, const std::string& file_label,
                              const ImportOptions& options) {
  LoadResult result;
  std::string error;
  auto doc = parse_xml(xml_text, file_label, &error);
  if (!doc) {
    result.error = error;
    return result;
  }
  Scenario s;
  try {
    Importer(options, &s).run(std::move(doc));
  } catch (const ImportError& e) {
    result.error = e.what();
    return result;
  }
  result.scenario = std::move(s);
  return result;
}

LoadResult load_openscenario_file(const std::string& path, const ImportOptions& options) {
  std::string error;
  const auto text = read_file(path, &error);
  if (!text) return {std::nullopt, error};
  return parse_openscenario(*text, path, options);
}

}  // namespace atmo::scenario
