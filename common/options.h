// Option structs declared once. A struct S keeps its fields with their defaults (the C++
// declaration); one OptionSchema<S> lists each field once more with its JSON key, its allowed
// range or enum values and a one-line doc, and everything else derives from that list:
//   Read     strict JSON types (JsonReader::Get), enum names parsed once into the enum, nested
//            objects and arrays of objects with their own schemas, member structs whose
//            fields stand flat among the parent's (Flat: one struct shared by several), then
//            Check;
//   ToJson   every field (what --print-config and config.resolved.json show);
//   Validate each range in order, then the struct-wide checks; errors are ConfigError
//            "<where>: key '<path>.<key>': <reason>" (common/json_reader.h);
//   entries  key, allowed values and doc of every field, for listings.
// Usage (see methods/stereo_ekf/stereo_ekf_options.cc):
//   const OptionSchema<Foo>& FooSchema() {
//     static const OptionSchema<Foo> schema = OptionSchema<Foo>()
//         .Field("rate", &Foo::rate, InRange(0.0, 1.0, "(]"), "fraction per frame")
//         .Field("mode", &Foo::mode, {{Mode::kA, "a"}, {Mode::kB, "b"}}, "what it does");
//     return schema;
//   }
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/json_reader.h"

namespace slt {

// Allowed values of a number: an interval with open or closed ends (or none), optionally
// required finite. Reason() gives the message of a failed check, e.g. "must be in (0, 1]".
struct NumberRange {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  bool finite = false;  // "a finite number" (NaN always fails a bounded range)
  std::string note;     // appended in parentheses, e.g. "0 = all lines"

  bool Contains(double v) const {
    if (finite && !std::isfinite(v)) return false;
    const bool has_lo = lo > -std::numeric_limits<double>::infinity();
    const bool has_hi = hi < std::numeric_limits<double>::infinity();
    if (has_lo && !(lo_open ? v > lo : v >= lo)) return false;
    if (has_hi && !(hi_open ? v < hi : v <= hi)) return false;
    return true;
  }
  // "must be > 0", "must be in [0, 90)", "must be a finite number >= 4.6 (note)".
  std::string Reason() const;
  // "> 0", "[0, 90)", "any" (for listings).
  std::string Allowed() const;
  NumberRange& Finite() {
    finite = true;
    return *this;
  }
  NumberRange& Note(std::string text) {
    note = std::move(text);
    return *this;
  }
};

// The number as a config writes it: integers without a decimal point, others shortest.
std::string FormatOptionNumber(double value);

// `ends` is "[]", "[)", "(]" or "()".
inline NumberRange InRange(double lo, double hi, const char* ends = "[]") {
  NumberRange range;
  range.lo = lo;
  range.hi = hi;
  range.lo_open = ends[0] == '(';
  range.hi_open = ends[1] == ')';
  return range;
}
inline NumberRange AnyNumber() { return {}; }
inline NumberRange AtLeast(double lo) { return InRange(lo, std::numeric_limits<double>::infinity(), "[]"); }
inline NumberRange Positive() { return InRange(0.0, std::numeric_limits<double>::infinity(), "(]"); }

// One line of an option listing (`track --list-options`): dotted key, allowed values, value
// (JSON), one-line doc.
struct OptionDoc {
  std::string key, allowed, value, doc;
};
// The listing as aligned text, one option per line.
std::string FormatOptionDocs(const std::vector<OptionDoc>& docs);

// For "used twice" checks: the first index whose key(item) equals an earlier item's;
// items.size() when every key differs.
template <typename T, typename Key>
size_t FirstRepeat(const std::vector<T>& items, const Key& key) {
  for (size_t i = 0; i < items.size(); ++i) {
    for (size_t k = 0; k < i; ++k) {
      if (key(items[k]) == key(items[i])) return i;
    }
  }
  return items.size();
}

template <typename E>
using EnumNames = std::vector<std::pair<E, const char*>>;

// "must be "a" or "b"" / "must be "a", "b" or "c"".
template <typename E>
std::string EnumReason(const EnumNames<E>& names) {
  std::string out = "must be ";
  for (size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? " or " : ", ";
    out += "\"" + std::string(names[i].second) + "\"";
  }
  return out;
}

template <typename E>
const char* EnumName(const EnumNames<E>& names, E value) {
  for (const auto& [e, name] : names) {
    if (e == value) return name;
  }
  return "unknown";
}

template <typename S>
class OptionSchema {
 public:
  struct Entry {
    std::string key;
    std::string doc;
    std::string allowed;  // for listings
    std::function<void(JsonReader&, S*)> read;
    std::function<nlohmann::json(const S&)> write;
    std::function<std::string(const S&)> check;  // "" = valid, else the reason
    // Nested objects only.
    std::function<void(const S&, const std::string&, const std::string&)> validate_child;
    std::function<void(const S&, const std::string&, std::vector<OptionDoc>*)> list_child;
  };

