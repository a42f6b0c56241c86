#include "common/script_runner.h"

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace slt {

std::string SourceDir() { return SLT_SOURCE_DIR; }

std::string ShellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') {
      q += "'\\''";
    } else {
      q += c;
    }
  }
  return q + "'";
}

std::string PythonInterpreter() {
  const char* env = std::getenv("SLT_PYTHON");
  return env != nullptr && *env != '\0' ? env : "/usr/bin/python3";
}

void RunPythonScript(const std::string& script, const std::vector<std::string>& args) {
  namespace fs = std::filesystem;
  std::error_code error;
  std::string path = (fs::path(SourceDir()) / script).string();
  if (!fs::is_regular_file(path, error)) path = script;
  if (!fs::is_regular_file(path, error)) throw std::runtime_error(script + " not found");
  std::string command = ShellQuote(PythonInterpreter()) + " " + ShellQuote(path);
  for (const std::string& arg : args) command += " " + ShellQuote(arg);
  const int status = std::system(command.c_str());
  if (status != 0) {
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : status;
    throw std::runtime_error(command + " exited with " + std::to_string(code));
  }
}

}  // namespace slt
