#include "common/json_reader.h"

#include <gtest/gtest.h>

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
