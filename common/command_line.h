// The command-line step every program shares (CLI11): parse, then the program's own checks of
// its options. --help prints the help on stdout and exits 0; a command-line error prints one
// line "<program>: error: <what> (see --help)" on stderr and exits 2.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdio>

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

}  // namespace slt
