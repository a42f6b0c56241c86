// What the programs take from the project's source tree: its Python scripts (scripts/*.py;
// run_experiment draws its plots with scripts/plot_experiment.py, evaluate its trajectory plot
// with scripts/plot_trajectory.py), and the config files taken by a bare name (run_experiment's
// experiments/configs/, simulate's rendered scenes in frontend/configs/). They share how the
// tree, the interpreter and a named file are found.
#pragma once

#include <string>
#include <vector>

namespace slt {

// The source tree this program was built from (compile-time SLT_SOURCE_DIR).
std::string SourceDir();
// <SourceDir()>/<relative> while the source tree exists, else <relative> (from the current
// directory): where a program finds scripts/ and writes results/.
std::string SourceTreePath(const std::string& relative);

// `s` quoted for a POSIX shell command line.
std::string ShellQuote(const std::string& s);

// The interpreter for the scripts: $SLT_PYTHON when set and not empty, else /usr/bin/python3
// (Debian's, which has python3-matplotlib from scripts/install_deps.sh).
std::string PythonInterpreter();

// Runs `<PythonInterpreter()> <script> <args>...`, the script found at SourceTreePath(script),
// else as ./<script> (`script` is relative, e.g. "scripts/plot_trajectory.py"). Throws
// std::runtime_error when the script is not found ("<script> not found") or exits with a
// non-zero code ("<command> exited with <code>").
void RunPythonScript(const std::string& script, const std::vector<std::string>& args);

// A file given by path or by name in a folder of the source tree: `name` as given (relative to
// the current directory), then ./<folder>/<name> and <SourceDir()>/<folder>/<name>, each as
// given and with `extension` appended (unless `name` ends in it). Throws std::runtime_error
// "<what> '<name>' not found (looked for <paths>); available: <FileNamesIn>".
std::string FindNamedFile(const std::string& name, const std::string& folder, const std::string& extension,
                          const std::string& what);

// The names FindNamedFile takes for the files below <SourceDir()>/<folder>/ that end in
// `extension`: their relative paths without it ("ci/noise_sweep_ci"), sorted; empty when the
// source tree is gone.
std::vector<std::string> FileNamesIn(const std::string& folder, const std::string& extension);

}  // namespace slt
