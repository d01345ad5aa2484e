// cli.h — the tools' command-line convention over CLI11 (as `atmo` and
// atmo-star-convert): --help prints the usage and exits 0; a bad argument
// (unknown option, missing or malformed value, out of range) prints CLI11's
// message, which names the option and the value, and exits 2.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>

namespace atmo::support {

// Parses argv into `app`: nullopt to go on, else the exit code to return at once.
inline std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  return std::nullopt;
}

}  // namespace atmo::support
