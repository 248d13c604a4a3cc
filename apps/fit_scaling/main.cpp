// fit_scaling: the scaling laws of MODEL.md section 8 fitted to friction_sweep tables and compared
// with the Peierls-cell prediction of Regime III (issue 9). Reads one or more sweep.csv files and a
// peierls_scan summary (or k1, k2 given), and writes into the output directory
// - summary.json: c0 with its error and window, k1, k2 and f_P used, the Regime I and the II -> III
//   crossovers, the Regime III comparison per R, the regime-map agreement, a Regime III fit of
//   k1, k2 to the friction data where they rise; times and provenance under "run";
// - predictions.csv: per data point, mu/alpha measured and every prediction, both regimes;
// - collapse.png: mu/alpha vs a/b_core^0 (log-log), data by model and R, the Regime I line, the
//   fitted Regime II law and the nucleation condition, the Regime III predictions per R;
// - regime_map.png: predicted mu/alpha over (a/d, R/d) with the regime boundaries and the data
//   points marked by their simulated regime.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "common/cli.hpp"
#include "common/cli_checks.hpp"
#include "common/line_fit.hpp"
#include "common/output_files.hpp"
#include "common/peierls_summary.hpp"
#include "common/plot.hpp"
#include "contact/hertz.hpp"
#include "nucleation/regime_map.hpp"
#include "nucleation/regime_three.hpp"
#include "nucleation/regime_two.hpp"
#include "nucleation/statistics.hpp"

using namespace asperity;
namespace fs = std::filesystem;
namespace nuc = asperity::nucleation;

namespace {

struct Options {
  std::vector<std::string> sweeps;  // sweep.csv files or friction_sweep output folders
  std::string peierls;              // peierls_scan summary.json or its folder; empty: k1, k2 given
  std::optional<double> k1, k2;     // Peierls law (dimensionless); override the summary
  double k1_error = 0.0, k2_error = 0.0;  // their errors when given
  std::optional<double> correlation;      // of k1 and k2 when given, in [-1, 1]
  double f_P = 0.5;                       // fraction of the local Peierls stress, (0, 1]
  std::vector<double> window;  // Regime II window in a/b_core^0 (2 values); empty: automatic
  int bootstrap = 4000;        // bootstrap resamples for c0
  long long seed = 20240909;   // bootstrap seed
  // Regime map ranges (d); empty: from the data (a/2 .. 3 a_max or past the crossovers, R/2 .. 2
  // R).
  std::vector<double> map_a, map_R;
  double rise_tolerance = 0.02;  // relative rise of mu/alpha that marks Regime III data
  std::string out = "results/fit_scaling";

