#include "asperity/apps/common/toml_reader.hpp"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>

namespace asperity::app {
namespace {

using settings::format_number;

std::string quoted(std::string_view s) {
  return '"' + std::string(s) + '"';
}

// Type name and, for scalars, the value: what the user wrote, for error messages.
std::string describe(const toml::node& node) {
  std::ostringstream os;
  os << node.type();
  if (const auto* s = node.as_string()) {
    os << ' ' << quoted(s->get());
  } else if (node.is_value()) {
    node.visit([&os](const auto& v) { os << ' ' << v; });
  }
  return os.str();
}

}  // namespace

SceneReader::SceneReader(toml::table table, std::string source)
    : table_(std::move(table)), source_(std::move(source)) {}

SceneReader SceneReader::from_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("cannot open scene file '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return from_string(text.str(), path);
}

SceneReader SceneReader::from_string(std::string_view text, std::string source_name) {
  try {
    toml::table table = toml::parse(text, source_name);
    return SceneReader(std::move(table), std::move(source_name));
  } catch (const toml::parse_error& e) {
    const auto& begin = e.source().begin;
    throw std::invalid_argument(source_name + ":" + std::to_string(begin.line) + ":" +
                                std::to_string(begin.column) + ": " + std::string(e.description()));
  }
}

std::string SceneReader::where(const toml::node& node) const {
  return " (line " + std::to_string(node.source().begin.line) + ")";
}

const toml::node* SceneReader::lookup(std::string_view key, bool strict) const {
  const toml::table* table = &table_;
  for (std::size_t start = 0;;) {
    const std::size_t dot = key.find('.', start);
    const toml::node* node = table->get(key.substr(start, dot - start));
    if (!node || dot == std::string_view::npos) return node;
    table = node->as_table();
    if (!table) {
      if (!strict) return nullptr;
      throw std::invalid_argument(source_ + ": key '" + std::string(key) + "': '" +
                                  std::string(key.substr(0, dot)) + "' is a " + describe(*node) +
                                  ", not a table" + where(*node));
    }
    start = dot + 1;
  }
}

bool SceneReader::has(std::string_view key) const {
  return lookup(key, false) != nullptr;
}

const toml::node* SceneReader::find(std::string_view key) {
  read_.emplace(key);
  return lookup(key, true);
}

double SceneReader::checked_number(std::string_view key, const toml::node& node,
                                   const Range& range) const {
  if (!node.is_number()) {
    throw std::invalid_argument(source_ + ": key '" + std::string(key) +
                                "': expected a number, got " + describe(node) + where(node));
  }
  const double v =
      node.is_integer() ? static_cast<double>(*node.value<int64_t>()) : *node.value<double>();
  if (!std::isfinite(v)) {
    throw std::invalid_argument(source_ + ": " + std::string(key) + " = " + format_number(v) +
                                ": not a finite number" + where(node));
  }
  if (!range.contains(v)) {
    throw std::invalid_argument(source_ + ": " + std::string(key) + " = " + format_number(v) +
                                ": allowed: " + range.describe() + where(node));
  }
  return v;
}

std::optional<double> SceneReader::optional_number(std::string_view key, const Range& range) {
  const toml::node* node = find(key);
  if (!node) return std::nullopt;
  return checked_number(key, *node, range);
}

double SceneReader::number(std::string_view key, double default_value, const Range& range) {
  return optional_number(key, range).value_or(default_value);
}

std::optional<std::vector<double>> SceneReader::optional_numbers(std::string_view key,
                                                                 const Range& range) {
  const toml::node* node = find(key);
  if (!node) return std::nullopt;
  const toml::array* array = node->as_array();
  if (!array) {
    throw std::invalid_argument(source_ + ": key '" + std::string(key) +
                                "': expected an array of numbers, got " + describe(*node) +
                                where(*node));
  }
  std::vector<double> values;
  values.reserve(array->size());
  for (std::size_t i = 0; i < array->size(); ++i) {
    const std::string element = std::string(key) + "[" + std::to_string(i) + "]";
    values.push_back(checked_number(element, *array->get(i), range));
  }
  return values;
}

std::vector<double> SceneReader::numbers(std::string_view key, std::vector<double> default_value,
                                         const Range& range) {
  auto values = optional_numbers(key, range);
  return values ? std::move(*values) : std::move(default_value);
}

std::optional<int> SceneReader::optional_integer(std::string_view key, const Range& range) {
  const toml::node* node = find(key);
  if (!node) return std::nullopt;
  if (!node->is_integer()) {
    throw std::invalid_argument(source_ + ": key '" + std::string(key) +
                                "': expected an integer, got " + describe(*node) + where(*node));
  }
  const int64_t v = *node->value<int64_t>();
  if (v < INT_MIN || v > INT_MAX || !range.contains(static_cast<double>(v))) {
    const std::string allowed =
        v < INT_MIN || v > INT_MAX ? "fits in a 32-bit int" : range.describe(true);
    throw std::invalid_argument(source_ + ": " + std::string(key) + " = " + std::to_string(v) +
                                ": allowed: " + allowed + where(*node));
  }
  return static_cast<int>(v);
}

int SceneReader::integer(std::string_view key, int default_value, const Range& range) {
  return optional_integer(key, range).value_or(default_value);
}

std::optional<std::string> SceneReader::optional_string(
    std::string_view key, std::initializer_list<std::string_view> allowed) {
  const toml::node* node = find(key);
  if (!node) return std::nullopt;
  if (!node->is_string()) {
    throw std::invalid_argument(source_ + ": key '" + std::string(key) +
                                "': expected a string, got " + describe(*node) + where(*node));
  }
  std::string v = *node->value<std::string>();
  if (allowed.size() == 0 || std::find(allowed.begin(), allowed.end(), v) != allowed.end()) {
    return v;
  }
  std::string list;
  for (std::string_view a : allowed)
    list += (list.empty() ? "" : ", ") + quoted(a);
  throw std::invalid_argument(source_ + ": " + std::string(key) + " = " + quoted(v) +
                              ": allowed: one of " + list + where(*node));
}

std::string SceneReader::string(std::string_view key, std::string default_value,
                                std::initializer_list<std::string_view> allowed) {
  auto v = optional_string(key, allowed);
  return v ? std::move(*v) : std::move(default_value);
}

std::optional<bool> SceneReader::optional_boolean(std::string_view key) {
  const toml::node* node = find(key);
  if (!node) return std::nullopt;
  if (!node->is_boolean()) {
    throw std::invalid_argument(source_ + ": key '" + std::string(key) +
                                "': expected a boolean, got " + describe(*node) + where(*node));
  }
  return *node->value<bool>();
}

std::optional<settings::Value> SceneReader::value(const settings::Info& setting) {
  const std::string_view key = setting.key;
  switch (setting.kind) {
    case settings::Kind::boolean:
      if (const auto v = optional_boolean(key)) return settings::Value(*v);
      return std::nullopt;
    case settings::Kind::integer:
      if (const auto v = optional_integer(key, setting.range))
        return settings::Value(static_cast<long long>(*v));
      return std::nullopt;
    case settings::Kind::number:
      if (const auto v = optional_number(key, setting.range)) return settings::Value(*v);
      return std::nullopt;
    case settings::Kind::numbers:
      if (auto v = optional_numbers(key, setting.range)) return settings::Value(std::move(*v));
      return std::nullopt;
    case settings::Kind::choice: {
      const toml::node* node = find(key);
      if (!node) return std::nullopt;
      if (!node->is_string()) {
        throw std::invalid_argument(source_ + ": key '" + std::string(key) +
                                    "': expected a string, got " + describe(*node) + where(*node));
      }
      const settings::Value v(*node->value<std::string>());
      try {
        setting.check(v);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(source_ + ": " + e.what() + where(*node));
      }
      return v;
    }
  }
  return std::nullopt;
}

bool SceneReader::boolean(std::string_view key, bool default_value) {
  return optional_boolean(key).value_or(default_value);
}

void SceneReader::reject_unknown() const {
  std::vector<std::string> unknown;
  // Leaves are values and empty tables; a non-empty table is known through its children.
  std::function<void(const toml::table&, const std::string&)> walk =
      [&](const toml::table& table, const std::string& prefix) {
        for (const auto& [k, node] : table) {
          const std::string key = prefix + std::string(k.str());
          const toml::table* sub = node.as_table();
          if (sub && !sub->empty()) {
            walk(*sub, key + ".");
          } else if (!read_.contains(key)) {
            unknown.push_back(key + where(node));
          }
        }
      };
  walk(table_, "");
  if (unknown.empty()) return;
  std::string list;
  for (const auto& key : unknown)
    list += (list.empty() ? "" : ", ") + key;
  throw std::invalid_argument(source_ + ": unknown key" + (unknown.size() > 1 ? "s" : "") +
                              " (misspelled?): " + list);
}

}  // namespace asperity::app