  // A number (int, unsigned or double) within `range`.
  template <typename T, typename = std::enable_if_t<std::is_arithmetic_v<T> && !std::is_same_v<T, bool>>>
  OptionSchema&& Field(std::string key, T S::*member, NumberRange range, std::string doc) && {
    Entry e = MakeEntry(std::move(key), std::move(doc), range.Allowed());
    const std::string k = e.key;
    e.read = [k, member](JsonReader& r, S* s) { r.Get(k, &(s->*member)); };
    e.write = [member](const S& s) { return nlohmann::json(s.*member); };
    e.check = [member, range](const S& s) {
      return range.Contains(static_cast<double>(s.*member)) ? std::string() : range.Reason();
    };
    entries_.push_back(std::move(e));
    return std::move(*this);
  }
  // An optional number: absent or null leaves it as it is (none by default) and none is
  // written as null; a number is read as Field's are and must lie within `range`.
  template <typename T, typename = std::enable_if_t<std::is_arithmetic_v<T> && !std::is_same_v<T, bool>>>
  OptionSchema&& Field(std::string key, std::optional<T> S::*member, NumberRange range, std::string doc) && {
    const std::string bounds = range.Allowed();
    Entry e = MakeEntry(std::move(key), std::move(doc),
                        std::string("null or ") + (std::is_integral_v<T> ? "an integer" : "a number") +
                            (bounds == "any" ? "" : " " + bounds));
    const std::string k = e.key;
    e.read = [k, member](JsonReader& r, S* s) {
      const nlohmann::json* v = r.Find(k);
      if (v == nullptr || v->is_null()) return;
      T value{};
      r.Get(k, &value);
      s->*member = value;
    };
    e.write = [member](const S& s) { return s.*member ? nlohmann::json(*(s.*member)) : nlohmann::json(); };
    e.check = [member, range](const S& s) {
      return !(s.*member) || range.Contains(static_cast<double>(*(s.*member))) ? std::string() : range.Reason();
    };
    entries_.push_back(std::move(e));
    return std::move(*this);
  }
  OptionSchema&& Field(std::string key, bool S::*member, std::string doc) && {
    Entry e = MakeEntry(std::move(key), std::move(doc), "true or false");
    const std::string k = e.key;
    e.read = [k, member](JsonReader& r, S* s) { r.Get(k, &(s->*member)); };
    e.write = [member](const S& s) { return nlohmann::json(s.*member); };
    entries_.push_back(std::move(e));
    return std::move(*this);
  }
  // A string; one of `allowed` unless that is empty.
  OptionSchema&& Field(std::string key, std::string S::*member, std::vector<std::string> allowed, std::string doc) && {
    std::string reason = "must be ", listed;
    for (size_t i = 0; i < allowed.size(); ++i) {
      const std::string quoted = "\"" + allowed[i] + "\"";
      reason += (i == 0 ? "" : i + 1 == allowed.size() ? " or " : ", ") + quoted;
      listed += (i == 0 ? "" : " | ") + allowed[i];
    }
    Entry e = MakeEntry(std::move(key), std::move(doc), allowed.empty() ? "a string" : listed);
    const std::string k = e.key;
    e.read = [k, member](JsonReader& r, S* s) { r.Get(k, &(s->*member)); };
    e.write = [member](const S& s) { return nlohmann::json(s.*member); };
    e.check = [member, allowed, reason](const S& s) {
      if (allowed.empty() || std::find(allowed.begin(), allowed.end(), s.*member) != allowed.end()) return std::string();
      return reason;
    };
    entries_.push_back(std::move(e));
    return std::move(*this);
  }
  // A JSON object kept as given (options passed on to another part, read there).
  OptionSchema&& Field(std::string key, nlohmann::json S::*member, std::string doc) && {
    Entry e = MakeEntry(std::move(key), std::move(doc), "object");
    const std::string k = e.key;
    e.read = [k, member](JsonReader& r, S* s) {
      const nlohmann::json* v = r.Find(k);
      if (v == nullptr) return;
      if (!v->is_object()) r.Fail(k, std::string("expected an object, got ") + v->type_name());
      s->*member = *v;
    };
    e.write = [member](const S& s) { return s.*member; };
    entries_.push_back(std::move(e));
    return std::move(*this);
  }
  // An enum written as one of `names`.
  template <typename E, typename = std::enable_if_t<std::is_enum_v<E>>>
  OptionSchema&& Field(std::string key, E S::*member, EnumNames<E> names, std::string doc) && {
    std::string allowed;
    for (const auto& [value, name] : names) allowed += (allowed.empty() ? "" : " | ") + std::string(name);
    Entry e = MakeEntry(std::move(key), std::move(doc), allowed);
    const std::string k = e.key;
    e.read = [k, member, names](JsonReader& r, S* s) {
      std::string name = EnumName(names, s->*member);
      r.Get(k, &name);
      for (const auto& [value, n] : names) {
        if (name == n) {
          s->*member = value;
          return;
        }
      }
      r.Fail(k, EnumReason(names));
    };
    e.write = [member, names](const S& s) { return nlohmann::json(EnumName(names, s.*member)); };
    entries_.push_back(std::move(e));
    return std::move(*this);
  }
  // Anything else: its own reader and writer (and check).
  OptionSchema&& Custom(std::string key, std::function<void(JsonReader&, S*)> read,
                        std::function<nlohmann::json(const S&)> write, std::string allowed, std::string doc,
                        std::function<std::string(const S&)> check = nullptr) && {
    Entry e = MakeEntry(std::move(key), std::move(doc), std::move(allowed));
    e.read = std::move(read);
    e.write = std::move(write);
    e.check = std::move(check);
    entries_.push_back(std::move(e));
    return std::move(*this);
  }
  // A nested object, read and written with its own schema (key paths "key.field").
  template <typename C>
  OptionSchema&& Child(std::string key, C S::*member, const OptionSchema<C>& schema, std::string doc) && {
    Entry e = MakeEntry(std::move(key), std::move(doc), "object");
    const std::string k = e.key;
    const OptionSchema<C>* child = &schema;  // schemas are static: they outlive this one
    e.read = [k, member, child](JsonReader& r, S* s) {
      JsonReader c = r.Child(k);
      child->ReadFields(c, &(s->*member));
      c.RejectUnknownKeys();
    };
    e.write = [member, child](const S& s) { return child->ToJson(s.*member); };
    e.validate_child = [k, member, child](const S& s, const std::string& where, const std::string& path) {
      child->Validate(s.*member, where, path.empty() ? k : path + "." + k);
    };
    e.list_child = [member, child](const S& s, const std::string& key, std::vector<OptionDoc>* out) {
      child->List(s.*member, key, out);
    };
    entries_.push_back(std::move(e));
    return std::move(*this);
  }
  // A member struct whose fields stand among this schema's own, under the child schema's keys
  // (no nesting in JSON): one option struct shared by several option structs that keep flat
  // keys. Its fields' reading, writing, checks and listing are the child schema's, in its order.
  template <typename C>
  OptionSchema&& Flat(C S::*member, const OptionSchema<C>& schema) && {
    for (const auto& c : schema.entries()) {
      Entry e = MakeEntry(c.key, c.doc, c.allowed);
      e.read = [member, read = c.read](JsonReader& r, S* s) { read(r, &(s->*member)); };
      if (c.write) e.write = [member, write = c.write](const S& s) { return write(s.*member); };
      if (c.check) e.check = [member, check = c.check](const S& s) { return check(s.*member); };
      if (c.validate_child) {
        e.validate_child = [member, v = c.validate_child](const S& s, const std::string& where, const std::string& path) {
          v(s.*member, where, path);
        };
      }
      if (c.list_child) {
        e.list_child = [member, list = c.list_child](const S& s, const std::string& key, std::vector<OptionDoc>* out) {
          list(s.*member, key, out);
        };
      }
      entries_.push_back(std::move(e));
    }
    for (const auto& [key, check] : schema.checks()) {
      checks_.push_back({key, [member, check = check](const S& s) { return check(s.*member); }});
    }
    return std::move(*this);
  }
  // An array of objects, each read and written with its own schema (key paths "key[i].field");
  // present, it replaces the default elements.
  template <typename C>
  OptionSchema&& Array(std::string key, std::vector<C> S::*member, const OptionSchema<C>& schema, std::string doc) && {
    Entry e = MakeEntry(std::move(key), std::move(doc), "array of objects");
    const std::string k = e.key;
    const OptionSchema<C>* child = &schema;  // schemas are static: they outlive this one
    e.read = [k, member, child](JsonReader& r, S* s) {
      const nlohmann::json* v = r.Find(k);
      if (v == nullptr) return;
      if (!v->is_array()) r.Fail(k, std::string("expected an array of objects, got ") + v->type_name());
      (s->*member).assign(v->size(), C());
      for (size_t i = 0; i < v->size(); ++i) {
        JsonReader item((*v)[i], r.where(), IndexedKey(r.KeyPath(k), i));
        child->ReadFields(item, &(s->*member)[i]);
        item.RejectUnknownKeys();
      }
    };
    e.write = [member, child](const S& s) {
      nlohmann::json items = nlohmann::json::array();
      for (const C& item : s.*member) items.push_back(child->ToJson(item));
      return items;
    };
    e.validate_child = [k, member, child](const S& s, const std::string& where, const std::string& path) {
      for (size_t i = 0; i < (s.*member).size(); ++i) {
        child->Validate((s.*member)[i], where, IndexedKey(path.empty() ? k : path + "." + k, i));
      }
    };
    e.list_child = [child](const S&, const std::string& key, std::vector<OptionDoc>* out) {
      child->List(C(), key + "[]", out);
    };
    entries_.push_back(std::move(e));
    return std::move(*this);
  }
  // A step of reading that is not a key: runs when reading reaches it (e.g. defaults that follow
  // a field read before).
  OptionSchema&& OnRead(std::function<void(S*)> step) && {
    Entry e;
    e.read = [step](JsonReader&, S* s) { step(s); };
    entries_.push_back(std::move(e));
    return std::move(*this);
  }
  // A check that involves more than one field, run after the per-field ones; "" = valid.
  OptionSchema&& Check(std::string key, std::function<std::string(const S&)> check) && {
    checks_.push_back({std::move(key), std::move(check)});
    return std::move(*this);
  }

