// A small JSON Schema (2020-12) validator covering exactly the keywords
// config/scenario.schema.json uses, so tests can check that the schema and the
// hand-written loader accept and reject the same documents. It refuses a
// schema with any keyword it does not know, so it cannot pass by ignoring one.
#ifndef ATMO_TESTS_SCENARIO_SCHEMA_VALIDATOR_H
#define ATMO_TESTS_SCENARIO_SCHEMA_VALIDATOR_H

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace atmo_test {

class SchemaValidator {
 public:
  explicit SchemaValidator(nlohmann::json schema);

  // Keywords in the schema this validator does not implement (should be none).
  std::vector<std::string> unknown_keywords() const;

  // Errors as "<pointer>: <what>"; empty if the document is valid.
  std::vector<std::string> validate(const nlohmann::json& document) const;

 private:
  void check(const nlohmann::json& schema, const nlohmann::json& value, const std::string& pointer,
             std::vector<std::string>* errors) const;
  void collect_unknown(const nlohmann::json& schema, const std::string& where,
                       std::vector<std::string>* out) const;
  const nlohmann::json& resolve(const std::string& ref) const;

  nlohmann::json schema_;
};

}  // namespace atmo_test

#endif
