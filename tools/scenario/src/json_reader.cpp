#include "json_reader.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace atmo::scenario::detail {

namespace {

// Builds the DOM like nlohmann's own parser, but sees every key so it can
// reject duplicates, and keeps the byte position of errors.
class DomBuilder : public nlohmann::json_sax<json> {
 public:
  explicit DomBuilder(json* root) : root_(root) {}

  bool null() override { return put(json(nullptr)); }
  bool boolean(bool v) override { return put(json(v)); }
  bool number_integer(number_integer_t v) override { return put(json(v)); }
  bool number_unsigned(number_unsigned_t v) override { return put(json(v)); }
  bool number_float(number_float_t v, const string_t&) override { return put(json(v)); }
  bool string(string_t& v) override { return put(json(v)); }
  bool binary(binary_t&) override { return put(json()); }  // never produced by text JSON
  bool start_object(std::size_t) override {
    json* j = place(json::object());
    stack_.push_back({j, {}, 0});
    return true;
  }
  bool key(string_t& k) override {
    Frame& f = stack_.back();
    if (f.node->contains(k)) {
      duplicate_ = path() + "/" + pointer_escape(k);
      return false;
    }
    f.key = k;
    return true;
  }
  bool end_object() override {
    stack_.pop_back();
    return true;
  }
  bool start_array(std::size_t) override {
    json* j = place(json::array());
    stack_.push_back({j, {}, 0});
    return true;
  }
  bool end_array() override {
    stack_.pop_back();
    return true;
  }
  bool parse_error(std::size_t position, const std::string& last_token,
                   const nlohmann::detail::exception& ex) override {
    std::string what = ex.what();
    // nlohmann reports the position after the last token read. When that is a
    // complete string or number literal (an unexpected one, or a number too
    // large), point at its first character; otherwise at the last one read.
    // Only string and number tokens start fresh in last_token.
    const auto number_char = [](char c) {
      return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' || c == 'e' || c == 'E';
    };
    const bool complete_string = last_token.size() >= 2 && last_token.front() == '"' &&
                                 last_token.back() == '"' &&
                                 what.find("invalid string") == std::string::npos;
    const bool number = !last_token.empty() &&
                        (last_token[0] == '-' || (last_token[0] >= '0' && last_token[0] <= '9')) &&
                        std::all_of(last_token.begin(), last_token.end(), number_char);
    error_position_ = position;
    if ((complete_string || number) && position >= last_token.size()) {
      error_position_ = position - last_token.size() + 1;
    }
    // Drop nlohmann's "[json.exception.x.y] parse error at line L, column C: ".
    if (const auto p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);
    if (what.rfind("parse error", 0) == 0) {
      if (const auto p = what.find(": "); p != std::string::npos) what = what.substr(p + 2);
    }
    error_ = what;
    return false;
  }

  const std::string& duplicate() const { return duplicate_; }
  const std::string& error() const { return error_; }
  std::size_t error_position() const { return error_position_; }

 private:
  struct Frame {
    json* node;
    std::string key;
    std::size_t index;
  };

  std::string path() const {
    std::string p;
    for (size_t i = 0; i + 1 < stack_.size(); ++i) {
      const Frame& parent = stack_[i];
      p += "/" + (parent.node->is_array() ? std::to_string(parent.index - 1)
                                          : pointer_escape(parent.key));
    }
    return p;
  }

  json* place(json&& v) {
    if (stack_.empty()) {
      *root_ = std::move(v);
      return root_;
    }
    Frame& f = stack_.back();
    if (f.node->is_array()) {
      f.node->push_back(std::move(v));
      ++f.index;
      return &f.node->back();
    }
    json& slot = (*f.node)[f.key];
    slot = std::move(v);
    return &slot;
  }
  bool put(json&& v) {
    place(std::move(v));
    return true;
  }

