#include "schema_validator.h"

#include <cmath>
#include <regex>
#include <set>
#include <stdexcept>

namespace atmo_test {

using nlohmann::json;

namespace {

// Annotations carry no assertion; "format" is annotation-only in 2020-12.
const std::set<std::string> kAnnotations = {"$schema", "$id",   "$comment", "title",
                                            "description", "default", "format",  "$defs"};
const std::set<std::string> kAssertions = {
    "$ref",    "type",         "properties", "required",         "additionalProperties",
    "items",   "minItems",     "maxItems",   "enum",             "const",
    "minimum", "maximum",      "exclusiveMinimum", "exclusiveMaximum", "minLength",
    "pattern", "oneOf",        "anyOf",      "allOf",            "not",
    "if",      "then",         "else"};

bool is_integer(const json& v) {
  if (v.is_number_integer()) return true;
  if (!v.is_number_float()) return false;
  const double d = v.get<double>();
  return std::isfinite(d) && std::trunc(d) == d;
}

bool has_type(const json& v, const std::string& t) {
  if (t == "object") return v.is_object();
  if (t == "array") return v.is_array();
  if (t == "string") return v.is_string();
  if (t == "number") return v.is_number();
  if (t == "integer") return is_integer(v);
  if (t == "boolean") return v.is_boolean();
  if (t == "null") return v.is_null();
  throw std::runtime_error("unknown type " + t);
}

size_t code_points(const std::string& s) {
  size_t n = 0;
  for (unsigned char c : s) n += (c & 0xC0) != 0x80;
  return n;
}

std::string escape(const std::string& key) {
  std::string out;
  for (char c : key) out += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
  return out;
}

}  // namespace

SchemaValidator::SchemaValidator(json schema) : schema_(std::move(schema)) {}

const json& SchemaValidator::resolve(const std::string& ref) const {
  const std::string prefix = "#/$defs/";
  if (ref.rfind(prefix, 0) != 0) throw std::runtime_error("unsupported $ref " + ref);
  return schema_.at("$defs").at(ref.substr(prefix.size()));
}

void SchemaValidator::collect_unknown(const json& s, const std::string& where,
                                      std::vector<std::string>* out) const {
  if (s.is_boolean()) return;
  if (!s.is_object()) {
    out->push_back(where + " (not a schema)");
    return;
  }
  for (const auto& [k, v] : s.items()) {
    if (kAnnotations.count(k) == 0 && kAssertions.count(k) == 0) out->push_back(where + "/" + k);
  }
  if (s.contains("$defs")) {
    for (const auto& [k, v] : s["$defs"].items()) collect_unknown(v, where + "/$defs/" + k, out);
  }
  if (s.contains("properties")) {
    for (const auto& [k, v] : s["properties"].items()) {
      collect_unknown(v, where + "/properties/" + k, out);
    }
  }
  for (const char* k : {"items", "additionalProperties", "not", "if", "then", "else"}) {
    if (s.contains(k)) collect_unknown(s[k], where + "/" + k, out);
  }
  for (const char* k : {"oneOf", "anyOf", "allOf"}) {
    if (s.contains(k)) {
      for (size_t i = 0; i < s[k].size(); ++i) {
        collect_unknown(s[k][i], where + "/" + k + "/" + std::to_string(i), out);
      }
    }
  }
}

std::vector<std::string> SchemaValidator::unknown_keywords() const {
  std::vector<std::string> out;
  collect_unknown(schema_, "", &out);
  return out;
}

std::vector<std::string> SchemaValidator::validate(const json& document) const {
  std::vector<std::string> errors;
  check(schema_, document, "", &errors);
  return errors;
}

void SchemaValidator::check(const json& s, const json& v, const std::string& ptr,
                            std::vector<std::string>* errors) const {
  auto fail = [&](const std::string& what) { errors->push_back(ptr + ": " + what); };
  if (s.is_boolean()) {
    if (!s.get<bool>()) fail("not allowed (false schema)");
    return;
  }
  if (s.contains("$ref")) check(resolve(s["$ref"].get<std::string>()), v, ptr, errors);
  if (s.contains("type")) {
    bool ok = false;
    if (s["type"].is_array()) {
      for (const auto& t : s["type"]) ok = ok || has_type(v, t.get<std::string>());
    } else {
      ok = has_type(v, s["type"].get<std::string>());
    }
    if (!ok) {
      fail("wrong type");
      return;  // later keywords would only repeat the problem
    }
  }
  if (s.contains("enum")) {
    bool found = false;
    for (const auto& e : s["enum"]) found = found || e == v;
    if (!found) fail("not in enum");
  }
  if (s.contains("const") && !(s["const"] == v)) fail("not the const value");
  if (v.is_number()) {
    const double x = v.get<double>();
    if (s.contains("minimum") && !(x >= s["minimum"].get<double>())) fail("below minimum");
    if (s.contains("maximum") && !(x <= s["maximum"].get<double>())) fail("above maximum");
    if (s.contains("exclusiveMinimum") && !(x > s["exclusiveMinimum"].get<double>())) {
      fail("not above exclusiveMinimum");
    }
    if (s.contains("exclusiveMaximum") && !(x < s["exclusiveMaximum"].get<double>())) {
      fail("not below exclusiveMaximum");
    }
  }
  if (v.is_string()) {
    const std::string& str = v.get_ref<const std::string&>();
    if (s.contains("minLength") && code_points(str) < s["minLength"].get<size_t>()) {
      fail("shorter than minLength");
    }
    if (s.contains("pattern") &&
        !std::regex_search(str, std::regex(s["pattern"].get<std::string>(), std::regex::ECMAScript))) {
      fail("does not match pattern");
    }
  }
  if (v.is_array()) {
    if (s.contains("minItems") && v.size() < s["minItems"].get<size_t>()) fail("too few items");
    if (s.contains("maxItems") && v.size() > s["maxItems"].get<size_t>()) fail("too many items");
    if (s.contains("items")) {
      for (size_t i = 0; i < v.size(); ++i) check(s["items"], v[i], ptr + "/" + std::to_string(i), errors);
    }
  }
  if (v.is_object()) {
    if (s.contains("required")) {
      for (const auto& r : s["required"]) {
        if (!v.contains(r.get<std::string>())) fail("missing required " + r.get<std::string>());
      }
    }
    for (const auto& [k, item] : v.items()) {
      const std::string child = ptr + "/" + escape(k);
      if (s.contains("properties") && s["properties"].contains(k)) {
        check(s["properties"][k], item, child, errors);
      } else if (s.contains("additionalProperties")) {
        check(s["additionalProperties"], item, child, errors);
      }
    }
  }
  auto passes = [&](const json& sub) {
    std::vector<std::string> e;
    check(sub, v, ptr, &e);
    return e.empty();
  };
  if (s.contains("allOf")) {
    for (const auto& sub : s["allOf"]) check(sub, v, ptr, errors);
  }
  if (s.contains("anyOf")) {
    bool any = false;
    for (const auto& sub : s["anyOf"]) any = any || passes(sub);
    if (!any) fail("matches no anyOf branch");
  }
  if (s.contains("oneOf")) {
    int n = 0;
    for (const auto& sub : s["oneOf"]) n += passes(sub);
    if (n != 1) fail("matches " + std::to_string(n) + " oneOf branches, not 1");
  }
  if (s.contains("not") && passes(s["not"])) fail("matches the 'not' schema");
  if (s.contains("if")) {
    if (passes(s["if"])) {
      if (s.contains("then")) check(s["then"], v, ptr, errors);
    } else if (s.contains("else")) {
      check(s["else"], v, ptr, errors);
    }
  }
}

}  // namespace atmo_test