  // Reads the keys present (the others keep their values), then checks. Unknown keys are the
  // caller's to reject (RejectUnknownKeys), once every part of its object is read.
  void Read(JsonReader& r, S* s) const {
    ReadFields(r, s);
    Validate(*s, r.where(), r.path());
  }
  // Reads without checking (nested objects are checked with their parent).
  void ReadFields(JsonReader& r, S* s) const {
    for (const Entry& e : entries_) e.read(r, s);
  }
  nlohmann::json ToJson(const S& s) const {
    nlohmann::json j = nlohmann::json::object();
    for (const Entry& e : entries_) {
      if (e.write) j[e.key] = e.write(s);
    }
    return j;
  }
  // Throws ConfigError for the first invalid field.
  void Validate(const S& s, const std::string& where, const std::string& path) const {
    for (const Entry& e : entries_) {
      if (e.validate_child) e.validate_child(s, where, path);
      if (!e.check) continue;
      const std::string reason = e.check(s);
      if (!reason.empty()) ThrowOptionError(where, path, e.key, reason);
    }
    for (const auto& [key, check] : checks_) {
      const std::string reason = check(s);
      if (!reason.empty()) ThrowOptionError(where, path, key, reason);
    }
  }
  // Every field with its value in `s` (a default-constructed S: the defaults), nested objects
  // flattened to "key.field", keys prefixed with "<prefix>.".
  void List(const S& s, const std::string& prefix, std::vector<OptionDoc>* out) const {
    for (const Entry& e : entries_) {
      if (e.key.empty()) continue;  // an OnRead step
      const std::string key = prefix.empty() ? e.key : prefix + "." + e.key;
      if (e.list_child) {
        e.list_child(s, key, out);
      } else {
        out->push_back({key, e.allowed, e.write ? e.write(s).dump() : "", e.doc});
      }
    }
  }
  // Every field with its default (`track --list-options` of a tracker with one schema).
  std::vector<OptionDoc> Docs() const {
    std::vector<OptionDoc> docs;
    List(S(), "", &docs);
    return docs;
  }
  const std::vector<Entry>& entries() const { return entries_; }
  const std::vector<std::pair<std::string, std::function<std::string(const S&)>>>& checks() const { return checks_; }

 private:
  static Entry MakeEntry(std::string key, std::string doc, std::string allowed) {
    Entry e;
    e.key = std::move(key);
    e.doc = std::move(doc);
    e.allowed = std::move(allowed);
    return e;
  }

  std::vector<Entry> entries_;
  std::vector<std::pair<std::string, std::function<std::string(const S&)>>> checks_;
};

}  // namespace slt
