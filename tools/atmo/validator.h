// validator.h — `atmo validate PLUGIN`: loads a plugin build the way a host
// does and checks the ABI contract, one forked process per check (a crash or
// a hang is that check's failure, not the validator's).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace atmo::validate {

struct CheckResult {
  bool passed = false;
  std::string detail;  // why it failed, or a short note when it passed
};

struct Check {
  std::string name;
  std::function<CheckResult(const std::string& plugin_path)> run;
};

// Every check, in the order they run.
std::vector<Check> all_checks();

struct Options {
  std::string plugin_path;
  std::string filter;        // substring of check names; empty = all
  bool in_process = false;   // debugging: no fork
  int timeout_s = 300;  // per check; the GL state checks draw every pass twice (llvmpipe on a loaded machine: > 120 s)
};

// Prints "PASS name" / "FAIL name: detail" per check and a summary line;
// returns the number of failures.
int run_validation(const Options& options);

}  // namespace atmo::validate