  json* root_;
  std::vector<Frame> stack_;
  std::string duplicate_, error_;
  std::size_t error_position_ = 0;
};

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1])});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string format_number(double v) {
  std::ostringstream s;
  s.precision(15);
  s << v;
  return s.str();
}

}  // namespace

bool parse_json(const std::string& text, json* out, std::string* error) {
  DomBuilder builder(out);
  if (json::sax_parse(text, &builder)) return true;
  if (!builder.duplicate().empty()) {
    *error = builder.duplicate() + ": duplicate key (each field may appear once)";
    return false;
  }
  // Line and column of the offending character, both from 1.
  const size_t at = std::min(builder.error_position() > 0 ? builder.error_position() - 1 : 0,
                             text.size());
  size_t line = 1, line_start = 0;
  for (size_t i = 0; i < at; ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  *error = "line " + std::to_string(line) + ", column " + std::to_string(at - line_start + 1) +
           ": JSON syntax error: " + builder.error();
  return false;
}

std::string pointer_escape(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

std::string describe(const json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array of " + std::to_string(v.size());
  if (v.is_null()) return "null";
  if (v.is_number_float()) return format_number(v.get<double>());
  std::string s = v.dump(-1, ' ', false, json::error_handler_t::replace);
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

bool Range::contains(double v) const {
  if (!std::isfinite(v)) return false;
  if (min && (min_exclusive ? !(v > *min) : !(v >= *min))) return false;
  if (max && (max_exclusive ? !(v < *max) : !(v <= *max))) return false;
  return true;
}

std::string Range::text() const {
  if (min && max) {
    return std::string("in ") + (min_exclusive ? "(" : "[") + format_number(*min) + ", " +
           format_number(*max) + (max_exclusive ? ")" : "]");
  }
  if (min) return (min_exclusive ? "> " : ">= ") + format_number(*min);
  if (max) return (max_exclusive ? "< " : "<= ") + format_number(*max);
  return "";
}

void Errors::add(const std::string& pointer, const std::string& message) {
  // "" is the root's JSON pointer; "/" would mean a key named "".
  lines_.push_back(file_ + ": " + (pointer.empty() ? std::string("(root)") : pointer) + ": " + message);
}

void Errors::expected(const std::string& pointer, const std::string& what, const json& found) {
  add(pointer, "expected " + what + ", found " + describe(found));
}

std::string Errors::joined() const {
  std::string out;
  for (const auto& l : lines_) {
    if (!out.empty()) out += '\n';
    out += l;
  }
  return out;
}

ObjectReader::ObjectReader(Errors& errors, const json& value, std::string pointer,
                           const std::vector<std::string>& shape, const std::string& what)
    : errors_(errors), pointer_(std::move(pointer)), shape_(shape), what_(what) {
  if (!value.is_object()) {
    errors_.expected(pointer_, "an object (" + what_ + ")", value);
    finished_ = true;
    return;
  }
  object_ = &value;
  valid_ = true;
}

ObjectReader::~ObjectReader() { finish(); }

const json* ObjectReader::field(const std::string& key, bool required,
                                const std::string& expected_text) {
  if (std::find(shape_.begin(), shape_.end(), key) == shape_.end()) {
    errors_.add(child(key), "internal: loader reads a field missing from shape \"" + what_ + "\"");
  }
  asked_.insert(key);
  if (!object_) return nullptr;
  const auto it = object_->find(key);
  if (it == object_->end()) {
    if (required) errors_.add(child(key), "required field missing: expected " + expected_text);
    return nullptr;
  }
  return &*it;
}

std::optional<double> read_number(Errors& errors, const json& value, const std::string& pointer,
                                  const Range& range) {
  const std::string what = range.text().empty() ? "a number" : "a number " + range.text();
  if (!value.is_number() || !range.contains(value.get<double>())) {
    errors.expected(pointer, what, value);
    return std::nullopt;
  }
  return value.get<double>();
}

std::optional<double> ObjectReader::number(const std::string& key, const Range& range,
                                           std::optional<double> default_value) {
  const std::string what = range.text().empty() ? "a number" : "a number " + range.text();
  const json* v = field(key, !default_value, what);
  if (!v) return default_value && valid_ ? default_value : std::nullopt;
  return read_number(errors_, *v, child(key), range);
}

std::optional<std::int64_t> ObjectReader::integer(const std::string& key, std::int64_t lo,
                                                  std::int64_t hi,
                                                  std::optional<std::int64_t> default_value) {
  const std::string what = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  const json* v = field(key, !default_value, what);
  if (!v) return default_value && valid_ ? default_value : std::nullopt;
  // As in JSON Schema, 640.0 is an integer; 640.5 is not.
  std::optional<std::int64_t> n;
  if (v->is_number_unsigned()) {
    const auto u = v->get<std::uint64_t>();
    if (u <= static_cast<std::uint64_t>(hi)) n = static_cast<std::int64_t>(u);
  } else if (v->is_number_integer()) {
    n = v->get<std::int64_t>();
  } else if (v->is_number_float()) {
    const double d = v->get<double>();
    if (std::trunc(d) == d && d >= static_cast<double>(lo) && d <= static_cast<double>(hi)) {
      n = static_cast<std::int64_t>(d);
    }
  }
  if (!n || *n < lo || *n > hi) {
    errors_.expected(child(key), what, *v);
    return std::nullopt;
  }
  return n;
}

std::optional<bool> ObjectReader::boolean(const std::string& key,
                                          std::optional<bool> default_value) {
  const json* v = field(key, !default_value, "true or false");
  if (!v) return default_value && valid_ ? default_value : std::nullopt;
  if (!v->is_boolean()) {
    errors_.expected(child(key), "true or false", *v);
    return std::nullopt;
  }
  return v->get<bool>();
}

std::optional<std::string> ObjectReader::string(const std::string& key, bool required,
                                                size_t min_length,
                                                const std::string& expected_text,
                                                bool (*pattern_ok)(const std::string&)) {
  const json* v = field(key, required, expected_text);
  if (!v) return std::nullopt;
  if (!v->is_string() || v->get_ref<const std::string&>().size() < min_length ||
      (pattern_ok && !pattern_ok(v->get_ref<const std::string&>()))) {
    errors_.expected(child(key), expected_text, *v);
    return std::nullopt;
  }
  return v->get<std::string>();
}

std::optional<size_t> ObjectReader::choice(const std::string& key,
                                           const std::vector<std::string>& options,
                                           std::optional<size_t> default_index) {
  std::string what = "one of ";
  for (size_t i = 0; i < options.size(); ++i) what += (i ? ", \"" : "\"") + options[i] + "\"";
  const json* v = field(key, !default_index, what);
  if (!v) return default_index && valid_ ? default_index : std::nullopt;
  if (v->is_string()) {
    const auto it = std::find(options.begin(), options.end(), v->get_ref<const std::string&>());
    if (it != options.end()) return static_cast<size_t>(it - options.begin());
  }
  errors_.expected(child(key), what, *v);
  return std::nullopt;
}

void ObjectReader::finish() {
  if (finished_) return;
  finished_ = true;
  for (const auto& name : shape_) {
    if (!asked_.count(name)) {
      errors_.add(child(name), "internal: shape \"" + what_ + "\" lists a field the loader never reads");
    }
  }
  for (const auto& [key, value] : object_->items()) {
    if (asked_.count(key)) continue;
    std::string best;
    size_t best_distance = 3;  // suggest only close matches
    for (const auto& name : shape_) {
      const size_t d = edit_distance(key, name);
      if (d < best_distance) {
        best_distance = d;
        best = name;
      }
    }
    std::string accepted;
    for (const auto& name : shape_) accepted += (accepted.empty() ? "" : ", ") + name;
    errors_.add(child(key), "unknown field in " + what_ +
                                (best.empty() ? "" : " (did you mean \"" + best + "\"?)") +
                                "; expected one of: " + accepted);
  }
}

}  // namespace atmo::scenario::detail
