#include "common/machine_info.h"

#include <sys/utsname.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <thread>

#ifndef SLT_BUILD_TYPE
#define SLT_BUILD_TYPE "unknown"
#endif

namespace slt {
namespace {


// Runs a command and returns its standard output; empty on failure.
std::string Capture(const std::string& command) {
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return "";
  std::string out;
  std::array<char, 256> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) out.append(buffer.data(), n);
  if (::pclose(pipe) != 0) return "";
  return out;
}

std::string Trim(std::string s) {
  const size_t b = s.find_first_not_of(" \t\r\n");
  const size_t e = s.find_last_not_of(" \t\r\n");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

}  // namespace

std::string GitCommit(const std::string& source_dir) {
  const std::string out = Trim(Capture("git -C " + ShellQuote(source_dir) + " rev-parse HEAD 2>/dev/null"));
  return out.empty() ? "unknown" : out;
}

bool GitDirty(const std::string& source_dir) {
  return !Trim(Capture("git -C " + ShellQuote(source_dir) + " status --porcelain --untracked-files=no 2>/dev/null")).empty();
}

std::string CpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) return Trim(line.substr(colon + 1));
    }
  }
  return "unknown";
}

int CpuCores() { return static_cast<int>(std::thread::hardware_concurrency()); }

std::string CompilerName() {
#if defined(__clang__)
  return std::string("Clang ") + __clang_version__;
#elif defined(__GNUC__)
  return "GCC " + std::to_string(__GNUC__) + "." + std::to_string(__GNUC_MINOR__) + "." +
         std::to_string(__GNUC_PATCHLEVEL__);
#else
  return "unknown";
#endif
}

std::string BuildType() { return SLT_BUILD_TYPE; }

std::string UtcNow() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  ::gmtime_r(&now, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof(buffer), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

nlohmann::json VersionAndMachineJson(const std::string& source_dir) {
  struct utsname u {};
  std::string os = "unknown";
  if (::uname(&u) == 0) os = std::string(u.sysname) + " " + u.release + " " + u.machine;
  return {{"git", {{"commit", GitCommit(source_dir)}, {"dirty", GitDirty(source_dir)}}},
          {"machine", {{"cpu", CpuModel()}, {"cores", CpuCores()}, {"os", os}}},
          {"compiler", CompilerName()},
          {"build_type", BuildType()}};
}

}  // namespace slt