  // Throws std::invalid_argument naming the option and the constraint.
  void validate() const {
    if (sweeps.empty()) throw std::invalid_argument("at least one sweep table is required");
    if (peierls.empty() && !(k1 && k2))
      throw std::invalid_argument("--peierls or both --k1 and --k2 are required (Regime III law)");
    if (!window.empty() && (window.size() != 2 || !(window[0] > 0.0) || !(window[1] >= window[0])))
      throw std::invalid_argument("--window: two values 0 < lo <= hi (a/b_core^0) expected");
    if (correlation && !(k1 && k2))
      throw std::invalid_argument("--k1-k2-correlation: only with both --k1 and --k2");
    for (const auto& [name, r] : {std::pair{"--map-a", map_a}, std::pair{"--map-R", map_R}}) {
      if (r.empty()) continue;
      if (r.size() != 2 || !(r[0] > 0.0) || !(r[1] > r[0]))
        throw std::invalid_argument(std::string(name) + ": two values 0 < lo < hi expected");
    }
  }
};

struct DataPoint {
  std::string source, model;
  double a = 0, R = 0, alpha = 0, nu = 0, x = 0, mu = 0;  // x = a/b_core^0, mu = mu/alpha
  int slip_events = 0;
};

struct Loaded {
  std::vector<DataPoint> points;
  nlohmann::json sources = nlohmann::json::array();
};

fs::path table_path(const std::string& p) {
  const fs::path path(p);
  return fs::is_directory(path) ? path / "sweep.csv" : path;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

Loaded load_sweeps(const std::vector<std::string>& sweeps) {
  Loaded out;
  for (const auto& s : sweeps) {
    const fs::path csv = table_path(s);
    if (!fs::exists(csv)) throw std::invalid_argument(csv.string() + ": no such sweep table");
    const app::CsvTable t = app::CsvTable::read(csv);
    for (const char* c : {"a", "R", "alpha", "nu", "a_over_bcore0", "mu_over_alpha",
                          "mu_is_lower_bound", "failed"}) {
      if (std::find(t.columns().begin(), t.columns().end(), c) == t.columns().end())
        throw std::invalid_argument(csv.string() + ": not a friction_sweep table (no column '" + c +
                                    "')");
    }
    const bool has_model =
        std::find(t.columns().begin(), t.columns().end(), "model") != t.columns().end();
    const bool has_settings =
        std::find(t.columns().begin(), t.columns().end(), "settings") != t.columns().end();
    const bool has_slips =
        std::find(t.columns().begin(), t.columns().end(), "slip_events") != t.columns().end();
    std::size_t used = 0, failed = 0, lower = 0;
    for (std::size_t i = 0; i < t.rows(); ++i) {
      // A failed point has no result; a lower bound (the slide stopped before its peak) would
      // bias a fit low: both are left out and counted.
      if (t.integer(i, "failed") != 0) {
        ++failed;
        continue;
      }
      if (t.integer(i, "mu_is_lower_bound") != 0) {
        ++lower;
        continue;
      }
      DataPoint p;
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
      p.mu = t.number(i, "mu_over_alpha");
      p.slip_events = has_slips ? static_cast<int>(t.integer(i, "slip_events")) : -1;
      if (!(p.a > 0 && p.R > 0 && p.x > 0 && p.mu > 0 && std::isfinite(p.mu)))
        throw std::invalid_argument(csv.string() + ": row " + std::to_string(i + 1) +
                                    ": a, R, a_over_bcore0 and mu_over_alpha must be > 0");
      out.points.push_back(p);
      ++used;
    }
    out.sources.push_back({{"table", csv.string()},
                           {"rows", t.rows()},
                           {"used", used},
                           {"failed_skipped", failed},
                           {"lower_bound_skipped", lower}});
  }
  if (out.points.empty()) throw std::invalid_argument("the sweep tables hold no usable point");
  // The bootstrap takes the points as independent measurements: a point given twice (a table
  // passed twice, or a sweep and a copy of it) would count double and shrink c0's error.
  std::map<std::tuple<std::string, double, double>, const DataPoint*> seen;
  for (const auto& p : out.points) {
    const auto [it, fresh] = seen.emplace(std::tuple{p.model, p.a, p.R}, &p);
    if (!fresh)
      throw std::invalid_argument("the point a = " + fmt("%g", p.a) + " d, R = " + fmt("%g", p.R) +
                                  " d (" + p.model + ") is in " + it->second->source + " and in " +
                                  p.source + ": give each point once");
  }
  return out;
}

// One regime map and one set of crossovers need one material and one alpha. The lateral force
// model's alpha is a parameter, the same on every row of a sweep; the explicit model's is the
// potential's, measured at each point's central load (0.709 ... 0.719 for a tip set up for 0.7,
// data/reference/sweep_explicit_R160.csv). Each row carries its own alpha into a/b_core^0 and
// b_core^0, so every per-point prediction uses it; only the map and the crossovers use the common
// alpha: the LFM rows' if there are any, else the mean. Rows further than max_spread from it
// would put the map off by more than that in a/b_core^0, and are refused.
struct MapAlpha {
  double alpha = 0.0;
  double min = 0.0, max = 0.0;  // over all rows
  std::string rule;
};

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

struct LawSource {
  nuc::PeierlsLaw law;
  // Factor from the law's errors to reported errors (statistics.hpp): t_factor of the scan fit's
  // degrees of freedom (points - 2) for its plain standard errors, 1 for given errors.
  double error_factor = 1.0;
  nlohmann::json json;
};

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

// Least-squares slope of ln y against ln x.
double log_slope(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<double> lx, ly;
  for (std::size_t i = 0; i < x.size(); ++i) {
    lx.push_back(std::log(x[i]));
    ly.push_back(std::log(y[i]));
  }
  return fit_line(lx, ly).slope;
}

}  // namespace

int main(int argc, char** argv) {
  return app::run_main(argc, argv, [](int argc_, char** argv_) {
    CLI::App cli{"Fit c0, compare with the Peierls prediction of Regime III, map the regimes"};
    Options o;
    std::optional<double> k1_error, k2_error;
    cli.add_option("sweeps", o.sweeps, "friction_sweep tables (sweep.csv) or output folders")
        ->required();
    cli.add_option("--peierls", o.peierls,
                   "peierls_scan summary.json (or its folder): k1, k2 of the edge fit");
    cli.add_option("--k1", o.k1,
                   "Peierls law prefactor k1 (with --k2; the pair overrides --peierls)")
        ->check(app::positive());
    cli.add_option("--k2", o.k2,
                   "Peierls law exponent k2 (with --k1; the pair overrides --peierls)")
        ->check(app::positive());
    cli.add_option("--k1-error", k1_error, "Error of a given k1")->check(app::non_negative());
    cli.add_option("--k2-error", k2_error, "Error of a given k2")->check(app::non_negative());
    cli.add_option("--k1-k2-correlation", o.correlation,
                   "Correlation of the given k1 and k2 errors (default 0)")
        ->check(app::finite_number(-1, 1));
    cli.add_option("--f-P", o.f_P, "Fraction of the local Peierls stress (Regime III)")
        ->check(app::finite_number(0, 1, true))
        ->capture_default_str();
    cli.add_option("--window", o.window,
                   "Regime II window lo,hi in a/b_core^0 (default: automatic)")
        ->delimiter(',')
        ->check(app::positive());
    cli.add_option("--bootstrap", o.bootstrap, "Bootstrap resamples for the error of c0")
        ->check(CLI::Range(100, 10000000))
        ->capture_default_str();
    cli.add_option("--seed", o.seed, "Bootstrap seed")->check(CLI::Range(0LL, 1LL << 62));
    cli.add_option("--map-a", o.map_a, "Regime map range of a (d): lo,hi")
        ->delimiter(',')
        ->check(app::positive());
    cli.add_option("--map-R", o.map_R, "Regime map range of R (d): lo,hi")
        ->delimiter(',')
        ->check(app::positive());
    cli.add_option("--out", o.out, "Output directory")->capture_default_str();
    if (!app::parse_command_line(cli, argc_, argv_)) return 0;
    if (k1_error) o.k1_error = *k1_error;
    if (k2_error) o.k2_error = *k2_error;
    o.validate();

    const auto t0 = std::chrono::steady_clock::now();
    const Loaded data = load_sweeps(o.sweeps);
    const LawSource law = read_law(o);
    const auto& pts = data.points;
    const MapAlpha map_alpha = common_alpha(pts);
    const double alpha = map_alpha.alpha, nu = pts.front().nu;

    // Regime II fit.
    // Branches (falling, then rising) are per model and R.
    std::map<std::string, int> series_of;
    for (const auto& p : pts)
      series_of.emplace(p.model, static_cast<int>(series_of.size()));
    std::vector<nuc::ScalingPoint> sp;
    for (const auto& p : pts)
      sp.push_back({.a_over_bcore0 = p.x,
                    .mu_over_alpha = p.mu,
                    .a = p.a,
                    .R = p.R,
                    .series = series_of.at(p.model)});
    nuc::RegimeTwoFitOptions fo{.bootstrap_samples = o.bootstrap,
                                .seed = static_cast<std::uint64_t>(o.seed)};
    fo.automatic.rise_tolerance = o.rise_tolerance;
    if (!o.window.empty()) fo.window = std::pair{o.window[0], o.window[1]};
    const nuc::RegimeTwoFit fit = nuc::fit_regime_two(sp, fo);
    if (!fit.valid)
      throw std::invalid_argument("no Regime II fit: " + fit.reason +
                                  " (give --window, or add points)");
    // k1 and k2 errors of a peierls_scan summary are plain standard errors: on the footing of
    // c0's reported error they are multiplied by t_factor of their degrees of freedom
    // (statistics.hpp), in the model too, so that the per-point regime_three_log_error is a
    // reported error like every other (+-2 of them: the 95.45% interval).
    nuc::PeierlsLaw reported_law = law.law;
    reported_law.k1_error *= law.error_factor;
    reported_law.k2_error *= law.error_factor;
    const nuc::Model model{.c0 = fit.c0, .law = reported_law, .f_P = o.f_P};
    std::vector<bool> in_window(pts.size(), false);
    for (std::size_t i : fit.used)
      in_window[i] = true;
    std::set<double> window_R;
    for (std::size_t i : fit.used)
      window_R.insert(pts[i].R);

    // Independent directions of uncertainty: c0 (k = 0), and the two principal axes of the
    // covariance of (k1, k2) (k = 1, 2): nucleation::moved_model.
    const auto moved_model = [&](int k, double errors) {
      return nuc::moved_model(model, fit.c0_error, k, errors);
    };

    // Per point: predictions and regimes.
    const std::vector<nuc::Regime> simulated = nuc::simulated_regimes(sp, fit.c0, o.rise_tolerance);
    app::CsvTable table({"source", "model", "a", "R", "a_over_bcore0", "bcore0", "mu_over_alpha",
                         "in_window", "regime_two_law", "nucleation", "regime_three_central",
                         "regime_three_integrated", "regime_three_log_error", "predicted",
                         "data_over_predicted", "predicted_regime", "simulated_regime",
                         "law_extrapolated", "regime_undetermined"});
    std::vector<nuc::Prediction> predictions;
    nlohmann::json disagreements = nlohmann::json::array();
    std::size_t agree = 0, in_law = 0, agree_in_law = 0, undetermined = 0, contradictions = 0;
    // The Regime III law is used outside the core widths it was fitted on when the centre's core
    // width b_core^0 (the smallest in the contact, where tau_P is largest) is outside the fit
    // window: below it the law is extrapolated where it matters, above it the law is tiny and
    // the regime map's test of it is empty.
    const auto extrapolated = [&](double beta) {
      return (law.law.b_min > 0.0 && beta < law.law.b_min) ||
             (law.law.b_max > 0.0 && beta > law.law.b_max);
    };
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const auto& p = pts[i];
      const double beta = p.a / p.x;
      const nuc::Prediction pr = nuc::predict(p.x, beta, model);
      predictions.push_back(pr);
      // The prediction cannot decide the regime of a point that lies within the fitted
      // parameters' uncertainty of a boundary: moving c0 or the (k1, k2) pair along one
      // independent direction by 2 reported errors (either way) changes its predicted regime.
      bool open = false;
      for (int k = 0; k < 3 && !open; ++k) {
        for (double e : {2.0, -2.0}) {
          const std::optional<nuc::Model> m = moved_model(k, e);
          open = open || !m || nuc::predict(p.x, beta, *m).regime != pr.regime;
        }
      }
      if (open) ++undetermined;
      if (!extrapolated(beta)) {
        ++in_law;
        if (pr.regime == simulated[i]) ++agree_in_law;
      }
      if (pr.regime == simulated[i]) {
        ++agree;
      } else {
        if (!open) ++contradictions;
        disagreements.push_back({{"a", p.a},
                                 {"R", p.R},
                                 {"a_over_bcore0", p.x},
                                 {"mu_over_alpha", p.mu},
                                 {"predicted", nuc::to_string(pr.regime)},
                                 {"simulated", nuc::to_string(simulated[i])},
                                 {"bcore0", beta},
                                 {"law_extrapolated", extrapolated(beta)},
                                 {"regime_undetermined", open}});
      }
      table.add_row({p.source, p.model, p.a, p.R, p.x, beta, p.mu,
                     static_cast<long long>(in_window[i]), pr.law_two, pr.nucleation, pr.central,
                     pr.integrated, pr.integrated_log_error, pr.mu_over_alpha,
                     p.mu / pr.mu_over_alpha, nuc::to_string(pr.regime),
                     nuc::to_string(simulated[i]), static_cast<long long>(extrapolated(beta)),
                     static_cast<long long>(open)});
    }

    // Crossovers: Regime I (a/b_core^0, any R), II -> III per R of the data.
    std::set<double> Rs;
    for (const auto& p : pts)
      Rs.insert(p.R);
    const double x_one = nuc::regime_one_crossover(fit.c0);
    const double x_one_two = nuc::regime_one_two_boundary(fit.c0);
    const double c = contact::bcore_factor(nu);
    nlohmann::json crossovers = nlohmann::json::array();
    for (double R : Rs) {
      const nuc::Crossover cr = nuc::regime_two_three_crossover(R, alpha, nu, model);
      nlohmann::json j = {{"R", R}, {"found", cr.found}};
      if (cr.found) {
        // Error of a: c0 and the (k1, k2) pair moved both ways along each independent direction
        // by its reported error (moved_model), the larger shift of a taken, in quadrature.
        // A move after which there is no crossover in range leaves the error incomplete.
        // Not included: the law's extrapolation below its fit window (law_extrapolated), a
        // systematic error (docs/nucleation.md).
        double var = 0.0;
        bool complete = true;
        for (int k = 0; k < 3; ++k) {
          double shift = 0.0;
          for (double sign : {1.0, -1.0}) {
            const std::optional<nuc::Model> m = moved_model(k, sign);
            if (!m) {
              complete = false;
              continue;
            }
            const nuc::Crossover moved = nuc::regime_two_three_crossover(R, alpha, nu, *m);
            if (moved.found) {
              shift = std::max(shift, std::abs(moved.a - cr.a));
            } else {
              complete = false;
            }
          }
          var += shift * shift;
        }
        j["a_error"] = std::sqrt(var);
        j["a_error_complete"] = complete;
      }
      if (cr.found)
        j.update({{"a", cr.a},
                  {"a_over_bcore0", cr.a_over_bcore0},
                  {"mu_over_alpha", cr.mu_over_alpha},
                  {"a_below_0.1_R", cr.small_slope},
                  {"bcore0", cr.a / cr.a_over_bcore0},
                  {"law_extrapolated", extrapolated(cr.a / cr.a_over_bcore0)}});
      j["regime_one_a"] = std::sqrt(x_one * R / (c * alpha));
      crossovers.push_back(j);
    }

    // Regime III: the upturn of each branch, model and R (its lowest point and every point past
    // it that rises) against the prediction, and a fit of k1, k2 to the rising points where there
    // are enough.
    nlohmann::json upturns = nlohmann::json::array();
    std::vector<double> beta3, mu3;
    std::set<std::pair<std::string, double>> branches;
    for (const auto& p : pts)
      branches.insert({p.model, p.R});
    for (const auto& [model_name, R] : branches) {
      std::vector<std::size_t> idx;
      for (std::size_t i = 0; i < pts.size(); ++i)
        if (pts[i].R == R && pts[i].model == model_name) idx.push_back(i);
      std::sort(idx.begin(), idx.end(),
                [&](std::size_t i, std::size_t j) { return pts[i].a < pts[j].a; });
      std::vector<std::size_t> branch;
      for (std::size_t k = 0; k < idx.size(); ++k) {
        if (simulated[idx[k]] != nuc::Regime::three) continue;
        if (branch.empty()) {
          // The branch starts at the lowest point before the first rising one.
          std::size_t lowest = idx[0];
          for (std::size_t m = 0; m < k; ++m)
            if (pts[idx[m]].mu < pts[lowest].mu) lowest = idx[m];
          branch.push_back(lowest);
        }
        branch.push_back(idx[k]);
      }
      if (branch.size() < 2) continue;
      std::vector<double> a, mu_data, mu_int, mu_comb;
      nlohmann::json rows = nlohmann::json::array();
      double worst_factor = 1.0;
      for (std::size_t i : branch) {
        const auto& pr = predictions[i];
        a.push_back(pts[i].a);
        mu_data.push_back(pts[i].mu);
        mu_int.push_back(pr.integrated);
        mu_comb.push_back(pr.mu_over_alpha);
        const double ratio = pts[i].mu / pr.integrated;
        worst_factor = std::max(worst_factor, std::max(ratio, 1.0 / ratio));
        rows.push_back({{"a", pts[i].a},
                        {"a_over_bcore0", pts[i].x},
                        {"mu_over_alpha", pts[i].mu},
                        {"regime_three_integrated", pr.integrated},
                        {"regime_three_central", pr.central},
                        {"predicted", pr.mu_over_alpha},
                        {"data_over_integrated", ratio}});
        // The fit takes only the rising points: the branch's lowest one is set by nucleation.
        if (simulated[i] == nuc::Regime::three) {
          beta3.push_back(pts[i].a / pts[i].x);
          mu3.push_back(pts[i].mu);
        }
      }
      const double sd = log_slope(a, mu_data), si = log_slope(a, mu_int),
                   sc = log_slope(a, mu_comb);
      upturns.push_back({{"R", R},
                         {"model", model_name},
                         {"a_range", {a.front(), a.back()}},
                         {"points", rows},
                         {"slope_dlnmu_dlna_data", sd},
                         {"slope_dlnmu_dlna_integrated", si},
                         {"slope_dlnmu_dlna_predicted", sc},
                         {"same_sign_of_slope", (sd > 0) == (si > 0)},
                         {"worst_factor_data_vs_integrated", worst_factor},
                         {"within_factor_2", worst_factor <= 2.0}});
    }
    nlohmann::json fit3 = {{"points", beta3.size()}};
    // Two parameters: at least 4 points, so that the errors rest on 2 degrees of freedom.
    if (beta3.size() >= 4) {
      const nuc::RegimeThreeFit f3 = nuc::fit_regime_three(
          beta3, mu3, {.form = nuc::RegimeThreeForm::integrated, .f_P = o.f_P});
      fit3["form"] = "integrated";
      fit3["valid"] = f3.valid;
      if (f3.valid) {
        fit3.update({{"k1", f3.law.k1},
                     {"k1_error", f3.law.k1_error},
                     {"k2", f3.law.k2},
                     {"k2_error", f3.law.k2_error},
                     {"correlation", f3.correlation},
                     {"window_bcore0", {f3.beta_min, f3.beta_max}},
                     {"dof", f3.dof},
                     {"rms_log_residual", f3.rms_log_residual}});
      } else {
        fit3["reason"] = f3.reason;
      }
    } else {
      fit3["reason"] = "fewer than 4 simulated Regime III points";
    }

    const fs::path dir = app::ensure_directory(o.out);
    app::remove_stale_temporaries(dir);
    table.write(dir / "predictions.csv");

    // Figures.
    std::vector<fs::path> figures;
    {
      std::vector<app::Series> s;
      std::map<std::pair<std::string, double>, app::Series> groups;
      const char* markers[] = {"7", "5", "9", "11", "13", "15"};
      for (const auto& p : pts) {
        auto& g = groups[{p.model, p.R}];
        g.x.push_back(p.x);
        g.y.push_back(p.mu);
      }
      // One colour per R (data and its predictions), one marker per model.
      const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#8c564b", "#e377c2"};
      std::map<double, std::string> colour_of;
      for (double R : Rs)
        colour_of[R] = colours[colour_of.size() % 6];
      std::map<std::string, std::string> marker_of;
      for (auto& [key, g] : groups) {
        if (!marker_of.count(key.first)) marker_of[key.first] = markers[marker_of.size() % 6];
        g.title = key.first + ", R = " + fmt("%g", key.second) + " d";
        g.style =
            "points pt " + marker_of[key.first] + " ps 1.6 lc rgb '" + colour_of[key.second] + "'";
        s.push_back(g);
      }
      double xmin = pts.front().x, xmax = xmin;
      for (const auto& p : pts) {
        xmin = std::min(xmin, p.x);
        xmax = std::max(xmax, p.x);
      }
      xmin /= 2.0;
      xmax *= 3.0;
      // Far enough to show each R's predicted II -> III crossover.
      for (const auto& j : crossovers) {
        if (j["found"].get<bool>()) xmax = std::max(xmax, 2.0 * j["a_over_bcore0"].get<double>());
      }
      app::Series one{.title = "Regime I: mu/alpha = 1", .style = "lines dt 3 lw 2 lc 'gray40'"};
      one.x = {xmin, xmax};
      one.y = {1.0, 1.0};
      s.push_back(one);
      app::Series law_in{.title = "Regime II fit: c0 = " + fmt("%.3f", fit.c0) + " +- " +
                                  fmt("%.3f", fit.c0_error) + " (window " +
                                  fmt("%g", fit.window_lo) + ".." + fmt("%g", fit.window_hi) + ")",
                         .style = "lines lw 2.5 lc 'black'"};
      app::Series law_out{.title = "", .style = "lines dt 2 lw 1 lc 'black'"};
      app::Series cond{.title = "nucleation condition (no expansion), min(1, 3(1 - x*^2))",
                       .style = "lines lw 1.5 lc 'dark-orange'"};
      for (int i = 0; i <= 200; ++i) {
        const double x = xmin * std::pow(xmax / xmin, i / 200.0);
        const double y = nuc::regime_two_law(x, fit.c0);
        const bool inside = x >= fit.window_lo && x <= fit.window_hi;
        law_in.x.push_back(x);
        law_in.y.push_back(inside ? y : NAN);
        law_out.x.push_back(x);
        law_out.y.push_back(y <= 1.5 ? y : NAN);
        cond.x.push_back(x);
        cond.y.push_back(nuc::nucleation_condition(x, fit.c0).mu_over_alpha);
      }
      s.push_back(law_out);
      s.push_back(law_in);
      s.push_back(cond);
      for (double R : Rs) {
        app::Series r3{.title = "Regime III, integrated f_P tau_P, R = " + fmt("%g", R) + " d",
                       .style = "lines lw 2 dt 4 lc rgb '" + colour_of[R] + "'"};
        app::Series comb{.title = "prediction max(II, III), R = " + fmt("%g", R) + " d",
                         .style = "lines lw 1 dt 1 lc rgb '" + colour_of[R] + "'"};
        for (int i = 0; i <= 200; ++i) {
          const double x = xmin * std::pow(xmax / xmin, i / 200.0);
          const double a = std::sqrt(x * R / (c * alpha));
          const nuc::Prediction pr = nuc::predict(x, a / x, model);
          r3.x.push_back(x);
          r3.y.push_back(pr.integrated > 1e-3 ? pr.integrated : NAN);
          comb.x.push_back(x);
          comb.y.push_back(pr.mu_over_alpha);
        }
        s.push_back(r3);
        s.push_back(comb);
      }
      const fs::path png = dir / "collapse.png";
      app::plot_png(png, s,
                    {.title = "Friction collapse: alpha = " + fmt("%g", alpha) +
                              ", nu = " + fmt("%g", nu) + "; k1 = " + fmt("%.3g", law.law.k1) +
                              ", k2 = " + fmt("%.3g", law.law.k2) + ", f_P = " + fmt("%g", o.f_P),
                     .xlabel = "a / b_core^0",
                     .ylabel = "mu / alpha",
                     .logx = true,
                     .logy = true,
                     .width = 1100,
                     .height = 750,
                     .yrange = std::pair{1e-3, 2.0},
                     .extra_commands = {"set key bottom left font ',9'", "set grid"}});
      figures.push_back(png);
    }
    {
      const int n = 80;
      std::vector<double> ax, Ry, v;
      std::vector<double> map_a = o.map_a, map_R = o.map_R;
      if (map_a.empty()) {
        double lo = pts.front().a, hi = lo;
        for (const auto& p : pts) {
          lo = std::min(lo, p.a);
          hi = std::max(hi, p.a);
        }
        for (const auto& j : crossovers) {
          if (j["found"].get<bool>()) hi = std::max(hi, 1.5 * j["a"].get<double>());
        }
        map_a = {lo / 2.0, 3.0 * hi};
      }
      if (map_R.empty()) map_R = {*Rs.begin() / 2.0, *Rs.rbegin() * 2.0};
      for (int i = 0; i < n; ++i) {
        ax.push_back(map_a[0] * std::pow(map_a[1] / map_a[0], i / (n - 1.0)));
        Ry.push_back(map_R[0] * std::pow(map_R[1] / map_R[0], i / (n - 1.0)));
      }
      for (double a : ax) {
        for (double R : Ry) {
          const double x = c * alpha * a * a / R;
          v.push_back(std::log10(nuc::predict(x, a / x, model).mu_over_alpha));
        }
      }
      std::vector<app::Series> overlays;
      app::Series b12{.title = "I | II (a/b_core^0 = " + fmt("%.2f", x_one_two) + ")",
                      .style = "lines lw 2.5 lc 'black'"};
      app::Series b23{.title = "II | III (prediction)", .style = "lines lw 2.5 lc 'red'"};
      app::Series slope{.title = "a = 0.1 R", .style = "lines dt 2 lw 1.5 lc 'gray70'"};
      for (double R : Ry) {
        b12.x.push_back(std::sqrt(x_one_two * R / (c * alpha)));
        b12.y.push_back(R);
        const nuc::Crossover cr = nuc::regime_two_three_crossover(R, alpha, nu, model);
        b23.x.push_back(cr.found ? cr.a : NAN);
        b23.y.push_back(R);
        slope.x.push_back(0.1 * R);
        slope.y.push_back(R);
      }
      overlays.push_back(b12);
      overlays.push_back(b23);
      overlays.push_back(slope);
      if (law.law.b_min > 0.0) {
        // Right of this line the centre's core width is below the Peierls fit window.
        app::Series edge{.title = "b_core^0 = " + fmt("%g", law.law.b_min) +
                                  " d (right: Peierls law extrapolated)",
                         .style = "lines dt 4 lw 2 lc 'white'"};
        for (double R : Ry) {
          edge.x.push_back(R / (c * alpha * law.law.b_min));
          edge.y.push_back(R);
        }
        overlays.push_back(edge);
      }
      const char* style[] = {"points pt 7 ps 1.6 lc 'orange'", "points pt 5 ps 1.6 lc 'cyan'",
                             "points pt 9 ps 2 lc 'magenta'"};
      for (nuc::Regime r : {nuc::Regime::one, nuc::Regime::two, nuc::Regime::three}) {
        app::Series d{.title = "simulated " + nuc::to_string(r),
                      .style = style[static_cast<int>(r) - 1]};
        for (std::size_t i = 0; i < pts.size(); ++i) {
          if (simulated[i] != r) continue;
          d.x.push_back(pts[i].a);
          d.y.push_back(pts[i].R);
        }
        if (!d.x.empty()) overlays.push_back(d);
      }
      // Disagreements: circled where the prediction decides, boxed where it cannot (a point on
      // a boundary within 2 errors of the fits, regime_undetermined).
      app::Series wrong{.title = "predicted regime differs",
                        .style = "points pt 6 ps 3 lc 'black'"};
      app::Series open{.title = "differs, on a boundary within 2 errors",
                       .style = "points pt 4 ps 3 lc 'black'"};
      for (const auto& dj : disagreements) {
        app::Series& into = dj["regime_undetermined"].get<bool>() ? open : wrong;
        into.x.push_back(dj["a"].get<double>());
        into.y.push_back(dj["R"].get<double>());
      }
      for (app::Series* ser : {&wrong, &open})
        if (!ser->x.empty()) overlays.push_back(*ser);
      const fs::path png = dir / "regime_map.png";
      app::heatmap_png(
          png, ax, Ry, v,
          {.title = "Predicted log10(mu/alpha): c0 = " + fmt("%.3f", fit.c0) +
                    ", k1 = " + fmt("%.3g", law.law.k1) + ", k2 = " + fmt("%.3g", law.law.k2) +
                    ", f_P = " + fmt("%g", o.f_P) + ", alpha = " + fmt("%g", alpha),
           .xlabel = "a / d",
           .ylabel = "R / d",
           .logx = true,
           .logy = true,
           .width = 1500,
           .height = 750,
           .extra_commands = {"set rmargin 50", "set key at screen 0.99,0.85 right top font ',9'"}},
          "log10(mu/alpha)", std::nullopt, overlays);
      figures.push_back(png);
    }

    nlohmann::json window_R_json = nlohmann::json::array();
    for (double R : window_R)
      window_R_json.push_back(R);
    nlohmann::json figure_names = nlohmann::json::array();
    for (const auto& f : figures)
      figure_names.push_back(f.filename().string());
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    app::write_json(
        dir / "summary.json",
        {{"tool", "fit_scaling"},
         {"inputs",
          {{"sweeps", data.sources},
           {"alpha", alpha},
           {"alpha_rule", map_alpha.rule},
           {"alpha_range", {map_alpha.min, map_alpha.max}},
           {"nu", nu}}},
         {"regime_two",
          {{"law", "mu/alpha = 3 (2 c0)^(2/3) (a/b_core^0)^(-2/3)"},
           {"c0", fit.c0},
           {"c0_error", fit.c0_error},
           {"error_kind",
            "bootstrap over points of ln(2 c0), x sqrt(n/(n-1)) x t_{n-1}(Phi(2))/2: +-2 errors "
            "is the 95.45% interval"},
           {"c0_se_bootstrap", fit.c0_se_bootstrap},
           {"c0_interval_2_errors", {fit.c0_lo, fit.c0_hi}},
           {"prefactor", fit.prefactor},
           {"prefactor_error", fit.prefactor_error},
           {"window_a_over_bcore0", {fit.window_lo, fit.window_hi}},
           {"window_automatic", fit.window_automatic},
           {"window_R", window_R_json},
           {"points", fit.points},
           {"dof", fit.dof},
           {"t_factor", fit.t_factor},
           {"points_trimmed", fit.trimmed},
           {"max_relative_deviation", fit.max_relative_deviation},
           {"within_max_deviation", fit.within_max_deviation},
           {"rms_log_residual", fit.rms_log_residual},
           {"free_slope", fit.free_slope},
           {"free_slope_error", fit.free_slope_error},
           {"c0_lower_half", fit.c0_lower_half},
           {"c0_upper_half", fit.c0_upper_half},
           {"c0_window_spread", fit.c0_window_spread},
           {"bootstrap_samples", o.bootstrap},
           {"seed", o.seed}}},
         {"regime_one_crossover",
          {{"a_over_bcore0_condition_reaches_1", x_one},
           {"a_over_bcore0_condition_reaches_1_error", x_one * fit.c0_error / fit.c0},
           {"a_over_bcore0_boundary", x_one_two},
           {"a_over_bcore0_boundary_error", x_one_two * fit.c0_error / fit.c0},
           {"boundary_rule", "nearer asymptote in ln(mu/alpha): 1 or the Regime II law"}}},
         {"peierls", law.json},
         {"f_P", o.f_P},
         {"crossovers_two_three", crossovers},
         {"regime_three_upturns", upturns},
         {"regime_three_fit_to_friction", fit3},
         {"regime_map",
          {{"points", pts.size()},
           {"agree", agree},
           {"all_agree", agree == pts.size()},
           {"points_law_in_window", in_law},
           {"agree_law_in_window", agree_in_law},
           {"undetermined", undetermined},
           {"contradictions", contradictions},
           {"disagreements", disagreements},
           {"rule",
            "III: rising branch (simulated) / Regime III law above the nucleation condition "
            "(predicted); else I or II by the nearer asymptote"}}},
         {"predictions", "predictions.csv"},
         {"figures", figure_names},
         {"run", {{"wall_s", wall}, {"provenance", app::provenance_json()}}}});

    std::printf("c0 = %.4f +- %.4f (a/b_core^0 in [%g, %g], %zu points%s; fit within %.1f%%)\n",
                fit.c0, fit.c0_error, fit.window_lo, fit.window_hi, fit.points,
                fit.window_automatic
                    ? (", automatic window, " + std::to_string(fit.trimmed) + " trimmed").c_str()
                    : "",
                100.0 * fit.max_relative_deviation);
    if (!fit.within_max_deviation)
      std::fprintf(stderr,
                   "fit_scaling: warning: the Regime II law misses a point of the window by "
                   "%.1f%%, more than %.0f%%%s: the data do not follow the law there\n",
                   100.0 * fit.max_relative_deviation, 100.0 * fo.automatic.max_deviation,
                   fit.window_automatic ? " even with the window trimmed to its minimum" : "");
    if (fit.free_slope_error > 0.0)
      std::printf(
          "  free log-log slope %.3f +- %.3f (law: -2/3); c0 lower / upper half of the "
          "window %.4f / %.4f\n",
          fit.free_slope, fit.free_slope_error, fit.c0_lower_half, fit.c0_upper_half);
    std::printf("Peierls law: k1 = %.4g +- %.2g, k2 = %.4g +- %.2g; f_P = %g\n", law.law.k1,
                law.law.k1_error, law.law.k2, law.law.k2_error, o.f_P);
    std::printf("Regime I boundary: a/b_core^0 = %.3g (condition reaches mu = alpha at %.3g)\n",
                x_one_two, x_one);
    for (const auto& j : crossovers) {
      if (j["found"].get<bool>()) {
        std::printf(
            "II -> III crossover at R = %g d: a = %.4g +- %.2g d (a/b_core^0 = %.4g, "
            "b_core^0 = %.3g d%s, mu/alpha = %.4g)\n",
            j["R"].get<double>(), j["a"].get<double>(), j["a_error"].get<double>(),
            j["a_over_bcore0"].get<double>(), j["bcore0"].get<double>(),
            j["law_extrapolated"].get<bool>() ? ", below the Peierls fit window" : "",
            j["mu_over_alpha"].get<double>());
      }
    }
    for (const auto& u : upturns) {
      std::printf(
          "upturn at R = %g d: slope dln(mu)/dln(a) data %.3f, prediction %.3f; worst "
          "factor %.3g\n",
          u["R"].get<double>(), u["slope_dlnmu_dlna_data"].get<double>(),
          u["slope_dlnmu_dlna_integrated"].get<double>(),
          u["worst_factor_data_vs_integrated"].get<double>());
    }
    std::printf(
        "regime map: %zu of %zu points in their simulated regime (%zu of %zu where the "
        "Peierls law is used within its window); %zu disagree where the prediction decides "
        "(%zu points within 2 errors of a boundary)\n",
        agree, pts.size(), agree_in_law, in_law, contradictions, undetermined);
    std::printf("results: %s\n", fs::absolute(dir / "summary.json").c_str());
    for (const auto& f : figures)
      std::printf("figure:  %s\n", fs::absolute(f).c_str());
    return 0;
  });
}
