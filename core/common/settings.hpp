// One description per setting (issue 24). Each options struct publishes a table of its settings:
// key, kind, allowed range or choices, unit, meaning, the command-line flag a tool offers for it,
// and how to get and set it. Everything that handles settings is made from the table:
// - validate(): the struct's validate() checks every row (one allowed set per setting);
// - the scene reader (apps/common/toml_reader: SceneReader::read): a TOML key per row, typed and
//   range-checked;
// - command-line flags (apps/common/settings_cli: SettingFlags): a flag per row that names one;
// - fingerprints of checkpoints and sweeps (fingerprint()): every row, exact values;
// - the summary.json echo of a run (apps/common/settings_cli: settings_echo).
// Defaults are the struct's own member initialisers: a table holds none.
//
// Tables compose: lift() re-roots the rows of a member struct (a slide's minimiser options
// under "solver."), so a setting is described where its struct is declared and nowhere else.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace asperity::settings {

// Allowed interval of a number; either bound may be absent, open or closed.
struct Range {
  std::optional<double> lower, upper;
  bool lower_closed = true, upper_closed = true;

  static Range any() { return {}; }
  static Range positive() { return {0.0, std::nullopt, false, true}; }
  static Range non_negative() { return {0.0, std::nullopt, true, true}; }
  static Range at_least(double a) { return {a, std::nullopt, true, true}; }
  static Range greater_than(double a) { return {a, std::nullopt, false, true}; }
  static Range at_most(double b) { return {std::nullopt, b, true, true}; }
  static Range less_than(double b) { return {std::nullopt, b, true, false}; }
  static Range closed(double a, double b) { return {a, b, true, true}; }
  static Range open(double a, double b) { return {a, b, false, false}; }
  static Range closed_open(double a, double b) { return {a, b, true, false}; }
  static Range open_closed(double a, double b) { return {a, b, false, true}; }

  [[nodiscard]] bool contains(double v) const;  // false for NaN
  // e.g. "> 0", ">= 1", "[0, 0.5)", "any"; `integers`: bounds written as integers (1000000).
  [[nodiscard]] std::string describe(bool integers = false) const;
};

// Shortest text that reads back to the same double (std::to_chars: 0.1, 1e-05, 4096).
std::string format_number(double v);

enum class Kind { boolean, integer, number, choice, numbers };

// A setting's value: bool, integer (long long), number (double), choice (string) or a list of
// numbers (a sweep's radii, a scan's core widths; empty: not given).
using Value = std::variant<bool, long long, double, std::string, std::vector<double>>;
// As it reads in a scene file and a fingerprint: true/false, the integer, format_number(), the
// choice's name, [x, y, ...].
std::string to_string(const Value& value);

// What a setting is, apart from the struct it lives in.
struct Info {
  std::string key;  // dotted name: the scene file's key; its name in messages, fingerprints and
                    // summaries
  Kind kind = Kind::number;
  Range range;                       // integer and number
  std::vector<std::string> choices;  // choice
  std::string unit;                  // e.g. "d", "G d^2"; empty: dimensionless or none
  std::string meaning;               // one line
  std::string flag;                  // command-line flag of the tools ("--tolerance"); empty: none
  // false for settings that do not change a result, only how it is computed or written (FFT
  // threads: the threaded passes give the same bits on any number, common/parallel.hpp; output
  // formats and path frames): left out of fingerprint(..., results_only) so that a sweep
  // reuses its rows whatever the threads.
  bool affects_results = true;
  // A number that may be left out (a std::optional<double> field, optional_number()): NaN is its
  // value when not given, allowed by check(), echoed as null and listed as "not given".
  bool optional = false;

