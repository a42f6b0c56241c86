#include "common/source_tree.h"

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace slt {

namespace fs = std::filesystem;

std::string SourceDir() { return SLT_SOURCE_DIR; }

std::string SourceTreePath(const std::string& relative) {
  std::error_code error;
  return fs::is_directory(SourceDir(), error) ? (fs::path(SourceDir()) / relative).string() : relative;
}

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
  std::error_code error;
  std::string path = SourceTreePath(script);
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

std::string FindNamedFile(const std::string& name, const std::string& folder, const std::string& extension,
                          const std::string& what) {
  const bool has_extension =
      name.size() > extension.size() && name.compare(name.size() - extension.size(), extension.size(), extension) == 0;
  std::vector<std::string> looked;  // each path once: an absolute name is the same under every base
  for (const std::string& base : {std::string(), folder, (fs::path(SourceDir()) / folder).string()}) {
    for (const std::string& file : {name, name + extension}) {
      if (has_extension && file != name) continue;
      const std::string path = base.empty() ? file : (fs::path(base) / file).string();
      std::error_code error;
      if (fs::is_regular_file(path, error)) return path;
      if (std::find(looked.begin(), looked.end(), path) == looked.end()) looked.push_back(path);
    }
  }
  const auto join = [](const std::vector<std::string>& items) {
    std::string text;
    for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
    return text;
  };
  const std::string available = join(FileNamesIn(folder, extension));
  throw std::runtime_error(what + " '" + name + "' not found (looked for " + join(looked) + "); available: " +
                           (available.empty() ? "none found" : available));
}

std::vector<std::string> FileNamesIn(const std::string& folder, const std::string& extension) {
  const fs::path root = fs::path(SourceDir()) / folder;
  std::vector<std::string> names;
  std::error_code error;
  for (fs::recursive_directory_iterator it(root, error), end; !error && it != end; it.increment(error)) {
    if (it->is_regular_file(error) && it->path().extension() == extension) {
      names.push_back(it->path().lexically_relative(root).replace_extension().generic_string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace slt
