// fit_scaling's inputs: the options' checks, the friction_sweep tables, the common alpha of the
// regime map and the Peierls law.
#include "fit_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/peierls_summary.hpp"
#include "asperity/nucleation/statistics.hpp"

namespace asperity::app::fit_scaling {

namespace fs = std::filesystem;
namespace nuc = asperity::nucleation;

const settings::Table<Options>& Options::settings() {
  using R = settings::Range;
  using O = Options;
  static const settings::Table<O> table = {
      settings::optional_number<O>(
          "k1", [](auto& o) -> auto& { return o.k1; }, R::positive(), "",
          "Peierls law prefactor, tau_P / tau_max = k1 exp(-k2 b_core / d) (with k2; the pair "
          "overrides --peierls)",
          "--k1"),
      settings::optional_number<O>(
          "k2", [](auto& o) -> auto& { return o.k2; }, R::positive(), "",
          "Peierls law exponent (with k1; the pair overrides --peierls)", "--k2"),
      settings::number<O>(
          "k1_error", [](auto& o) -> auto& { return o.k1_error; }, R::non_negative(), "",
          "error of a given k1", "--k1-error"),
      settings::number<O>(
          "k2_error", [](auto& o) -> auto& { return o.k2_error; }, R::non_negative(), "",
          "error of a given k2", "--k2-error"),
      settings::optional_number<O>(
          "k1_k2_correlation", [](auto& o) -> auto& { return o.correlation; }, R::closed(-1, 1), "",
          "correlation of the given k1 and k2 errors (only with both; not given: 0)",
          "--k1-k2-correlation"),
      settings::number<O>(
          "f_P", [](auto& o) -> auto& { return o.f_P; }, R::open_closed(0, 1), "",
          "fraction of the local Peierls stress integrated (Regime III law, "
          "MODEL.md 8)",
          "--f-P"),
      settings::numbers<O>(
          "window", [](auto& o) -> auto& { return o.window; }, R::positive(), "",
          "Regime II window lo,hi in a/b_core^0 (empty: automatic)", "--window"),
      settings::integer<O>(
          "bootstrap", [](auto& o) -> auto& { return o.bootstrap; }, R::closed(100, 10000000), "",
          "bootstrap resamples for the error of c0", "--bootstrap"),
      settings::integer<O>(
          "seed", [](auto& o) -> auto& { return o.seed; }, R::closed(0, 2147483647), "",
          "bootstrap seed", "--seed"),
      settings::number<O>(
          "rise_tolerance", [](auto& o) -> auto& { return o.rise_tolerance; }, R::closed_open(0, 1),
          "",
          "relative rise of mu/alpha past a branch's lowest point that marks "
          "simulated Regime III (docs/nucleation.md)"),
      settings::numbers<O>(
          "map_a", [](auto& o) -> auto& { return o.map_a; }, R::positive(), "d",
          "regime map range of a: lo,hi (empty: from the data)", "--map-a"),
      settings::numbers<O>(
          "map_R", [](auto& o) -> auto& { return o.map_R; }, R::positive(), "d",
          "regime map range of R: lo,hi (empty: from the data)", "--map-R"),
      settings::optional_number<O>(
          "c0_hertz", [](auto& o) -> auto& { return o.c0_hertz; }, R::positive(), "",
          "c0 of the Hertz law for mixed tables, when no Hertz table is given", "--c0-hertz"),
      settings::optional_number<O>(
          "c0_adhesive", [](auto& o) -> auto& { return o.c0_adhesive; }, R::positive(), "",
          "c0 of the adhesive law for mixed tables, when no adhesive table is given",
          "--c0-adhesive"),
      settings::numbers<O>(
          "forecast_R", [](auto& o) -> auto& { return o.forecast_R; }, R::positive(), "d",
          "forecast: sphere radii without data, with forecast_a (forecast.csv)", "--forecast-R"),
      settings::numbers<O>(
          "forecast_a", [](auto& o) -> auto& { return o.forecast_a; }, R::positive(), "d",
          "forecast: contact radii at each forecast_R: predicted mu/alpha, its error and its "
          "slope in a (an upturn where it is positive)",
          "--forecast-a"),
  };
  return table;
}

void Options::validate() const {
  if (sweeps.empty()) throw std::invalid_argument("at least one sweep table is required");
  settings::validate(*this, settings());
  // Whether a Peierls law is needed depends on the tables' envelopes: main() asks has_law().
  if (!window.empty() && (window.size() != 2 || !(window[1] >= window[0])))
    throw std::invalid_argument("window = " + settings::to_string(window) +
                                ": allowed: two values 0 < lo <= hi (a/b_core^0)");
  if (correlation && !(k1 && k2))
    throw std::invalid_argument("k1_k2_correlation: only with both k1 and k2 given");
  if (forecast_R.empty() != forecast_a.empty())
    throw std::invalid_argument("forecast_R and forecast_a: give both or neither");
  for (const auto& [name, r] :
       {std::pair{"forecast_R", forecast_R}, std::pair{"forecast_a", forecast_a}}) {
    if (std::set<double>(r.begin(), r.end()).size() != r.size())
      throw std::invalid_argument(std::string(name) + " = " + settings::to_string(r) +
                                  ": a value is given twice");
  }
  for (const auto& [name, r] : {std::pair{"map_a", map_a}, std::pair{"map_R", map_R}}) {
    if (!r.empty() && (r.size() != 2 || !(r[1] > r[0])))
      throw std::invalid_argument(std::string(name) + " = " + settings::to_string(r) +
                                  ": allowed: two values 0 < lo < hi");
  }
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

namespace {

fs::path table_path(const std::string& p) {
  const fs::path path(p);
  return fs::is_directory(path) ? path / "sweep.csv" : path;
}

}  // namespace

Loaded load_sweeps(const std::vector<std::string>& sweeps) {
  Loaded out;
  for (const auto& s : sweeps) {
    const fs::path csv = table_path(s);
    if (!fs::exists(csv)) throw std::invalid_argument(csv.string() + ": no such sweep table");
    const app::CsvTable t = app::CsvTable::read(csv);
    const auto has = [&](const char* c) {
      return std::find(t.columns().begin(), t.columns().end(), c) != t.columns().end();
    };
    for (const char* c :
         {"a", "R", "alpha", "nu", "a_over_bcore0", "mu_is_lower_bound", "failed"}) {
      if (!has(c))
        throw std::invalid_argument(csv.string() + ": not a friction_sweep table (no column '" + c +
                                    "')");
    }
    // The envelope of each row (issue 27); tables before it hold Hertz rows.
    const bool has_envelope = has("envelope");
    const bool has_model =
        std::find(t.columns().begin(), t.columns().end(), "model") != t.columns().end();
    const bool has_settings =
        std::find(t.columns().begin(), t.columns().end(), "settings") != t.columns().end();
    const bool has_slips =
        std::find(t.columns().begin(), t.columns().end(), "slip_events") != t.columns().end();
    // The scaling laws (MODEL.md 8) are the aligned tip's: rows of a tip out of registry
    // (issue 27, sweep.tip_angle and sweep.tip_mismatch) are left out and counted.
    const bool has_tip =
        std::find(t.columns().begin(), t.columns().end(), "tip_angle") != t.columns().end() &&
        std::find(t.columns().begin(), t.columns().end(), "tip_mismatch") != t.columns().end();
    std::size_t used = 0, failed = 0, lower = 0, tipped = 0;
    for (std::size_t i = 0; i < t.rows(); ++i) {
      if (has_tip && (t.number(i, "tip_angle") != 0.0 || t.number(i, "tip_mismatch") != 0.0)) {
        ++tipped;
        continue;
      }
      // A failed point has no result: left out and counted. A lower bound (the slide stopped
      // before its peak) would bias a fit low, but can still place a point on the rising
      // branch: flagged (DataPoint::lower_bound) and counted.
      if (t.integer(i, "failed") != 0) {
        ++failed;
        continue;
      }
      DataPoint p;
      p.lower_bound = t.integer(i, "mu_is_lower_bound") != 0;
      if (p.lower_bound) ++lower;
      p.source = csv.string();
      // friction_sweep tables name the model in their settings ("model=explicit"); older
      // tables and LFM rows do not.
      p.model = has_model ? t.text(i, "model")
                : has_settings && t.text(i, "settings").find("model=explicit") != std::string::npos
                    ? "explicit"
                    : "LFM";
      p.a = t.number(i, "a");
      p.R = t.number(i, "R");
      p.alpha = t.number(i, "alpha");
      p.nu = t.number(i, "nu");
      p.x = t.number(i, "a_over_bcore0");
      p.envelope = has_envelope ? t.text(i, "envelope") : "hertz";
      // The column of the envelope's law: mu/alpha, tau_fric/tau0 or Fx/F_I.
      const char* y = p.envelope == "hertz"      ? "mu_over_alpha"
                      : p.envelope == "adhesive" ? "tau_fric_over_tau0"
                      : p.envelope == "mixed"    ? "friction_over_regime_one"
                                                 : nullptr;
      if (y == nullptr || !has(y) || (p.envelope != "hertz" && !(has("tau0") && has("G"))))
        throw std::invalid_argument(csv.string() + ": row " + std::to_string(i + 1) +
                                    ": envelope '" + p.envelope +
                                    "' is not one of hertz, adhesive, mixed with its columns");
      p.mu = t.number(i, y);
      if (p.envelope != "hertz") {
        p.tau0 = t.number(i, "tau0");
        p.G = t.number(i, "G");
      }
      if (p.envelope == "mixed") {
        p.mu_over_alpha = t.number(i, "mu_over_alpha");
        p.tau_fric_over_tau0 = t.number(i, "tau_fric_over_tau0");
      }
      p.slip_events = has_slips ? static_cast<int>(t.integer(i, "slip_events")) : -1;
      if (!(p.a > 0 && p.R > 0 && p.x > 0 && p.mu > 0 && std::isfinite(p.mu)))
        throw std::invalid_argument(csv.string() + ": row " + std::to_string(i + 1) +
                                    ": a, R, a_over_bcore0 and " + y + " must be > 0");
      if (p.envelope != "hertz" && !(p.tau0 > 0 && p.G > 0))
        throw std::invalid_argument(csv.string() + ": row " + std::to_string(i + 1) + ": a " +
                                    p.envelope + " row needs tau0 > 0 and G > 0");
      out.points.push_back(p);
      ++used;
    }
    out.sources.push_back({{"table", csv.string()},
                           {"rows", t.rows()},
                           {"used", used},
                           {"failed_skipped", failed},
                           {"lower_bounds", lower},
                           {"tip_out_of_registry_skipped", tipped}});
  }
  if (out.points.empty()) throw std::invalid_argument("the sweep tables hold no usable point");
  // A lower bound and a measured value of the same point (a capped slide and its longer rerun):
  // the measured one stands for it, the bound is dropped.
  using Key = std::tuple<std::string, std::string, double, double, double>;
  const auto key = [](const DataPoint& p) { return Key{p.model, p.envelope, p.tau0, p.a, p.R}; };
  std::set<Key> measured;
  for (const auto& p : out.points)
    if (!p.lower_bound) measured.insert(key(p));
  std::erase_if(out.points,
                [&](const DataPoint& p) { return p.lower_bound && measured.count(key(p)) > 0; });
  // The bootstrap takes the points as independent measurements: a point given twice (a table
  // passed twice, or a sweep and a copy of it) would count double and shrink c0's error.
  std::map<Key, const DataPoint*> seen;
  for (const auto& p : out.points) {
    const auto [it, fresh] = seen.emplace(key(p), &p);
    if (!fresh)
      throw std::invalid_argument("the point a = " + fmt("%g", p.a) + " d, R = " + fmt("%g", p.R) +
                                  " d (" + p.model + ") is in " + it->second->source + " and in " +
                                  p.source + ": give each point once");
  }
  return out;
}

ByEnvelope split_envelopes(const std::vector<DataPoint>& pts) {
  ByEnvelope out;
  for (const auto& p : pts) {
    // The adhesive and mixed analyses take measured values only.
    if (p.lower_bound && p.envelope != "hertz") continue;
    (p.envelope == "adhesive" ? out.adhesive
     : p.envelope == "mixed"  ? out.mixed
                              : out.hertz)
        .push_back(p);
  }
  return out;
}

MapAlpha common_alpha(const std::vector<DataPoint>& pts) {
  constexpr double max_spread = 0.05;
  const DataPoint& first = pts.front();
  const DataPoint* lfm = nullptr;
  double sum = 0.0;
  MapAlpha out{.min = first.alpha, .max = first.alpha};
  for (const auto& p : pts) {
    if (std::abs(p.nu - first.nu) > 1e-12)
      throw std::invalid_argument(p.source + ": nu = " + fmt("%g", p.nu) +
                                  " differs from the first table's (" + fmt("%g", first.nu) +
                                  "): one regime map needs one material");
    if (p.model == "LFM") {
      if (lfm && std::abs(p.alpha - lfm->alpha) > 1e-12)
        throw std::invalid_argument(
            p.source + ": alpha = " + fmt("%g", p.alpha) + " differs from " + lfm->source + "'s (" +
            fmt("%g", lfm->alpha) + "): one regime map needs one alpha of the lateral force model");
      if (!lfm) lfm = &p;
    }
    sum += p.alpha;
    out.min = std::min(out.min, p.alpha);
    out.max = std::max(out.max, p.alpha);
  }
  out.alpha = lfm ? lfm->alpha : sum / static_cast<double>(pts.size());
  out.rule = lfm ? "the lateral force model's" : "mean of the rows' (explicit model: measured)";
  for (const auto& p : pts) {
    if (std::abs(p.alpha / out.alpha - 1.0) > max_spread)
      throw std::invalid_argument(p.source + ": alpha = " + fmt("%g", p.alpha) + " is more than " +
                                  fmt("%g", 100 * max_spread) + "% from the map's alpha " +
                                  fmt("%g", out.alpha) + " (" + out.rule +
                                  "): one regime map needs one alpha");
  }
  return out;
}

LawSource read_law(const Options& o) {
  LawSource s;
  double dof = 0.0;  // of the k1, k2 fit; 0: given or unknown
  nlohmann::json j = {{"source", "given"}};
  if (!o.peierls.empty()) {
    const app::PeierlsSummaryFit fit = app::read_peierls_fit(o.peierls, "edge");
    s.law = fit.law;
    dof = std::max(0.0, fit.points - 2.0);
    j = {{"source", fit.file.string()},
         {"fit", "edge (theta = 90 deg), tau_P = k1 tau_max exp(-k2 b_core/d)"},
         {"window_b_core", {s.law.b_min, s.law.b_max}},
         {"points", fit.points},
         {"L", fit.L}};
    // Summaries before the correlation was written lack it: taken as 0, which overstates the
    // errors of the predictions.
    if (fit.correlation_missing)
      j["correlation_missing"] = "taken as 0 (a peierls_scan summary without k1_k2_correlation)";
    // Without the number of points (a fit of two parameters needs three) the degrees of freedom
    // are unknown: the errors are taken as reported errors, which understates them.
    if (fit.points < 3)
      j["points_missing"] =
          "reported_error_factor taken as 1 (a peierls_scan summary without the fit's points)";
  }
  if (o.k1.has_value() != o.k2.has_value()) {
    // k1 and k2 come from one fit, with correlated errors: one of them replaced would leave a
    // law that no fit gave, with errors of unknown footing.
    throw std::invalid_argument("give --k1 and --k2 together (" +
                                std::string(o.k1 ? "--k1" : "--k2") + " alone was given)");
  }
  if (o.k1 || o.k2) {
    dof = 0.0;  // given errors are taken as reported errors
    // The summary's correlation belongs to its k1 and k2 together.
    s.law.correlation = o.correlation.value_or(0.0);
  }
  if (o.k1) {
    s.law.k1 = *o.k1;
    s.law.k1_error = o.k1_error;
    j["k1_given"] = true;
  }
  if (o.k2) {
    s.law.k2 = *o.k2;
    s.law.k2_error = o.k2_error;
    j["k2_given"] = true;
  }
  s.law.validate();
  // The scan's errors are plain standard errors; predictions and their uncertainties use them
  // times this factor (statistics.hpp). Given errors are used as they are.
  s.error_factor = dof > 0.0 ? nuc::t_factor(dof) : 1.0;
  j["reported_error_factor"] = s.error_factor;
  j.update({{"k1", s.law.k1},
            {"k1_error", s.law.k1_error},
            {"k2", s.law.k2},
            {"k2_error", s.law.k2_error},
            {"k1_k2_correlation", s.law.correlation}});
  s.json = j;
  return s;
}

}  // namespace asperity::app::fit_scaling
