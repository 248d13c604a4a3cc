// Reading scene files (TOML) into option structs. Every value is validated where it is read, and
// keys that are never read are reported, so a misspelled key fails loudly instead of silently
// falling back to a default.
#pragma once

#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "asperity/core/common/settings.hpp"

namespace asperity::app {

// Allowed interval for a number (one definition, with the settings tables).
using Range = settings::Range;

// A parsed TOML document with typed, validated access through dotted keys ("contact.a").
// Absent keys yield the caller's default; present keys of the wrong type, non-finite numbers and
// out-of-range values throw std::invalid_argument naming the file, key, value and allowed set.
class SceneReader {
 public:
  static SceneReader from_file(const std::string& path);
  static SceneReader from_string(std::string_view text, std::string source_name);

  const std::string& source_name() const { return source_; }

  // Integers are accepted where a number is expected.
  double number(std::string_view key, double default_value, const Range& range = Range::any());
  std::optional<double> optional_number(std::string_view key, const Range& range = Range::any());
  std::vector<double> numbers(std::string_view key, std::vector<double> default_value,
                              const Range& range = Range::any());
  std::optional<std::vector<double>> optional_numbers(std::string_view key,
                                                      const Range& range = Range::any());

  int integer(std::string_view key, int default_value, const Range& range = Range::any());
  std::optional<int> optional_integer(std::string_view key, const Range& range = Range::any());

  // An empty `allowed` list accepts any string.
  std::string string(std::string_view key, std::string default_value,
                     std::initializer_list<std::string_view> allowed = {});
  std::optional<std::string> optional_string(std::string_view key,
                                             std::initializer_list<std::string_view> allowed = {});

  bool boolean(std::string_view key, bool default_value);
  std::optional<bool> optional_boolean(std::string_view key);

  // The value of a setting (common/settings.hpp) if its key is present: typed and checked
  // against the setting's allowed set, with the file, key, value, allowed set and line in the
  // message of a bad one.
  std::optional<settings::Value> value(const settings::Info& setting);
  // Every setting of a table present in the document, applied to `root`.
  template <class Root>
  void read(const settings::Table<Root>& table, Root& root) {
    for (const settings::Setting<Root>& s : table) {
      if (const auto v = value(s)) s.set(root, *v);
    }
  }

  // Whether `key` is present, whatever its value; does not count as reading it.
  [[nodiscard]] bool has(std::string_view key) const;

  // Throws naming every key present in the document that no getter has asked for.
  void reject_unknown() const;

 private:
  SceneReader(toml::table table, std::string source);
  const toml::node* find(std::string_view key);  // marks the key as read
  // The node at a dotted key, or nullptr; a parent that is not a table throws when `strict`
  // (find's reads), else counts as absent (has()).
  const toml::node* lookup(std::string_view key, bool strict) const;
  double checked_number(std::string_view key, const toml::node& node, const Range& range) const;
  std::string where(const toml::node& node) const;

  toml::table table_;
  std::string source_;
  std::set<std::string, std::less<>> read_;
};

}  // namespace asperity::app
