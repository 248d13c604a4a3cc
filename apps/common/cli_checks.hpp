// Command-line number checks that also reject NaN and infinities (CLI11's range validators
// compare, and every comparison with NaN is false, so "--a nan" would pass them).
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <limits>
#include <string>

namespace asperity::app {

// A finite number in [lo, hi]; open_lo excludes lo (for "> 0").
inline CLI::Validator finite_number(double lo, double hi, bool open_lo = false) {
  const std::string allowed = (open_lo ? "> " : ">= ") + CLI::detail::to_string(lo) +
                              (std::isinf(hi) ? "" : " and <= " + CLI::detail::to_string(hi));
  return CLI::Validator(
      [lo, hi, open_lo, allowed](std::string& text) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
        if (!std::isfinite(v) || v < lo || (open_lo && v == lo) || v > hi) {
          return "got " + text + ", allowed: finite, " + allowed;
        }
        return {};
      },
      "NUMBER " + allowed);
}

inline CLI::Validator positive() {
  return finite_number(0.0, std::numeric_limits<double>::infinity(), true);
}
inline CLI::Validator non_negative() {
  return finite_number(0.0, std::numeric_limits<double>::infinity());
}

}  // namespace asperity::app
