#include "common/command_line.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace slt {
namespace {

// Parses `args` with one option --n (an integer that must not be 3).
int Parse(std::vector<std::string> args, int* n) {
  CLI::App app{"test"};
  app.add_option("--n", *n, "a number");
  std::vector<char*> argv;
  args.insert(args.begin(), "program");
  for (std::string& a : args) argv.push_back(a.data());
  return ParseCommandLine(app, static_cast<int>(argv.size()), argv.data(), "program", [&] {
    if (*n == 3) throw CLI::ValidationError("--n", "must not be 3");
  });
}

TEST(ParseCommandLine, GoesOnStopsWithHelpOrFailsWithTwo) {
  int n = 0;
  EXPECT_EQ(Parse({"--n", "5"}, &n), -1);
  EXPECT_EQ(n, 5);
  testing::internal::CaptureStdout();
  EXPECT_EQ(Parse({"--help"}, &n), 0);
  EXPECT_NE(testing::internal::GetCapturedStdout().find("--n"), std::string::npos);
  testing::internal::CaptureStderr();
  EXPECT_EQ(Parse({"--m", "1"}, &n), 2);
  EXPECT_EQ(Parse({"--n", "3"}, &n), 2);
  const std::string errors = testing::internal::GetCapturedStderr();
  EXPECT_NE(errors.find("program: error: "), std::string::npos);
  EXPECT_NE(errors.find("must not be 3 (see --help)"), std::string::npos);
}

TEST(ReadOptionsFile, TheFilesJsonOrEveryDefault) {
  EXPECT_EQ(ReadOptionsFile(""), nlohmann::json::object());
  const std::string path = (std::filesystem::path(::testing::TempDir()) / "slt_options_file.json").string();
  WriteJsonFile(path, {{"a", 1}});
  EXPECT_EQ(ReadOptionsFile(path), nlohmann::json({{"a", 1}}));
  std::filesystem::remove(path);
  EXPECT_THROW(ReadOptionsFile(path), ConfigError);
}

TEST(RunProgram, ExitsWithTheBodysCodeOrOneLineOfError) {
  EXPECT_EQ(RunProgram("program", [] { return 3; }), 3);
  testing::internal::CaptureStderr();
  EXPECT_EQ(RunProgram("program", []() -> int { throw CLI::RequiredError("--input"); }), 2);
  EXPECT_EQ(RunProgram("program", []() -> int { throw std::runtime_error("x.json: cannot open file"); }), 1);
  EXPECT_EQ(testing::internal::GetCapturedStderr(),
            "program: error: --input is required\nprogram: error: x.json: cannot open file\n");
}

}  // namespace
}  // namespace slt