  // "(0, 1) G d^2", "integer >= 1", "one of \"lbfgs\", \"cg\"", "true or false".
  [[nodiscard]] std::string allowed() const;
  // Throws std::invalid_argument "<key> = <value>: allowed: <allowed()>" if the value is not of
  // the kind or not allowed (a number must also be finite).
  void check(const Value& value) const;
  // The choice that `text` names: `text` itself, or, for choices named by integers (a sign:
  // "-1", "1"), the one equal to it as an integer ("+1", "01"); else `text` unchanged (check()
  // then refuses it).
  [[nodiscard]] std::string choice_named(const std::string& text) const;
  // For a choice whose names are all integers (a sign: "-1", "1"), the integer `name` writes;
  // else nullopt. Echoes (summary.json) give such a choice as that number.
  [[nodiscard]] std::optional<long long> integer_choice(const std::string& name) const;
  // Whether `value` is an optional number's "not given" (NaN in a row with `optional`): echoed
  // as null, listed as "not given", shown without a default.
  [[nodiscard]] bool not_given(const Value& value) const {
    return optional && std::holds_alternative<double>(value) && std::isnan(std::get<double>(value));
  }
};

template <class Root>
struct Setting : Info {
  std::function<Value(const Root&)> get;
  std::function<void(Root&, const Value&)> set;  // callers check the value first (check())
};

template <class Root>
using Table = std::vector<Setting<Root>>;

// Rows over an accessor: a generic lambda returning a reference to the field, callable on both a
// Root& and a const Root&, e.g. [](auto& s) -> auto& { return s.max_step; }.
template <class Root, class Ref>
Setting<Root> number(std::string key, Ref ref, Range range, std::string unit, std::string meaning,
                     std::string flag = {}) {
  Setting<Root> s;
  static_cast<Info&>(s) = {std::move(key),  Kind::number,       range,          {},
                           std::move(unit), std::move(meaning), std::move(flag)};
  s.get = [ref](const Root& r) { return Value(static_cast<double>(ref(r))); };
  s.set = [ref](Root& r, const Value& v) { ref(r) = std::get<double>(v); };
  return s;
}

template <class Root, class Ref>
Setting<Root> integer(std::string key, Ref ref, Range range, std::string unit, std::string meaning,
                      std::string flag = {}) {
  Setting<Root> s;
  static_cast<Info&>(s) = {std::move(key),  Kind::integer,      range,          {},
                           std::move(unit), std::move(meaning), std::move(flag)};
  s.get = [ref](const Root& r) { return Value(static_cast<long long>(ref(r))); };
  s.set = [ref](Root& r, const Value& v) {
    ref(r) = static_cast<std::remove_cvref_t<decltype(ref(r))>>(std::get<long long>(v));
  };
  return s;
}

template <class Root, class Ref>
Setting<Root> boolean(std::string key, Ref ref, std::string meaning, std::string flag = {}) {
  Setting<Root> s;
  static_cast<Info&>(s) = {std::move(key),     Kind::boolean,  {}, {}, {},
                           std::move(meaning), std::move(flag)};
  s.get = [ref](const Root& r) { return Value(static_cast<bool>(ref(r))); };
  s.set = [ref](Root& r, const Value& v) { ref(r) = std::get<bool>(v); };
  return s;
}

// A choice among names; `name` and `parse` convert the field (an enum, or a string) to and from
// them.
template <class Root, class Ref, class Name, class Parse>
Setting<Root> choice(std::string key, Ref ref, std::vector<std::string> choices, Name name,
                     Parse parse, std::string meaning, std::string flag = {}) {
  Setting<Root> s;
  static_cast<Info&>(s) = {std::move(key),     Kind::choice,   {}, std::move(choices), {},
                           std::move(meaning), std::move(flag)};
  s.get = [ref, name](const Root& r) { return Value(std::string(name(ref(r)))); };
  s.set = [ref, parse](Root& r, const Value& v) { ref(r) = parse(std::get<std::string>(v)); };
  return s;
}

// A list of numbers, each finite and within `range` (an empty list: not given; whether one must
// be is the struct's validate() to say, as it is for lists that exclude each other).
template <class Root, class Ref>
Setting<Root> numbers(std::string key, Ref ref, Range range, std::string unit, std::string meaning,
                      std::string flag = {}) {
  Setting<Root> s;
  static_cast<Info&>(s) = {std::move(key),  Kind::numbers,      range,          {},
                           std::move(unit), std::move(meaning), std::move(flag)};
  s.get = [ref](const Root& r) { return Value(std::vector<double>(ref(r))); };
  s.set = [ref](Root& r, const Value& v) { ref(r) = std::get<std::vector<double>>(v); };
  return s;
}

