// Reading option structs from JSON with errors that name the file and the key.
//
// Every config in the project (simulation, trackers, experiments) is a JSON object whose
// fields all have defaults: a missing key keeps the default, an unknown key or a value of the
// wrong type is an error. Errors are ConfigError exceptions whose message reads
//   "<where>: key '<path>': <reason>"
// where <where> names the file (or "--config" flag) and <path> is the dotted key path.
#pragma once

#include <nlohmann/json.hpp>
#include <cstdint>
#include <istream>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "common/file_io.h"

namespace slt {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class JsonReader {
 public:
  // `where` names the source ("sim.json"), `path` the object's dotted key path ("" at the top).
  JsonReader(const nlohmann::json& object, std::string where, std::string path = "");

  // Reads `key` into *value when present; keeps *value (the default) when absent. Types are
  // strict: a bool must be true/false, an integer must be a JSON integer in range (2.5 is not
  // read as 2), a floating-point value any number.
  template <typename T>
  JsonReader& Get(const std::string& key, T* value) {
    const nlohmann::json* v = Find(key);
    if (v == nullptr) return *this;
    if constexpr (std::is_same_v<T, bool>) {
      if (!v->is_boolean()) Fail(key, std::string("expected true or false, got ") + v->type_name());
    } else if constexpr (std::is_integral_v<T>) {
      const char* expected = std::is_unsigned_v<T> ? "expected a non-negative integer, got " : "expected an integer, got ";
      if (!v->is_number_integer() || (std::is_unsigned_v<T> && !v->is_number_unsigned() && v->get<std::int64_t>() < 0)) {
        Fail(key, expected + v->dump());
      }
      // Parsed documents hold non-negative integers as unsigned, built ones as signed.
      const bool in_range =
          v->is_number_unsigned()
              ? v->get<std::uint64_t>() <= static_cast<std::uint64_t>(std::numeric_limits<T>::max())
              : (v->get<std::int64_t>() >= static_cast<std::int64_t>(std::numeric_limits<T>::min()) &&
                 (v->get<std::int64_t>() < 0 ||
                  static_cast<std::uint64_t>(v->get<std::int64_t>()) <=
                      static_cast<std::uint64_t>(std::numeric_limits<T>::max())));
      if (!in_range) Fail(key, "integer out of range: " + v->dump());
    } else if constexpr (std::is_floating_point_v<T>) {
      if (!v->is_number()) Fail(key, std::string("expected a number, got ") + v->type_name());
    }
    try {
      *value = v->get<T>();
    } catch (const nlohmann::json::exception& e) {
      Fail(key, std::string("wrong type (") + v->type_name() + ")");
    }
    return *this;
  }
  // A nested object; absent gives an empty object (all defaults).
  JsonReader Child(const std::string& key);
  // The raw value of `key`, or nullptr; marks the key as known.
  const nlohmann::json* Find(const std::string& key);
  bool Has(const std::string& key) const { return object_.contains(key); }

  // Throws naming the first key that was never asked for (a typo in a config must not be
  // silently ignored).
  void RejectUnknownKeys() const;
  // Throws "<where>: key '<path.key>': <reason>".
  [[noreturn]] void Fail(const std::string& key, const std::string& reason) const;
  std::string KeyPath(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  const std::string& where() const { return where_; }
  const std::string& path() const { return path_; }

 private:
  nlohmann::json object_;
  std::string where_;
  std::string path_;
  std::set<std::string> known_;
};

// The key path of an array element: "key[i]".
inline std::string IndexedKey(const std::string& key, size_t i) { return key + "[" + std::to_string(i) + "]"; }

// For the Check() methods of option structs: throws ConfigError
// "<where>: key '<path>.<key>': <reason>" (path may be empty).
[[noreturn]] void ThrowOptionError(const std::string& where, const std::string& path,
                                   const std::string& key, const std::string& reason);

// Deeper nesting is refused while parsing: no file of the project nests more than a handful of
// levels, and nlohmann's recursive copy and destruction would overflow the stack long before
// the parser stops (100 000 levels crash).
constexpr int kMaxJsonDepth = 100;

// Parses JSON; throws ConfigError "<where>: invalid JSON (...)" on a syntax error, a number
// that overflows a double (1e309) or nesting deeper than kMaxJsonDepth. Every JSON reader of the
// project parses through these.
nlohmann::json ParseJson(std::istream& in, const std::string& where);
nlohmann::json ParseJson(const std::string& text, const std::string& where);
// Parses a JSON file; throws ConfigError naming the file on I/O or syntax errors (a directory
// is an I/O error).
nlohmann::json ReadJsonFile(const std::string& path);
// The dotted key path ("a.b[2]") of the first number in `value` that is not finite (nlohmann
// holds NaN and infinity and dumps them as null); "" when every number is finite.
std::string FindNonFiniteNumber(const nlohmann::json& value, const std::string& path = "");
// Sets `value` at the dotted key path ("scene.paper.lines") in `object`, creating intermediate
// objects. Throws std::invalid_argument on an empty part or a part that is not an object.
void SetDottedKey(nlohmann::json* object, const std::string& dotted_key, const nlohmann::json& value);
// Writes atomically (temporary file + rename; WriteTextFileAtomically, common/file_io.h).
void WriteJsonFile(const std::string& path, const nlohmann::json& value, int indent = 2);

}  // namespace slt
