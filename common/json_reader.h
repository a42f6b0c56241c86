// Reading option structs from JSON with errors that name the file and the key.
//
// Every config in the project (simulation, trackers, experiments) is a JSON object whose
// fields all have defaults: a missing key keeps the default, an unknown key or a value of the
// wrong type is an error. Errors are ConfigError exceptions whose message reads
//   "<where>: key '<path>': <reason>"
// where <where> names the file (or "--config" flag) and <path> is the dotted key path.
#pragma once

#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>
#include <string>

namespace slt {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class JsonReader {
 public:
  // `where` names the source ("sim.json"), `path` the object's dotted key path ("" at the top).
  JsonReader(const nlohmann::json& object, std::string where, std::string path = "");

  // Reads `key` into *value when present; keeps *value (the default) when absent.
  template <typename T>
  JsonReader& Get(const std::string& key, T* value) {
    const nlohmann::json* v = Find(key);
    if (v == nullptr) return *this;
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

 private:
  nlohmann::json object_;
  std::string where_;
  std::string path_;
  std::set<std::string> known_;
};

// Parses a JSON file; throws ConfigError naming the file on I/O or syntax errors.
nlohmann::json ReadJsonFile(const std::string& path);
// Writes atomically (temporary file + rename): readers never see a half-written file.
void WriteJsonFile(const std::string& path, const nlohmann::json& value, int indent = 2);
void WriteTextFileAtomically(const std::string& path, const std::string& contents);

}  // namespace slt
