#include "common/script_runner.h"

#include <gtest/gtest.h>

#include <cstdlib>
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

TEST(ScriptRunner, ShellQuoteSurvivesQuotesAndSpaces) {
  EXPECT_EQ(ShellQuote("a b"), "'a b'");
  EXPECT_EQ(ShellQuote("it's"), "'it'\\''s'");
  EXPECT_EQ(ShellQuote(""), "''");
}

TEST(ScriptRunner, InterpreterFollowsTheEnvironment) {
  {
    ScopedPython python("/opt/my/python3");
    EXPECT_EQ(PythonInterpreter(), "/opt/my/python3");
  }
  ScopedPython empty("");
  EXPECT_EQ(PythonInterpreter(), "/usr/bin/python3");
}

TEST(ScriptRunner, RunsTheScriptOfTheSourceTreeAndReportsItsExitCode) {
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

}  // namespace
}  // namespace slt
