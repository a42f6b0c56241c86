// The program version (git) and the machine, saved beside every result.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "common/source_tree.h"  // SourceDir, ShellQuote

namespace slt {

// `git rev-parse HEAD` in `source_dir`; "unknown" when git or the repository is unavailable.
std::string GitCommit(const std::string& source_dir);
// True when tracked files differ from HEAD (`git status --porcelain --untracked-files=no`).
bool GitDirty(const std::string& source_dir);
// "model name" of /proc/cpuinfo ("unknown" elsewhere).
std::string CpuModel();
int CpuCores();  // std::thread::hardware_concurrency()
std::string CompilerName();  // e.g. "GCC 12.2.0"
std::string BuildType();     // CMAKE_BUILD_TYPE of this build
// Current UTC time, ISO 8601.
std::string UtcNow();

// {"git": {"commit", "dirty"}, "machine": {"cpu", "cores", "os"}, "compiler", "build_type"}.
nlohmann::json VersionAndMachineJson(const std::string& source_dir);

}  // namespace slt
