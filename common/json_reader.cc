#include "common/json_reader.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <system_error>
#include <unistd.h>

namespace slt {

JsonReader::JsonReader(const nlohmann::json& object, std::string where, std::string path)
    : object_(object.is_null() ? nlohmann::json::object() : object),
      where_(std::move(where)),
      path_(std::move(path)) {
  if (!object_.is_object()) {
    throw ConfigError(where_ + ": " + (path_.empty() ? std::string("top level") : "key '" + path_ + "'") +
                      ": expected a JSON object, got " + object_.type_name());
  }
}

const nlohmann::json* JsonReader::Find(const std::string& key) {
  known_.insert(key);
  const auto it = object_.find(key);
  return it == object_.end() ? nullptr : &*it;
}

JsonReader JsonReader::Child(const std::string& key) {
  const nlohmann::json* v = Find(key);
  return JsonReader(v ? *v : nlohmann::json::object(), where_, KeyPath(key));
}

void JsonReader::RejectUnknownKeys() const {
  for (const auto& item : object_.items()) {
    if (!known_.count(item.key())) Fail(item.key(), "unknown key");
  }
}

void JsonReader::Fail(const std::string& key, const std::string& reason) const {
  throw ConfigError(where_ + ": key '" + KeyPath(key) + "': " + reason);
}

void ThrowOptionError(const std::string& where, const std::string& path, const std::string& key,
                      const std::string& reason) {
  throw ConfigError(where + ": key '" + (path.empty() ? key : path + "." + key) + "': " + reason);
}

nlohmann::json ReadJsonFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open file");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw ConfigError(path + ": invalid JSON (" + e.what() + ")");
  }
}

void WriteTextFileAtomically(const std::string& path, const std::string& contents) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot write file");
    out << contents;
    out.flush();
    if (!out) {
      std::remove(tmp.c_str());
      throw std::runtime_error(path + ": write failed");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot move the written file into place");
  }
}

void WriteJsonFile(const std::string& path, const nlohmann::json& value, int indent) {
  WriteTextFileAtomically(path, value.dump(indent) + "\n");
}

}  // namespace slt
