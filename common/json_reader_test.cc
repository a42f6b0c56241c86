#include "common/json_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/json_changes.h"

namespace slt {
namespace {

TEST(JsonReader, DefaultsKeptAndValuesRead) {
  const auto j = nlohmann::json::parse(R"({"a": 2.5, "inner": {"n": 3}})");
  JsonReader r(j, "x.json");
  double a = 1.0, b = 7.0;
  int n = 0;
  r.Get("a", &a).Get("b", &b);
  r.Child("inner").Get("n", &n);
  r.RejectUnknownKeys();
  EXPECT_EQ(a, 2.5);
  EXPECT_EQ(b, 7.0);
  EXPECT_EQ(n, 3);
}

TEST(JsonReader, ErrorsNameFileAndKey) {
  const auto j = nlohmann::json::parse(R"({"a": "text", "inner": {"typo": 1}})");
  EXPECT_EQ(ConfigErrorOf([&] {
              JsonReader r(j, "x.json");
              double a;
              r.Get("a", &a);
            }),
            "x.json: key 'a': expected a number, got string");
  EXPECT_EQ(ConfigErrorOf([&] {
              JsonReader r(j, "x.json");
              double a;
              r.Find("a");
              JsonReader inner = r.Child("inner");
              inner.Get("n", &a);
              inner.RejectUnknownKeys();
            }),
            "x.json: key 'inner.typo': unknown key");
  EXPECT_NE(ConfigErrorOf([] { ReadJsonFile("/nonexistent/file.json"); }).find("/nonexistent/file.json"),
            std::string::npos);
}

}  // namespace
}  // namespace slt

namespace slt {
namespace {

TEST(JsonReader, TypesAreStrict) {
  const auto j = nlohmann::json::parse(R"({"n": 2.5, "b": 1, "u": -3, "big": 5000000000, "ok": 7, "x": 3})");
  int n = 0;
  bool b = false;
  unsigned u = 0;
  int big = 0;
  std::uint64_t ok = 0;
  double x = 0.0;
  EXPECT_THROW(JsonReader(j, "f.json").Get("n", &n), ConfigError);
  EXPECT_THROW(JsonReader(j, "f.json").Get("b", &b), ConfigError);
  EXPECT_THROW(JsonReader(j, "f.json").Get("u", &u), ConfigError);
  EXPECT_THROW(JsonReader(j, "f.json").Get("big", &big), ConfigError);
  JsonReader(j, "f.json").Get("ok", &ok).Get("x", &x);
  EXPECT_EQ(ok, 7u);
  EXPECT_EQ(x, 3.0);
  // A document built in code holds 7 as a signed integer.
  nlohmann::json built = {{"ok", 7}};
  JsonReader(built, "code").Get("ok", &ok);
  EXPECT_EQ(ok, 7u);
}

}  // namespace
}  // namespace slt

namespace slt {
namespace {

std::string TempDir(const std::string& name) {
  const std::string dir = std::string(::testing::TempDir()) + "slt_json_reader_" + name;
  std::filesystem::create_directories(dir);
  return dir;
}

// 100 000 levels crashed the parser's callers (stack overflow); the limit is checked while
// parsing, so the message names the file.
TEST(ParseJson, RefusesDeepNesting) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  EXPECT_EQ(ConfigErrorOf([&] { ParseJson(deep, "deep.json"); }),
            "deep.json: invalid JSON (nested deeper than 100 levels)");
  const std::string ok = std::string(kMaxJsonDepth, '[') + "1" + std::string(kMaxJsonDepth, ']');
  EXPECT_TRUE(ParseJson(ok, "ok.json").is_array());
  const std::string one_more = "[" + ok + "]";
  EXPECT_EQ(ConfigErrorOf([&] { ParseJson(one_more, "deep.json"); }),
            "deep.json: invalid JSON (nested deeper than 100 levels)");
  const std::string path = TempDir("deep") + "/deep.json";
  std::ofstream(path) << "{\"a\": " << deep << "}";
  EXPECT_NE(ConfigErrorOf([&] { ReadJsonFile(path); }).find(path + ": invalid JSON (nested deeper"), std::string::npos);
}

// nlohmann reports 1e309 as out_of_range, not parse_error: it escaped without the file name.
TEST(ParseJson, NumberOverflowNamesTheFile) {
  const std::string message = ConfigErrorOf([] { ParseJson(R"({"x": 1e309})", "big.json"); });
  EXPECT_EQ(message.rfind("big.json: invalid JSON (", 0), 0u) << message;
  EXPECT_NE(message.find("1e309"), std::string::npos) << message;
}

TEST(FindNonFiniteNumber, NamesTheKey) {
  nlohmann::json j = {{"a", 1.0}, {"b", {{"c", {1.0, std::nan("")}}}}};
  EXPECT_EQ(FindNonFiniteNumber(j), "b.c[1]");
  j["b"]["c"][1] = 2.0;
  EXPECT_EQ(FindNonFiniteNumber(j), "");
  EXPECT_EQ(FindNonFiniteNumber(nlohmann::json(HUGE_VAL)), "(top level)");
}

TEST(ReadJsonFile, DirectoryNamesTheFile) {
  const std::string dir = TempDir("dir");
  EXPECT_EQ(ConfigErrorOf([&] { ReadJsonFile(dir); }), dir + ": is a directory, expected a file");
}

TEST(JsonReader, SetDottedKeyCreatesObjectsAndKeepsSiblings) {
  nlohmann::json j = {{"noise", {{"model", "gaussian"}}}};
  SetDottedKey(&j, "noise.endpoint_px", 1.5);
  SetDottedKey(&j, "scene.paper.lines", 12);
  EXPECT_EQ(j["noise"]["model"], "gaussian");
  EXPECT_EQ(j["noise"]["endpoint_px"], 1.5);
  EXPECT_EQ(j["scene"]["paper"]["lines"], 12);
  EXPECT_THROW(SetDottedKey(&j, "noise.model.x", 1), std::invalid_argument);
  EXPECT_THROW(SetDottedKey(&j, "noise..x", 1), std::invalid_argument);
}

}  // namespace
}  // namespace slt
