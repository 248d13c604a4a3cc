#include "asperity/apps/common/settings_cli.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <vector>

namespace asperity::app {

settings::Value parse_setting(const settings::Info& setting, const std::string& text) {
  const auto bad = [&](const std::string& what) {
    throw std::invalid_argument(setting.key + " = " + text + ": " + what);
  };
  settings::Value v;
  switch (setting.kind) {
    case settings::Kind::boolean:
      if (text != "true" && text != "false") bad("allowed: true or false");
      v = text == "true";
      break;
    case settings::Kind::integer: {
      long long n = 0;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
      if (ec != std::errc() || end != text.data() + text.size()) bad("not an integer");
      v = n;
      break;
    }
    case settings::Kind::number: {
      // strtod: also "1e-5", "inf" and "nan", which the check then refuses by name.
      char* end = nullptr;
      const double x = std::strtod(text.c_str(), &end);
      if (text.empty() || end != text.c_str() + text.size()) bad("not a number");
      // NaN is how an optional number says "not given": a flag gives a value or is left out.
      if (std::isnan(x)) bad("not a number");
      v = x;
      break;
    }
    case settings::Kind::numbers: {
      // Comma-separated, as the tools' list flags always took them ("--a 30,60,120").
      std::vector<double> list;
      std::size_t from = 0;
      while (from <= text.size()) {
        const std::size_t comma = std::min(text.find(',', from), text.size());
        const std::string item = text.substr(from, comma - from);
        char* end = nullptr;
        const double x = std::strtod(item.c_str(), &end);
        if (item.empty() || end != item.c_str() + item.size()) bad("not a list of numbers");
        list.push_back(x);
        from = comma + 1;
      }
      v = std::move(list);
      break;
    }
    case settings::Kind::choice:
      v = setting.choice_named(text);  // "+1" for a sign's "1"
      break;
  }
  setting.check(v);
  return v;
}

std::string setting_help(const settings::Info& setting, const std::string& key_label) {
  std::string help = setting.meaning;
  return help.append("; ")
      .append(key_label)
      .append(" ")
      .append(setting.key)
      .append(", allowed: ")
      .append(setting.allowed());
}

}  // namespace asperity::app
