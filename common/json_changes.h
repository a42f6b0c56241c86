// For tests that check an options reader reads every key: other values for a JSON leaf,
// different from it, the plausible ones first (fractions stay in (0, 1), counts and scales
// grow), so that a key read but ignored comes back at its old value and shows.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

namespace slt {

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
