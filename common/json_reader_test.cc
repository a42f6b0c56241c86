#include "common/json_reader.h"

#include <gtest/gtest.h>

namespace slt {
namespace {

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

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
  EXPECT_EQ(ErrorOf([&] {
              JsonReader r(j, "x.json");
              double a;
              r.Get("a", &a);
            }),
            "x.json: key 'a': wrong type (string)");
  EXPECT_EQ(ErrorOf([&] {
              JsonReader r(j, "x.json");
              double a;
              r.Find("a");
              JsonReader inner = r.Child("inner");
              inner.Get("n", &a);
              inner.RejectUnknownKeys();
            }),
            "x.json: key 'inner.typo': unknown key");
  EXPECT_NE(ErrorOf([] { ReadJsonFile("/nonexistent/file.json"); }).find("/nonexistent/file.json"),
            std::string::npos);
}

}  // namespace
}  // namespace slt
