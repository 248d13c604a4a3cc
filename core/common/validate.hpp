// Checks shared by the validate() functions of option structs: each throws
// std::invalid_argument naming the field, the value and what is allowed.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

namespace asperity {

[[noreturn]] inline void reject(const std::string& field, const std::string& value,
                                const std::string& allowed) {
  throw std::invalid_argument(field + ": got " + value + ", allowed: " + allowed);
}

// field: e.g. "BondedOptions.tolerance".
inline void require_positive(const std::string& field, double value) {
  if (!std::isfinite(value) || !(value > 0.0))
    reject(field, std::to_string(value), "finite and > 0");
}

inline void require_at_least(const std::string& field, long long value, long long minimum) {
  if (value < minimum) reject(field, std::to_string(value), ">= " + std::to_string(minimum));
}

}  // namespace asperity
