#include "common/source_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace slt {
namespace {

// Sets $SLT_PYTHON for one test and restores it.
class ScopedPython {
 public:
  explicit ScopedPython(const char* value) {
    const char* old = std::getenv("SLT_PYTHON");
    had_ = old != nullptr;
    if (had_) old_ = old;
    ::setenv("SLT_PYTHON", value, 1);
  }
  ~ScopedPython() {
    if (had_) {
      ::setenv("SLT_PYTHON", old_.c_str(), 1);
    } else {
      ::unsetenv("SLT_PYTHON");
    }
  }

 private:
  bool had_ = false;
  std::string old_;
};

TEST(SourceTree, ShellQuoteSurvivesQuotesAndSpaces) {
  EXPECT_EQ(ShellQuote("a b"), "'a b'");
  EXPECT_EQ(ShellQuote("it's"), "'it'\\''s'");
  EXPECT_EQ(ShellQuote(""), "''");
}

TEST(SourceTree, InterpreterFollowsTheEnvironment) {
  {
    ScopedPython python("/opt/my/python3");
    EXPECT_EQ(PythonInterpreter(), "/opt/my/python3");
  }
  ScopedPython empty("");
  EXPECT_EQ(PythonInterpreter(), "/usr/bin/python3");
}

TEST(SourceTree, RunsTheScriptOfTheSourceTreeAndReportsItsExitCode) {
  // /bin/true and /bin/false stand in for the interpreter: the script is found and "run".
  {
    ScopedPython python("/bin/true");
    EXPECT_NO_THROW(RunPythonScript("scripts/plot_experiment.py", {"an argument", "it's"}));
  }
  ScopedPython python("/bin/false");
  try {
    RunPythonScript("scripts/plot_experiment.py", {});
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("exited with 1"), std::string::npos) << e.what();
  }
  try {
    RunPythonScript("scripts/no_such_script.py", {});
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "scripts/no_such_script.py not found");
  }
}

TEST(SourceTree, PathsLeadIntoTheSourceTreeWhileItExists) {
  ASSERT_TRUE(std::filesystem::is_directory(SourceDir()));
  EXPECT_EQ(SourceTreePath("results/x"), SourceDir() + "/results/x");
}

// run_experiment's configs and simulate's scenes: by path, or by name with or without the
// extension; a missing one names where it looked and what there is.
TEST(SourceTree, FindsNamedFilesAndListsThemWhenOneIsMissing) {
  namespace fs = std::filesystem;
  // ./frontend/configs/ is looked in before the source tree's: the same file from the source root.
  const std::string file = SourceDir() + "/frontend/configs/room_752x480.json";
  const std::string path = FindNamedFile("room_752x480", "frontend/configs", ".json", "simulation config");
  EXPECT_TRUE(fs::equivalent(path, file)) << path;
  EXPECT_EQ(FindNamedFile("room_752x480.json", "frontend/configs", ".json", "simulation config"), path);
  EXPECT_EQ(FindNamedFile(file, "frontend/configs", ".json", "simulation config"), file);  // a path as given
  const std::vector<std::string> names = FileNamesIn("experiments/configs", ".json");
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  EXPECT_NE(std::find(names.begin(), names.end(), "ci/noise_sweep_ci"), names.end());  // below subfolders
  EXPECT_TRUE(FileNamesIn("no/such/folder", ".json").empty());
  try {
    FindNamedFile("no_such_scene", "frontend/configs", ".json", "simulation config");
    FAIL() << "found a file that does not exist";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("simulation config 'no_such_scene' not found (looked for no_such_scene, no_such_scene.json, "
                            "frontend/configs/no_such_scene, ", 0),
              0u)
        << message;
    EXPECT_NE(message.find("; available: corridor_640x480, paper_640x480, room_752x480, room_ci_640x480"),
              std::string::npos)
        << message;
  }
  try {
    FindNamedFile("/no/such/scene.json", "frontend/configs", ".json", "simulation config");
    FAIL() << "found a file that does not exist";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();  // an absolute path is looked for once
    EXPECT_EQ(message.rfind("simulation config '/no/such/scene.json' not found (looked for /no/such/scene.json); ", 0), 0u)
        << message;
  }
}

}  // namespace
}  // namespace slt
