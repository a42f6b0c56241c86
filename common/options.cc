#include "common/options.h"

#include <cstdio>

namespace slt {

std::string FormatOptionDocs(const std::vector<OptionDoc>& docs) {
  size_t key_width = 3, value_width = 7;
  for (const OptionDoc& d : docs) {
    key_width = std::max(key_width, d.key.size());
    value_width = std::max(value_width, d.value.size());
  }
  auto pad = [](const std::string& s, size_t width) { return s + std::string(width - s.size() + 2, ' '); };
  std::string out = pad("key", key_width) + pad("default", value_width) + "allowed: doc\n";
  for (const OptionDoc& d : docs) out += pad(d.key, key_width) + pad(d.value, value_width) + d.allowed + ": " + d.doc + "\n";
  return out;
}

std::string FormatOptionNumber(double value) {
  if (std::isfinite(value) && value == std::floor(value) && std::abs(value) < 1e15) {
    return std::to_string(static_cast<long long>(value));
  }
  char buffer[32];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buffer, sizeof(buffer), "%.*g", precision, value);
    if (std::strtod(buffer, nullptr) == value) break;
  }
  return buffer;
}

std::string NumberRange::Allowed() const {
  const bool has_lo = lo > -std::numeric_limits<double>::infinity();
  const bool has_hi = hi < std::numeric_limits<double>::infinity();
  std::string out;
  if (has_lo && has_hi) {
    out = std::string(lo_open ? "(" : "[") + FormatOptionNumber(lo) + ", " + FormatOptionNumber(hi) +
          (hi_open ? ")" : "]");
  } else if (has_lo) {
    out = std::string(lo_open ? "> " : ">= ") + FormatOptionNumber(lo);
  } else if (has_hi) {
    out = std::string(hi_open ? "< " : "<= ") + FormatOptionNumber(hi);
  } else {
    out = finite ? "finite" : "any";
  }
  return out;
}

std::string NumberRange::Reason() const {
  const bool has_lo = lo > -std::numeric_limits<double>::infinity();
  const bool has_hi = hi < std::numeric_limits<double>::infinity();
  std::string out = "must be ";
  if (finite) out += has_lo || has_hi ? "a finite number " : "finite";
  if (has_lo && has_hi) out += "in ";
  if (has_lo || has_hi) out += Allowed();
  if (!note.empty()) out += " (" + note + ")";
  return out;
}

}  // namespace slt
