// Running the project's Python scripts (scripts/*.py) from its programs: run_experiment draws
// its plots with scripts/plot_experiment.py, evaluate its trajectory plot with
// scripts/plot_trajectory.py. They share how the script and the interpreter are found.
#pragma once

#include <string>
#include <vector>

namespace slt {

// The source tree this program was built from (compile-time SLT_SOURCE_DIR).
std::string SourceDir();

// `s` quoted for a POSIX shell command line.
std::string ShellQuote(const std::string& s);

// The interpreter for the scripts: $SLT_PYTHON when set and not empty, else /usr/bin/python3
// (Debian's, which has python3-matplotlib from scripts/install_deps.sh).
std::string PythonInterpreter();

// Runs `<PythonInterpreter()> <script> <args>...`, the script found as <SourceDir()>/<script>
// and then as ./<script> (`script` is relative, e.g. "scripts/plot_trajectory.py"). Throws
// std::runtime_error when the script is not found ("<script> not found") or exits with a
// non-zero code ("<command> exited with <code>").
void RunPythonScript(const std::string& script, const std::vector<std::string>& args);

}  // namespace slt
