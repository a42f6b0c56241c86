// The command-line steps every program shares (CLI11): parse, then the program's own checks of
// its options (--help prints the help on stdout and exits 0; a command-line error prints one line
// "<program>: error: <what> (see --help)" on stderr and exits 2); the options several programs
// take, declared once, and their options files; and the run of the program's work with its errors reported.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>

#include "common/csv.h"
#include "common/json_reader.h"

namespace slt {

// The exit code when the program is to stop there (help, or a command-line error), -1 when it
// goes on. `validate` runs after a successful parse and reports a bad value or combination by
// throwing CLI::ValidationError (or any CLI::ParseError).
template <typename Validate>
int ParseCommandLine(CLI::App& app, int argc, char** argv, const char* program, const Validate& validate) {
  try {
    app.parse(argc, argv);
    validate();
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: error: %s (see --help)\n", program, e.what());
    return 2;
  }
  return -1;
}

inline int ParseCommandLine(CLI::App& app, int argc, char** argv, const char* program) {
  return ParseCommandLine(app, argc, argv, program, [] {});
}

// The program's work after parsing: `body` returns the exit code. An error it throws prints one
// line "<program>: error: <what>" on stderr and exits 2 for a command-line error found late
// (CLI::Error, e.g. a missing option), 1 for any other.
template <typename Body>
int RunProgram(const char* program, const Body& body) {
  try {
    return body();
  } catch (const CLI::Error& e) {
    std::fprintf(stderr, "%s: error: %s\n", program, e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", program, e.what());
    return 1;
  }
}

// A seed option read as text (CLI11 would read "-1" as 2^64 - 1 and "010" as 8): the whole text a
// decimal number in [0, 2^64 - 1], else CLI::ValidationError naming `flag`.
inline std::uint64_t ParseSeedOption(const std::string& flag, const std::string& text) {
  try {
    return ParseInteger<std::uint64_t>(text);
  } catch (const std::invalid_argument&) {
    throw CLI::ValidationError(flag, "expected an integer in [0, 2^64-1], got '" + text + "'");
  }
}

// The options file an option names (--config FILE): its JSON, or {} when the option is not given
// (every option keeps its default). ReadJsonFile's errors name the file.
inline nlohmann::json ReadOptionsFile(const std::string& path) {
  return path.empty() ? nlohmann::json::object() : ReadJsonFile(path);
}

// --method,-m: a registered tracker (methods/pose_tracker.h), and its options file under
// `config_flag` (JSON; missing keys keep their defaults). Returns the --method option.
inline CLI::Option* AddTrackerOptions(CLI::App& app, std::string* method, std::string* config_path,
                                      const char* config_flag) {
  app.add_option(config_flag, *config_path, "Tracker options, JSON (missing keys keep their defaults)");
  return app.add_option("--method,-m", *method, "Tracker name (track --list)");
}

}  // namespace slt