// A number that may be left out: a std::optional<double> field, NaN in the row's value when it is
// not given (Info::optional); when given, finite and within `range`.
template <class Root, class Ref>
Setting<Root> optional_number(std::string key, Ref ref, Range range, std::string unit,
                              std::string meaning, std::string flag = {}) {
  Setting<Root> s;
  static_cast<Info&>(s) = {std::move(key),  Kind::number,       range,          {},
                           std::move(unit), std::move(meaning), std::move(flag)};
  s.optional = true;
  s.get = [ref](const Root& r) {
    const std::optional<double>& v = ref(r);
    return Value(v ? *v : std::numeric_limits<double>::quiet_NaN());
  };
  s.set = [ref](Root& r, const Value& v) {
    const double x = std::get<double>(v);
    ref(r) = std::isnan(x) ? std::nullopt : std::optional<double>(x);
  };
  return s;
}

// The row, marked as not changing results (Info::affects_results).
template <class Root>
Setting<Root> neutral(Setting<Root> s) {
  s.affects_results = false;
  return s;
}

// A choice stored as its name (a std::string field).
template <class Root, class Ref>
Setting<Root> choice(std::string key, Ref ref, std::vector<std::string> choices,
                     std::string meaning, std::string flag = {}) {
  const auto same = [](const std::string& name) { return name; };
  return choice<Root>(std::move(key), ref, std::move(choices), same, same, std::move(meaning),
                      std::move(flag));
}

// The rows of a member's table under `prefix`, reached through `project`, a generic lambda
// returning a reference to the member ([](auto& s) -> auto& { return s.minimizer; }).
template <class Root, class Part, class Project>
void lift(Table<Root>& into, const Table<Part>& part, const std::string& prefix, Project project) {
  for (const Setting<Part>& p : part) {
    Setting<Root> s;
    static_cast<Info&>(s) = static_cast<const Info&>(p);
    s.key = prefix + p.key;
    s.get = [get = p.get, project](const Root& r) { return get(project(r)); };
    s.set = [set = p.set, project](Root& r, const Value& v) { set(project(r), v); };
    into.push_back(std::move(s));
  }
}

// A tool's narrower allowed range for a row it lifted: gf_validate compares converged solutions
// with analytic ones, so it allows tolerances below 0.01 where the solvers' own tables allow any
// relative tolerance below 1. Narrowing the row (not checking after reading) keeps the range in
// one place: the reader's and the flags' messages, validate() and the tool's --list-settings all
// give it. `why` is appended to the row's meaning. Throws std::logic_error if `key` has no row.
template <class Root>
void narrow(Table<Root>& table, std::string_view key, Range range, const std::string& why) {
  for (Setting<Root>& s : table) {
    if (s.key != key) continue;
    s.range = range;
    s.meaning += " (" + why + ")";
    return;
  }
  throw std::logic_error("settings::narrow: no row " + std::string(key));
}

// Every row of the table checked on `root`: throws for the first value not allowed.
template <class Root>
void validate(const Root& root, const Table<Root>& table) {
  for (const Setting<Root>& s : table)
    s.check(s.get(root));
}

// The row of `key`, or nullptr.
template <class Root>
const Setting<Root>* find(const Table<Root>& table, std::string_view key) {
  for (const Setting<Root>& s : table) {
    if (s.key == key) return &s;
  }
  return nullptr;
}

// "key=value key=value ..." over every row (results_only: those that affect results), values
// exact (to_string(Value)): equal strings, equal settings. `skip`: keys left out (a sweep's
// rows carry a and R in their own columns).
template <class Root>
std::string fingerprint(const Root& root, const Table<Root>& table, bool results_only = false,
                        const std::vector<std::string>& skip = {}) {
  std::string out;
  for (const Setting<Root>& s : table) {
    if (results_only && !s.affects_results) continue;
    if (std::find(skip.begin(), skip.end(), s.key) != skip.end()) continue;
    // append(): GCC 12 warns falsely (-Wrestrict) on " " + string.
    out.append(out.empty() ? "" : " ").append(s.key).append("=").append(to_string(s.get(root)));
  }
  return out;
}

}  // namespace asperity::settings
