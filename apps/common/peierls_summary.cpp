#include "asperity/apps/common/peierls_summary.hpp"

#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace asperity::app {

namespace fs = std::filesystem;

PeierlsSummaryFit read_peierls_fit(const fs::path& path, const std::string& character) {
  PeierlsSummaryFit out;
  fs::path p = path;
  if (fs::is_directory(p)) p /= "summary.json";
  if (!fs::exists(p)) throw std::invalid_argument(p.string() + ": no such peierls_scan summary");
  out.file = p;
  std::ifstream in(p, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const nlohmann::json summary = nlohmann::json::parse(text, nullptr, false);
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

std::vector<PeierlsAngleFit> read_peierls_fits(const fs::path& path) {
  fs::path p = path;
  if (fs::is_directory(p)) p /= "summary.json";
  if (!fs::exists(p)) throw std::invalid_argument(p.string() + ": no such peierls_scan summary");
  std::ifstream in(p, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const nlohmann::json summary = nlohmann::json::parse(text, nullptr, false);
  if (summary.is_discarded() || !summary.is_object() || !summary.contains("fits") ||
      !summary["fits"].is_object()) {
    throw std::invalid_argument(p.string() + ": not a peierls_scan summary with fits (fits)");
  }
  std::vector<PeierlsAngleFit> out;
  for (const auto& [key, e] : summary["fits"].items()) {
    if (!e.is_object() || !e.value("valid", false)) continue;
    const nlohmann::json theta = e.contains("theta_deg") ? e["theta_deg"] : nlohmann::json();
    if (!theta.is_number() || !(theta.get<double>() >= 0.0 && theta.get<double>() <= 90.0)) {
      throw std::invalid_argument(p.string() + ": fits." + key + ".theta_deg = " + theta.dump() +
                                  ": not an angle in [0, 90] degrees");
    }
    out.push_back({key, theta.get<double>(), read_peierls_fit(p, key)});
  }
  return out;
}

}  // namespace asperity::app
