// Private helpers of the scenario loader: a JSON parser that reports line and
// column and rejects duplicate keys, and typed field readers that record
// errors as "<file>: <pointer>: expected ..., found ...".
#ifndef ATMO_SCENARIO_JSON_READER_H
#define ATMO_SCENARIO_JSON_READER_H

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace atmo::scenario::detail {

using nlohmann::json;

// Parses text into *out. On a syntax error returns false and sets *error to
// "line L, column C: <what>". A key repeated in one object is an error too
// (the last one would silently win otherwise).
bool parse_json(const std::string& text, json* out, std::string* error);

std::string pointer_escape(const std::string& key);  // RFC 6901: ~ -> ~0, / -> ~1
std::string describe(const json& value);              // for "found ..."

// A numeric range; its text ("in (0, 180)", "> 0", "") goes into messages.
struct Range {
  std::optional<double> min, max;
  bool min_exclusive = false, max_exclusive = false;
  bool contains(double v) const;
  std::string text() const;
  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  static Range open(double lo, double hi) { return {lo, hi, true, true}; }
  static Range above(double lo) { return {lo, std::nullopt, true, false}; }
  static Range at_least(double lo) { return {lo, std::nullopt, false, false}; }
  static Range any() { return {}; }
};

class Errors {
 public:
  explicit Errors(std::string file) : file_(std::move(file)) {}
  void add(const std::string& pointer, const std::string& message);
  void expected(const std::string& pointer, const std::string& what, const json& found);
  bool empty() const { return lines_.empty(); }
  std::string joined() const;
  const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::vector<std::string> lines_;
};

// Reads the fields of one JSON object. Built from its shape (the accepted
// field names); finish() reports fields that are present but not accepted.
// Asking for a field the shape does not list, or never asking for a listed
// one, is a loader bug and is reported as "internal" so tests catch drift.
class ObjectReader {
 public:
  // Returns nullopt-like (valid() false) if `value` is not an object.
  ObjectReader(Errors& errors, const json& value, std::string pointer,
               const std::vector<std::string>& shape, const std::string& what);
  ~ObjectReader();
  ObjectReader(const ObjectReader&) = delete;
  ObjectReader& operator=(const ObjectReader&) = delete;

  bool valid() const { return valid_; }
  const std::string& pointer() const { return pointer_; }
  std::string child(const std::string& key) const { return pointer_ + "/" + pointer_escape(key); }

  // The field's value, or null if absent (reports a missing required field).
  const json* field(const std::string& key, bool required, const std::string& expected_text);

  // Typed readers: absent -> default (or an error when required, i.e. no
  // default given); wrong type or range -> error and nullopt.
  std::optional<double> number(const std::string& key, const Range& range,
                               std::optional<double> default_value);
  std::optional<std::int64_t> integer(const std::string& key, std::int64_t lo, std::int64_t hi,
                                      std::optional<std::int64_t> default_value);
  std::optional<bool> boolean(const std::string& key, std::optional<bool> default_value);
  // min_length 0 allows ""; pattern_ok validates the text when given.
  std::optional<std::string> string(const std::string& key, bool required, size_t min_length,
                                    const std::string& expected_text = "a string",
                                    bool (*pattern_ok)(const std::string&) = nullptr);
  // One of `options`; returns its index.
  std::optional<size_t> choice(const std::string& key, const std::vector<std::string>& options,
                               std::optional<size_t> default_index);

  void finish();  // unknown-field and drift checks; also run by the destructor

 private:
  Errors& errors_;
  const json* object_ = nullptr;
  std::string pointer_;
  const std::vector<std::string>& shape_;
  std::string what_;
  std::set<std::string> asked_;
  bool valid_ = false;
  bool finished_ = false;
};

// Reads a number at `pointer`, outside any object (array items).
std::optional<double> read_number(Errors& errors, const json& value, const std::string& pointer,
                                  const Range& range);

}  // namespace atmo::scenario::detail

#endif  // ATMO_SCENARIO_JSON_READER_H
