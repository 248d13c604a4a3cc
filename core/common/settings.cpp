#include "asperity/core/common/settings.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace asperity::settings {

bool Range::contains(double v) const {
  if (std::isnan(v)) return false;
  if (lower && (lower_closed ? v < *lower : v <= *lower)) return false;
  if (upper && (upper_closed ? v > *upper : v >= *upper)) return false;
  return true;
}

std::string Range::describe(bool integers) const {
  const auto number = [integers](double v) {
    return integers ? std::to_string(static_cast<long long>(v)) : format_number(v);
  };
  // append() rather than "[" + string: GCC 12 warns falsely (-Wrestrict) on the latter.
  if (lower && upper) {
    return std::string(lower_closed ? "[" : "(")
        .append(number(*lower))
        .append(", ")
        .append(number(*upper))
        .append(upper_closed ? "]" : ")");
  }
  if (lower) return std::string(lower_closed ? ">= " : "> ").append(number(*lower));
  if (upper) return std::string(upper_closed ? "<= " : "< ").append(number(*upper));
  return "any";
}

std::string format_number(double v) {
  // Shortest round trip: the text reads back to the same double, so it is exact in
  // fingerprints and as short as the user's own number in messages.
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, end);
}

std::string to_string(const Value& value) {
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, bool>) {
          return v ? "true" : "false";
        } else if constexpr (std::is_same_v<T, long long>) {
          return std::to_string(v);
        } else if constexpr (std::is_same_v<T, double>) {
          return format_number(v);
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          std::string out = "[";
          for (std::size_t i = 0; i < v.size(); ++i)
            out.append(i ? ", " : "").append(format_number(v[i]));
          return out.append("]");
        } else {
          return v;
        }
      },
      value);
}

std::string Info::allowed() const {
  switch (kind) {
    case Kind::boolean:
      return "true or false";
    case Kind::integer:
      return "an integer " + range.describe(true);
    case Kind::number: {
      std::string s = range.describe() == "any" ? "a finite number" : range.describe();
      if (!unit.empty()) s += " " + unit;
      return optional ? s + ", or not given" : s;
    }
    case Kind::numbers: {
      std::string s = "a list of numbers";
      if (range.describe() != "any") s.append(" ").append(range.describe());
      return unit.empty() ? s : s + " " + unit;
    }
    case Kind::choice: {
      std::string list;
      for (const std::string& c : choices)
        list.append(list.empty() ? "one of " : ", ").append("\"").append(c).append("\"");
      return list;
    }
  }
  return "?";
}

namespace {

// The integer `t` writes ("-1", "+1", "01"), or nullopt.
std::optional<long long> integer(const std::string& t) {
  if (t.starts_with("+-")) return std::nullopt;
  const char* first = t.data() + (t.starts_with('+') ? 1 : 0);
  const char* last = t.data() + t.size();
  long long n = 0;
  const auto [end, ec] = std::from_chars(first, last, n);
  if (first == last || ec != std::errc() || end != last) return std::nullopt;
  return n;
}

}  // namespace

std::optional<long long> Info::integer_choice(const std::string& name) const {
  if (kind != Kind::choice || choices.empty()) return std::nullopt;
  for (const std::string& c : choices) {
    if (!integer(c)) return std::nullopt;
  }
  return integer(name);
}

std::string Info::choice_named(const std::string& text) const {
  if (std::find(choices.begin(), choices.end(), text) != choices.end()) return text;
  const std::optional<long long> n = integer(text);
  if (!n) return text;
  for (const std::string& c : choices) {
    if (integer(c) == n) return c;
  }
  return text;
}

void Info::check(const Value& value) const {
  const auto fail = [&] {
    const std::string shown = kind == Kind::choice && std::holds_alternative<std::string>(value)
                                  ? "\"" + std::get<std::string>(value) + "\""
                                  : to_string(value);
    throw std::invalid_argument(key + " = " + shown + ": allowed: " + allowed());
  };
  switch (kind) {
    case Kind::boolean:
      if (!std::holds_alternative<bool>(value)) fail();
      return;
    case Kind::integer:
      // Integer settings are ints.
      if (!std::holds_alternative<long long>(value) ||
          std::get<long long>(value) < std::numeric_limits<int>::min() ||
          std::get<long long>(value) > std::numeric_limits<int>::max() ||
          !range.contains(static_cast<double>(std::get<long long>(value))))
        fail();
      return;
    case Kind::number:
      if (!std::holds_alternative<double>(value)) fail();
      if (not_given(value)) return;
      if (!std::isfinite(std::get<double>(value)) || !range.contains(std::get<double>(value)))
        fail();
      return;
    case Kind::numbers:
      if (!std::holds_alternative<std::vector<double>>(value)) fail();
      for (const double x : std::get<std::vector<double>>(value)) {
        if (!std::isfinite(x) || !range.contains(x)) fail();
      }
      return;
    case Kind::choice:
      if (!std::holds_alternative<std::string>(value)) fail();
      for (const std::string& c : choices) {
        if (c == std::get<std::string>(value)) return;
      }
      fail();
  }
}

}  // namespace asperity::settings
