// For the tests of config readers. ConfigErrorOf: the message of the ConfigError a call
// throws; ExceptionMessageOf, of any exception (readers of other files). ChangedJsonValues: other values for a JSON leaf, different from it, the plausible ones
// first (fractions stay in (0, 1), counts and scales grow), so that a key read but ignored comes
// back at its old value and shows.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <nlohmann/json.hpp>
#include <vector>

#include "common/json_reader.h"

namespace slt {

// The message of the ConfigError that f throws, or "" when it throws none.
inline std::string ConfigErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

// The message of the std::exception that f throws, or "" when it throws none.
inline std::string ExceptionMessageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// Empty for null, objects and arrays; strings get one value no enum accepts.
inline std::vector<nlohmann::json> ChangedJsonValues(const nlohmann::json& value) {
  if (value.is_boolean()) return {!value.get<bool>()};
  if (value.is_number_unsigned()) return {value.get<std::uint64_t>() + 1};
  if (value.is_number_integer()) {
    const std::int64_t v = value.get<std::int64_t>();
    return {v + 1, v - 1};
  }
  if (value.is_number_float()) {
    const double v = value.get<double>();
    if (v == 0.0) return {0.5};
    if (v > 0.0 && v < 1.0) return {0.5 * v, 1.5 * v};
    return {1.5 * v, 0.5 * v};
  }
  if (value.is_string()) return {"no such value"};
  return {};
}

}  // namespace slt
