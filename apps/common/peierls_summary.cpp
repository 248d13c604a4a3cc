#include "asperity/apps/common/peierls_summary.hpp"

#include "asperity/apps/common/output_files.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <utility>

namespace asperity::app {

namespace fs = std::filesystem;

namespace {

// The summary's path (`path` or summary.json in it) and its JSON (discarded if not JSON).
std::pair<fs::path, nlohmann::json> read_summary(const fs::path& path) {
  fs::path p = path;
  if (fs::is_directory(p)) p /= "summary.json";
  if (!fs::exists(p)) throw std::invalid_argument(p.string() + ": no such peierls_scan summary");
  std::ifstream in(p, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return {p, nlohmann::json::parse(text, nullptr, false)};
}

// The fit `character` of the summary `summary` read from `p`, checked (read_peierls_fit).
PeierlsSummaryFit fit_in(const fs::path& p, const nlohmann::json& summary,
                         const std::string& character) {
  PeierlsSummaryFit out;
  out.file = p;
  const std::string key = "fits." + character;
  if (summary.is_discarded() || !summary.is_object() || !summary.contains("fits") ||
      !summary["fits"].is_object() || !summary["fits"].contains(character)) {
    throw std::invalid_argument(p.string() + ": not a peierls_scan summary with an " + character +
                                " fit (" + key + ")");
  }
  const nlohmann::json& e = summary["fits"][character];
  if (!e.is_object() || !e.value("valid", false)) {
    throw std::invalid_argument(p.string() + ": the " + character +
                                " fit is not valid (too few resolved points)");
  }
  // The summary is a file like any other input: every number is checked, and a missing or
  // mistyped key is named (it once crashed on an empty window).
  const auto number = [&](const nlohmann::json& v, const std::string& name, bool positive) {
    if (!v.is_number() || !std::isfinite(v.get<double>()) ||
        (positive ? v.get<double>() <= 0.0 : v.get<double>() < 0.0)) {
      throw std::invalid_argument(
          p.string() + ": " + key + "." + name + " = " + v.dump() +
          (positive ? ": not a finite positive number" : ": not a finite non-negative number"));
    }
    return v.get<double>();
  };
  const auto field = [&](const char* name) {
    if (!e.contains(name))
      throw std::invalid_argument(p.string() + ": " + key + "." + name + " missing");
    return e[name];
  };
  nucleation::PeierlsLaw& law = out.law;
  law.k1 = number(field("k1"), "k1", true);
  law.k1_error = number(field("k1_error"), "k1_error", false);
  law.k2 = number(field("k2"), "k2", true);
  law.k2_error = number(field("k2_error"), "k2_error", false);
  if (e.contains("k1_k2_correlation")) {
    const nlohmann::json& v = e["k1_k2_correlation"];
    if (!v.is_number() || !(v.get<double>() >= -1.0 && v.get<double>() <= 1.0)) {
      throw std::invalid_argument(p.string() + ": " + key + ".k1_k2_correlation = " + v.dump() +
                                  ": not a number in [-1, 1]");
    }
    law.correlation = v.get<double>();
  } else {
    out.correlation_missing = true;
  }
  const nlohmann::json window = field("window_b_core");
  if (!window.is_array() || window.size() != 2) {
    throw std::invalid_argument(p.string() + ": " + key + ".window_b_core = " + window.dump() +
                                ": not a pair [b_min, b_max]");
  }
  law.b_min = number(window[0], "window_b_core[0]", false);
  law.b_max = number(window[1], "window_b_core[1]", true);
  if (law.b_min >= law.b_max) {
    throw std::invalid_argument(p.string() + ": " + key + ".window_b_core = " + window.dump() +
                                ": b_min must be below b_max");
  }
  out.points = e.value("points", 0);
  out.L = summary.contains("scene") && summary["scene"].is_object() ? summary["scene"].value("L", 0)
                                                                    : 0;
  return out;
}

}  // namespace

PeierlsSummaryFit read_peierls_fit(const fs::path& path, const std::string& character) {
  const auto [p, summary] = read_summary(path);
  return fit_in(p, summary, character);
}

PeierlsAngles read_peierls_angles(const fs::path& path) {
  PeierlsAngles out;
  const auto [p, summary] = read_summary(path);
  out.summary = p;
  if (summary.is_discarded() || !summary.is_object() || !summary.contains("fits") ||
      !summary["fits"].is_object()) {
    throw std::invalid_argument(p.string() + ": not a peierls_scan summary with fits (fits)");
  }
  // Angles are matched between the fits and the table's rows to this (both are the cell's
  // offered angle, written from the same double).
  constexpr double same_angle = 1e-6;
  const auto angle_of = [&](double theta) -> std::size_t {
    for (std::size_t i = 0; i < out.angles.size(); ++i) {
      if (std::abs(out.angles[i].theta_deg - theta) < same_angle) return i;
    }
    out.angles.push_back({.theta_deg = theta});
    out.fit_keys.emplace_back();
    return out.angles.size() - 1;
  };
  for (const auto& [key, e] : summary["fits"].items()) {
    if (!e.is_object() || !e.value("valid", false)) continue;
    const nlohmann::json theta = e.contains("theta_deg") ? e["theta_deg"] : nlohmann::json();
    if (!theta.is_number() || !(theta.get<double>() >= 0.0 && theta.get<double>() <= 90.0)) {
      throw std::invalid_argument(p.string() + ": fits." + key + ".theta_deg = " + theta.dump() +
                                  ": not an angle in [0, 90] degrees");
    }
    const std::size_t i = angle_of(theta.get<double>());
    out.angles[i].law = fit_in(p, summary, key).law;
    out.fit_keys[i] = key;
  }
  const fs::path table_path = p.parent_path() / "peierls.csv";
  if (fs::exists(table_path)) {
    out.table = table_path;
    const CsvTable table = CsvTable::read(table_path);
    std::vector<std::map<double, double>> samples(out.angles.size());
    for (std::size_t r = 0; r < table.rows(); ++r) {
      double least = std::numeric_limits<double>::infinity();
      for (const char* sign : {"pos", "neg"}) {
        if (table.integer(r, std::string("resolved_") + sign) == 0) continue;
        least = std::min(least, table.number(r, std::string("tau_P_over_tau_max_") + sign));
      }
      if (!std::isfinite(least)) continue;  // unresolved both ways: no value to interpolate
      const std::size_t i = angle_of(table.number(r, "theta_deg"));
      samples.resize(out.angles.size());
      const double b = table.number(r, "b_core");
      const auto [at, fresh] = samples[i].emplace(b, least);
      if (!fresh) at->second = std::min(at->second, least);
    }
    for (std::size_t i = 0; i < samples.size(); ++i) {
      for (const auto& [b, ratio] : samples[i]) {
        out.angles[i].b_core.push_back(b);
        out.angles[i].ratio.push_back(ratio);
      }
    }
  }
  for (const nucleation::AngleLaw& a : out.angles) {
    try {
      a.validate();
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument((out.table.empty() ? p : out.table).string() + ": " + e.what());
    }
  }
  // Ascending angle, keys alongside.
  std::vector<std::size_t> order(out.angles.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return out.angles[a].theta_deg < out.angles[b].theta_deg;
  });
  PeierlsAngles sorted{.summary = out.summary, .table = out.table};
  for (const std::size_t i : order) {
    sorted.angles.push_back(std::move(out.angles[i]));
    sorted.fit_keys.push_back(std::move(out.fit_keys[i]));
  }
  return sorted;
}

}  // namespace asperity::app
