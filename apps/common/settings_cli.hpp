// Command-line flags made from a settings table (common/settings.hpp): every setting that names
// a flag gets one, with its meaning, unit and allowed set as help and its check at parse time.
// The values are kept as given until the scene is read, then applied over it: a flag overrides
// the scene's key.
#pragma once

#include <algorithm>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "asperity/apps/common/cli.hpp"
#include "asperity/core/common/settings.hpp"

namespace asperity::app {

// Parses a flag's text as the setting's kind (a number, an integer, true/false, a choice) and
// checks it against the setting's allowed set; throws std::invalid_argument with the reason.
settings::Value parse_setting(const settings::Info& setting, const std::string& text);

// The help line of a setting: "<meaning>; <key_label> <key>, allowed: <allowed>" (numbers carry
// their unit in the allowed set). The label says where the key is found: a scene file's, or
// for a tool without one the summary.json echo's.
std::string setting_help(const settings::Info& setting, const std::string& key_label = "scene key");

// Every setting of `root` as {key: value} (numbers, integers, booleans, choice names; a choice
// named by integers, a sign, as its integer): the echo of a run's settings in its summary.json.
// `skip`: keys left out (a sweep's contact.a and contact.R, which its points set).
template <class Root>
nlohmann::json settings_echo(const Root& root, const settings::Table<Root>& table,
                             const std::vector<std::string>& skip = {}) {
  nlohmann::json out = nlohmann::json::object();
  for (const settings::Setting<Root>& s : table) {
    if (std::find(skip.begin(), skip.end(), s.key) != skip.end()) continue;
    const settings::Value v = s.get(root);
    if (s.not_given(v)) {
      out[s.key] = nullptr;
      continue;
    }
    if (const auto* name = std::get_if<std::string>(&v)) {
      if (const auto n = s.integer_choice(*name)) {
        out[s.key] = *n;
        continue;
      }
    }
    std::visit([&](const auto& x) { out[s.key] = x; }, v);
  }
  return out;
}

// A Markdown table of the settings: key, default (the value in `defaults`), allowed, flag,
// meaning. The reference of a tool's scene keys (docs/settings.md is made from it).
// `skip`: keys left out (a sweep scene's contact.a and contact.R, which its points set);
// `header`: false for rows that continue another table (a tool whose scene joins two tables).
template <class Root>
std::string settings_markdown(const Root& defaults, const settings::Table<Root>& table,
                              const std::vector<std::string>& skip = {}, bool header = true) {
  std::string out =
      header ? "| key | default | allowed | flag | meaning |\n|---|---|---|---|---|\n" : "";
  // A "|" inside a cell ends it: escaped.
  const auto cell = [](const std::string& text) {
    std::string escaped;
    for (const char c : text) {
      if (c == '|') escaped.push_back('\\');
      escaped.push_back(c);
    }
    return escaped;
  };
  for (const settings::Setting<Root>& s : table) {
    if (std::find(skip.begin(), skip.end(), s.key) != skip.end()) continue;
    const settings::Value v = s.get(defaults);
    std::string value = settings::to_string(v);
    if (s.kind == settings::Kind::choice) value = "\"" + value + "\"";
    if (s.not_given(v)) value = "not given";
    out.append("| `").append(s.key).append("` | ").append(value).append(" | ");
    out.append(s.allowed()).append(" | ").append(s.flag.empty() ? "" : "`" + s.flag + "`");
    out.append(" | ")
        .append(cell(s.meaning))
        .append(s.affects_results ? "" : " (does not change results)");
    out.append(" |\n");
  }
  return out;
}

// --list-settings: prints `table_text()` (settings_markdown() of the tool's tables) and ends the
// parse as --help does (parse_command_line() returns false: exit status 0, nothing run). `what`
// names the rows ("setting", "scene key"), `doc` where the table is kept. The flag's callback
// runs after the parse and before CLI11 checks required arguments, so a tool's required inputs
// need not be given with it.
inline void add_list_settings(CLI::App& cli, std::function<std::string()> table_text,
                              const std::string& doc, const std::string& what = "setting") {
  cli.add_flag_callback(
      "--list-settings",
      [table_text = std::move(table_text)] {
        std::printf("%s", table_text().c_str());
        throw CLI::Success();
      },
      "Print every " + what + " (default, allowed values, flag, meaning) as a Markdown table and " +
          "exit (" + doc + ")");
}

// The same for one table, with the defaults of `defaults`. The table must outlive the parse (the
// flag keeps a reference): a settings() table, static; a temporary is refused.
template <class Root>
void add_list_settings(CLI::App& cli, settings::Table<Root>&& table, Root defaults,
                       const std::string& doc, const std::string& what = "setting") = delete;
template <class Root>
void add_list_settings(CLI::App& cli, const settings::Table<Root>& table, Root defaults,
                       const std::string& doc, const std::string& what = "setting") {
  add_list_settings(
      cli, [&table, defaults = std::move(defaults)] { return settings_markdown(defaults, table); },
      doc, what);
}

class SettingFlags {
 public:
  // Adds a flag for every row of `table` that names one (`only`: of these keys alone);
  // `key_label` as setting_help's. With `defaults`, the help shows each flag's default (for a
  // tool without a scene file, whose defaults are the structs'; a scene tool's flag overrides
  // the scene's value, so it shows none).
  template <class Root>
  void add(CLI::App& cli, const settings::Table<Root>& table,
           const std::vector<std::string>& only = {}, const std::string& key_label = "scene key",
           const Root* defaults = nullptr) {
    for (const settings::Setting<Root>& s : table) {
      if (s.flag.empty()) continue;
      if (!only.empty() && std::find(only.begin(), only.end(), s.key) == only.end()) continue;
      const settings::Info info = s;
      const auto check = CLI::Validator(
          [info](std::string& text) -> std::string {
            try {
              parse_setting(info, text);
            } catch (const std::invalid_argument& e) {
              return e.what();
            }
            return {};
          },
          "");
      CLI::Option* option = nullptr;
      if (info.kind == settings::Kind::boolean) {
        // A switch: "--xyz" alone is true, "--xyz=false" false (and "--xyz false", joined by
        // parse_command_line()); it takes the Python layer's True (a bare flag) and never
        // swallows a file name after it.
        option = cli.add_flag(s.flag)
                     ->description(setting_help(s, key_label) + " (the flag alone: true)")
                     ->type_name(kBooleanFlagType);
        option->each([this, key = info.key](const std::string& text) { given_[key] = text; });
        option->check(check);
      } else {
        option =
            cli.add_option_function<std::string>(
                   s.flag, [this, key = info.key](const std::string& text) { given_[key] = text; },
                   setting_help(s, key_label))
                ->check(check)
                ->type_name(info.kind == settings::Kind::choice    ? "CHOICE"
                            : info.kind == settings::Kind::integer ? "INT"
                            : info.kind == settings::Kind::numbers ? "LIST"
                                                                   : "NUMBER");
      }
      if (defaults != nullptr) {
        const settings::Value v = s.get(*defaults);
        // A switch's default goes into its help: CLI11's is what the flag alone gives.
        if (info.kind == settings::Kind::boolean) {
          option->description(option->get_description() + "; default " + settings::to_string(v));
        } else if (!s.not_given(v)) {
          option->default_str(settings::to_string(v));
        }
      }
    }
  }

  // Whether the flag of `key` was given.
  [[nodiscard]] bool given(const std::string& key) const { return given_.contains(key); }
  // Applies every given flag whose setting is in `table` to `root`.
  template <class Root>
  void apply(const settings::Table<Root>& table, Root& root) const {
    for (const settings::Setting<Root>& s : table) {
      if (const auto found = given_.find(s.key); found != given_.end())
        s.set(root, parse_setting(s, found->second));
    }
  }

 private:
  std::map<std::string, std::string> given_;  // key -> the flag's text
};

}  // namespace asperity::app
