#include "common/options.h"

#include <gtest/gtest.h>

#include "common/json_changes.h"

namespace slt {
namespace {

enum class Mode { kFast, kExact };

struct Inner {
  double rate = 0.5;
};

struct Outer {
  int count = 3;
  bool on = true;
  Mode mode = Mode::kFast;
  Inner inner;
  int follows_mode = 0;  // set while reading, from the mode read before it
};

const OptionSchema<Inner>& InnerSchema() {
  static const OptionSchema<Inner> schema =
      OptionSchema<Inner>().Field("rate", &Inner::rate, InRange(0.0, 1.0, "(]"), "a fraction");
  return schema;
}

const OptionSchema<Outer>& OuterSchema() {
  static const OptionSchema<Outer> schema =
      OptionSchema<Outer>()
          .Field("count", &Outer::count, AtLeast(1).Note("one at least"), "how many")
          .Field("on", &Outer::on, "a flag")
          .Field("mode", &Outer::mode, {{Mode::kFast, "fast"}, {Mode::kExact, "exact"}}, "a mode")
          .OnRead([](Outer* o) { o->follows_mode = o->mode == Mode::kExact ? 7 : 1; })
          .Child("inner", &Outer::inner, InnerSchema(), "nested")
          .Check("count", [](const Outer& o) { return o.on || o.count == 3 ? "" : "must be 3 when off"; });
  return schema;
}

std::string ErrorOf(const nlohmann::json& j) {
  try {
    Outer o;
    JsonReader r(j, "o.json", "top");
    OuterSchema().Read(r, &o);
    r.RejectUnknownKeys();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(OptionSchema, ReadsWritesAndParsesModesOnce) {
  Outer o;
  JsonReader r(nlohmann::json{{"count", 5}, {"mode", "exact"}, {"inner", {{"rate", 1.0}}}}, "o.json");
  OuterSchema().Read(r, &o);
  r.RejectUnknownKeys();
  EXPECT_EQ(o.count, 5);
  EXPECT_EQ(o.mode, Mode::kExact);
  EXPECT_EQ(o.inner.rate, 1.0);
  EXPECT_EQ(o.follows_mode, 7);
  EXPECT_TRUE(o.on);  // absent: the default
  const nlohmann::json expected = {{"count", 5}, {"on", true}, {"mode", "exact"}, {"inner", {{"rate", 1.0}}}};
  EXPECT_EQ(OuterSchema().ToJson(o), expected);
}

TEST(OptionSchema, ErrorsNameTheFileAndTheDottedKey) {
  EXPECT_EQ(ErrorOf({{"count", 0}}), "o.json: key 'top.count': must be >= 1 (one at least)");
  EXPECT_EQ(ErrorOf({{"count", 2.5}}), "o.json: key 'top.count': expected an integer, got 2.5");
  EXPECT_EQ(ErrorOf({{"mode", "slow"}}), "o.json: key 'top.mode': must be \"fast\" or \"exact\"");
  EXPECT_EQ(ErrorOf({{"inner", {{"rate", 0.0}}}}), "o.json: key 'top.inner.rate': must be in (0, 1]");
  EXPECT_EQ(ErrorOf({{"inner", {{"rat", 0.1}}}}), "o.json: key 'top.inner.rat': unknown key");
  EXPECT_EQ(ErrorOf({{"on", false}, {"count", 4}}), "o.json: key 'top.count': must be 3 when off");
  EXPECT_EQ(ErrorOf({{"cnt", 4}}), "o.json: key 'top.cnt': unknown key");
  EXPECT_EQ(ErrorOf({{"on", false}}), "no error");
}

struct List {
  std::vector<Inner> items = {Inner()};
  nlohmann::json passed = nlohmann::json::object();
};

const OptionSchema<List>& ListSchema() {
  static const OptionSchema<List> schema = OptionSchema<List>()
                                               .Array("items", &List::items, InnerSchema(), "inner objects")
                                               .Field("passed", &List::passed, "kept as given");
  return schema;
}

std::string ListErrorOf(const nlohmann::json& j) {
  return ConfigErrorOf([&] {
    List l;
    JsonReader r(j, "l.json");
    ListSchema().Read(r, &l);
  });
}

TEST(OptionSchema, ArraysOfObjectsAndObjectsKeptAsGiven) {
  List l;
  JsonReader r(nlohmann::json{{"items", {{{"rate", 0.25}}, nlohmann::json::object()}}, {"passed", {{"a", 1}}}}, "l.json");
  ListSchema().Read(r, &l);
  ASSERT_EQ(l.items.size(), 2u);
  EXPECT_EQ(l.items[0].rate, 0.25);
  EXPECT_EQ(l.items[1].rate, 0.5);  // absent: the default
  EXPECT_EQ(l.passed, nlohmann::json({{"a", 1}}));
  const nlohmann::json expected = {{"items", {{{"rate", 0.25}}, {{"rate", 0.5}}}}, {"passed", {{"a", 1}}}};
  EXPECT_EQ(ListSchema().ToJson(l), expected);
  EXPECT_EQ(ListErrorOf({{"items", {{{"rate", 0.25}}, {{"rate", 2.0}}}}}), "l.json: key 'items[1].rate': must be in (0, 1]");
  EXPECT_EQ(ListErrorOf({{"items", {{{"rat", 0.25}}}}}), "l.json: key 'items[0].rat': unknown key");
  EXPECT_EQ(ListErrorOf({{"items", {1}}}), "l.json: key 'items[0]': expected a JSON object, got number");
  EXPECT_EQ(ListErrorOf({{"items", 1}}), "l.json: key 'items': expected an array of objects, got number");
  EXPECT_EQ(ListErrorOf({{"passed", 1}}), "l.json: key 'passed': expected an object, got number");
  std::vector<OptionDoc> docs;
  ListSchema().List(List(), "", &docs);
  ASSERT_EQ(docs.size(), 2u);
  EXPECT_EQ(docs[0].key, "items[].rate");
}

// Outer's fields and Outer's own, under flat keys in one object.
struct Flattened {
  double level = 2.0;
  Outer shared;
};

const OptionSchema<Flattened>& FlattenedSchema() {
  static const OptionSchema<Flattened> schema = OptionSchema<Flattened>()
                                                    .Field("level", &Flattened::level, Positive(), "its own")
                                                    .Flat(&Flattened::shared, OuterSchema());
  return schema;
}

TEST(OptionSchema, FlatMembersKeepTheirKeysAmongTheParentsOwn) {
  Flattened f;
  JsonReader r(nlohmann::json{{"level", 3.0}, {"count", 5}, {"mode", "exact"}, {"inner", {{"rate", 1.0}}}}, "f.json", "top");
  FlattenedSchema().Read(r, &f);
  r.RejectUnknownKeys();
  EXPECT_EQ(f.level, 3.0);
  EXPECT_EQ(f.shared.count, 5);
  EXPECT_EQ(f.shared.mode, Mode::kExact);
  EXPECT_EQ(f.shared.inner.rate, 1.0);
  EXPECT_EQ(f.shared.follows_mode, 7);  // the child's reading steps run too
  const nlohmann::json expected = {{"level", 3.0}, {"count", 5}, {"on", true}, {"mode", "exact"}, {"inner", {{"rate", 1.0}}}};
  EXPECT_EQ(FlattenedSchema().ToJson(f), expected);
  auto error_of = [](const nlohmann::json& j) {
    return ConfigErrorOf([&] {
      Flattened g;
      JsonReader reader(j, "f.json", "top");
      FlattenedSchema().Read(reader, &g);
    });
  };
  EXPECT_EQ(error_of({{"count", 0}}), "f.json: key 'top.count': must be >= 1 (one at least)");
  EXPECT_EQ(error_of({{"inner", {{"rate", 0.0}}}}), "f.json: key 'top.inner.rate': must be in (0, 1]");
  EXPECT_EQ(error_of({{"on", false}, {"count", 4}}), "f.json: key 'top.count': must be 3 when off");  // its checks
  std::vector<OptionDoc> docs;
  FlattenedSchema().List(Flattened(), "p", &docs);
  std::vector<std::string> keys;
  for (const OptionDoc& d : docs) keys.push_back(d.key);
  EXPECT_EQ(keys, (std::vector<std::string>{"p.level", "p.count", "p.on", "p.mode", "p.inner.rate"}));
  EXPECT_EQ(docs[1].doc, "how many");
  EXPECT_EQ(docs[1].allowed, ">= 1");
}

TEST(FirstRepeat, IndexOfTheFirstKeySeenBefore) {
  const std::vector<std::pair<int, std::string>> items = {{1, "a"}, {2, "b"}, {3, "a"}, {4, "b"}};
  EXPECT_EQ(FirstRepeat(items, [](const auto& item) { return item.second; }), 2u);
  EXPECT_EQ(FirstRepeat(items, [](const auto& item) { return item.first; }), items.size());
  EXPECT_EQ(FirstRepeat(std::vector<int>{}, [](int v) { return v; }), 0u);
}

TEST(NumberRange, ReasonsAndAllowedValues) {
  EXPECT_EQ(Positive().Reason(), "must be > 0");
  EXPECT_EQ(AtLeast(4.6).Finite().Reason(), "must be a finite number >= 4.6");
  EXPECT_EQ(InRange(0.0, 90.0, "[)").Reason(), "must be in [0, 90)");
  EXPECT_EQ(AnyNumber().Finite().Reason(), "must be finite");
  EXPECT_EQ(InRange(0.0, 1.0, "()").Allowed(), "(0, 1)");
  EXPECT_TRUE(InRange(0.0, 1.0, "(]").Contains(1.0));
  EXPECT_FALSE(InRange(0.0, 1.0, "(]").Contains(0.0));
  EXPECT_FALSE(Positive().Contains(std::nan("")));
  EXPECT_FALSE(AtLeast(0.0).Finite().Contains(HUGE_VAL));
  EXPECT_TRUE(AtLeast(0.0).Contains(HUGE_VAL));
  // Every field of a schema has a key, a doc and its allowed values for listings.
  for (const auto& e : OuterSchema().entries()) {
    if (e.key.empty()) continue;  // a reading step
    EXPECT_FALSE(e.doc.empty()) << e.key;
    EXPECT_FALSE(e.allowed.empty()) << e.key;
  }
}

}  // namespace
}  // namespace slt
