// Keyword arguments set through a settings table (core/common/settings.hpp): the Python face of
// the one description of each setting. A keyword is a table's key; its value is converted to
// the setting's kind, checked against its allowed set (ValueError naming the key) and set.
// The help of a binding lists the keywords from the same table.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

#include "asperity/core/common/settings.hpp"
#include "errors.hpp"

namespace asperity::python {

// The Python value as a setting of `info`'s kind: bool for a boolean; an int for an integer (a
// float with an integral value too); an int or a float for a number; a str for a choice (an int
// too, as its decimal name: slip_sign=-1); a sequence of numbers for a list. TypeError else.
settings::Value keyword_value(const settings::Info& info, const pybind11::handle& value);

// Sets the row of `name` in `table` on `root` from `value`; false if the table has no such key.
template <class Root>
bool set_keyword(const settings::Table<Root>& table, Root& root, const std::string& name,
                 const pybind11::handle& value) {
  const settings::Setting<Root>* row = settings::find(table, name);
  if (row == nullptr) return false;
  const settings::Value v = keyword_value(*row, value);
  value_errors([&] {
    row->check(v);
    return 0;
  });
  row->set(root, v);
  return true;
}

// The keys of `table`, comma-separated (for the message of an unknown keyword).
template <class Root>
std::string keyword_names(const settings::Table<Root>& table) {
  std::string out;
  for (const settings::Setting<Root>& s : table)
    out.append(out.empty() ? "" : ", ").append(s.key);
  return out;
}

// One line per setting: "  key = <default>: <meaning> (allowed: <allowed>)"; an optional
// number not given by default reads "None".
template <class Root>
std::string keywords_help(const settings::Table<Root>& table, const Root& defaults = {}) {
  std::string out;
  for (const settings::Setting<Root>& s : table) {
    const settings::Value v = s.get(defaults);
    out.append("  ").append(s.key).append(" = ").append(s.not_given(v) ? "None"
                                                                       : settings::to_string(v));
    out.append(": ").append(s.meaning).append(" (allowed: ").append(s.allowed()).append(")\n");
  }
  return out;
}

}  // namespace asperity::python
