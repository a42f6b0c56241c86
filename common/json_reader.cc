#include "common/json_reader.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "common/file_io.h"

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

nlohmann::json ParseJson(std::istream& in, const std::string& where) {
  // The callback sees every value as it starts, before the tree under it is built: a deep
  // document is refused after kMaxJsonDepth levels, not parsed (and later copied or destroyed)
  // recursively to the end of the stack.
  using Event = nlohmann::json::parse_event_t;
  const auto limit_depth = [&where](int depth, Event event, nlohmann::json&) {
    // `depth` counts the enclosing levels: the top-level value starts at 0.
    if ((event == Event::object_start || event == Event::array_start) && depth >= kMaxJsonDepth) {
      throw ConfigError(where + ": invalid JSON (nested deeper than " + std::to_string(kMaxJsonDepth) + " levels)");
    }
    return true;
  };
  try {
    return nlohmann::json::parse(in, limit_depth);
  } catch (const nlohmann::json::exception& e) {
    // parse_error, and out_of_range for a number that overflows a double (1e309).
    throw ConfigError(where + ": invalid JSON (" + e.what() + ")");
  }
}

nlohmann::json ParseJson(const std::string& text, const std::string& where) {
  std::istringstream in(text);
  return ParseJson(in, where);
}

nlohmann::json ReadJsonFile(const std::string& path) {
  std::ifstream in;
  try {
    in = OpenInputFile(path);
  } catch (const std::runtime_error& e) {
    throw ConfigError(e.what());
  }
  return ParseJson(in, path);
}

std::string FindNonFiniteNumber(const nlohmann::json& value, const std::string& path) {
  if (value.is_number_float()) return std::isfinite(value.get<double>()) ? "" : (path.empty() ? "(top level)" : path);
  if (value.is_array()) {
    for (size_t i = 0; i < value.size(); ++i) {
      std::string found = FindNonFiniteNumber(value[i], path + "[" + std::to_string(i) + "]");
      if (!found.empty()) return found;
    }
  } else if (value.is_object()) {
    for (const auto& item : value.items()) {
      std::string found = FindNonFiniteNumber(item.value(), path.empty() ? item.key() : path + "." + item.key());
      if (!found.empty()) return found;
    }
  }
  return "";
}

void WriteJsonFile(const std::string& path, const nlohmann::json& value, int indent) {
  WriteTextFileAtomically(path, value.dump(indent) + "\n");
}

void SetDottedKey(nlohmann::json* object, const std::string& dotted_key, const nlohmann::json& value) {
  nlohmann::json* node = object;
  size_t start = 0;
  while (true) {
    const size_t dot = dotted_key.find('.', start);
    const std::string part = dotted_key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (part.empty()) throw std::invalid_argument("malformed dotted key '" + dotted_key + "'");
    if (!node->is_object()) {
      throw std::invalid_argument("'" + dotted_key.substr(0, start ? start - 1 : 0) + "' is not an object");
    }
    if (dot == std::string::npos) {
      (*node)[part] = value;
      return;
    }
    if (!node->contains(part)) (*node)[part] = nlohmann::json::object();
    node = &(*node)[part];
    start = dot + 1;
  }
}

}  // namespace slt
