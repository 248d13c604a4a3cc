// fit_scaling's pieces (main.cpp wires them): the options, the friction_sweep tables and the
// Peierls law read in, the nucleation/ analysis they feed, and the files and report written
// from it. The physics and statistics are nucleation/'s; this is input, wiring and output.
//
// Each row carries its interface envelope (sweep.csv's envelope column, issue 27; tables made
// before it are Hertz tables), and each envelope has its law:
// - hertz: mu/alpha = 3 (2 c0)^(2/3) (a/b_core^0)^(-2/3), with the Regime III prediction, the
//   crossovers and the regime map (which need the Peierls law): predictions.csv, collapse.png,
//   regime_map.png, summary.json's regime_two ... regime_map;
// - adhesive: tau_fric/tau0 = 2 (a/(2 c0 b_core))^(-1/2), c0 fitted alike:
//   adhesive_predictions.csv, adhesive_collapse.png, summary.json's "adhesive";
// - mixed (tau0 + alpha p): each point against both limits, the Hertz law at its Hertz control
//   parameter and the adhesive law at its tau0 one, each with its c0 (fitted from the tables of
//   that envelope given along, or --c0-hertz, --c0-adhesive), and the mixed nucleation
//   condition: mixed_predictions.csv, mixed_limits.png, summary.json's "mixed".
#pragma once

#include <cstddef>
#include <filesystem>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "asperity/core/common/settings.hpp"
#include "asperity/nucleation/comparison.hpp"
#include "asperity/nucleation/regime_map.hpp"
#include "asperity/nucleation/regime_three.hpp"
#include "asperity/nucleation/regime_two.hpp"

namespace asperity::app::fit_scaling {

struct Options {
  std::vector<std::string> sweeps;  // sweep.csv files or friction_sweep output folders
  std::string peierls;              // peierls_scan summary.json or its folder; empty: k1, k2 given
  std::optional<double> k1, k2;     // Peierls law (dimensionless); override the summary
  double k1_error = 0.0, k2_error = 0.0;             // their errors when given
  std::optional<double> correlation;                 // of k1 and k2 when given, in [-1, 1]
  double f_P = nucleation::kDefaultPeierlsFraction;  // fraction of the local Peierls stress
  std::vector<double> window;  // Regime II window in a/b_core^0 (2 values); empty: automatic
  // bootstrap resamples for c0, and their seed: the fit's own defaults
  int bootstrap = nucleation::RegimeTwoFitOptions{}.bootstrap_samples;
  long long seed = static_cast<long long>(nucleation::RegimeTwoFitOptions{}.seed);
  // Regime map ranges (d); empty: from the data (a/2 .. 3 a_max or past the crossovers, R/2 .. 2
  // R).
  std::vector<double> map_a, map_R;
  double rise_tolerance = 0.02;  // relative rise of mu/alpha that marks Regime III data
  // c0 of the Hertz and adhesive laws for the mixed rows, when no table of that envelope is given
  // (one that is given is fitted and used instead).
  std::optional<double> c0_hertz, c0_adhesive;
  // Forecast (d): the prediction at every a of forecast_a at every R of forecast_R, for sweeps
  // still to be run (forecast.csv); both empty: none.
  std::vector<double> forecast_R, forecast_a;
  std::string out = "results/fit_scaling";

  // Each setting described once (core/common/settings.hpp; the inputs, sweeps, peierls and out,
  // are not settings): the flags, their checks, --list-settings, summary.json's "settings" echo
  // and validate() come from this table.
  static const settings::Table<Options>& settings();
  // Throws std::invalid_argument naming the setting and the constraint: each row's, then those
  // between settings (two window values in order, the forecast's lists together, ...).
  void validate() const;
  // Whether a Peierls law is given (--peierls, or --k1 and --k2): the Hertz tables need one.
  [[nodiscard]] bool has_law() const { return !peierls.empty() || (k1 && k2); }
};

// printf-style formatting of one number, for messages and figure titles.
std::string fmt(const char* format, double v);

struct DataPoint {
  std::string source, model;
  // x = a/b_core^0 of the row's envelope; mu = its friction over its Regime I value, the y of its
  // law: mu/alpha (hertz), tau_fric/tau0 (adhesive), Fx/(alpha Fz + tau0 A) (mixed)
  double a = 0, R = 0, alpha = 0, nu = 0, x = 0, mu = 0;
  int slip_events = 0;
  // mu is a lower bound (mu_is_lower_bound): the slide reached its cap still rising. Kept for
  // the Hertz law's regime map and upturns (nucleation::ScalingPoint::lower_bound), never
  // fitted; left out of the adhesive and mixed analyses.
  bool lower_bound = false;
  std::string envelope = "hertz";  // tables before the envelopes: hertz
  double tau0 = 0.0, G = 1.0;      // tau0 in the unit of stress, G the substrate's (1 before)
  // Mixed rows: the friction against each limit.
  double mu_over_alpha = std::numeric_limits<double>::quiet_NaN();
  double tau_fric_over_tau0 = std::numeric_limits<double>::quiet_NaN();
};

// The points of each envelope, each in the order of the tables.
struct ByEnvelope {
  std::vector<DataPoint> hertz, adhesive, mixed;
};
ByEnvelope split_envelopes(const std::vector<DataPoint>& pts);

struct Loaded {
  std::vector<DataPoint> points;
  nlohmann::json sources = nlohmann::json::array();  // per table: rows used and skipped
};

// The usable rows of friction_sweep tables (sweep.csv or its folder): failed points are left
// out and counted, lower bounds flagged and counted (DataPoint::lower_bound). Throws
// std::invalid_argument for a missing or foreign table, a bad row, no usable point or a point given
// twice.
Loaded load_sweeps(const std::vector<std::string>& sweeps);

// One regime map and one set of crossovers need one material and one alpha. The lateral force
// model's alpha is a parameter, the same on every row of a sweep; the explicit model's is the
// potential's, measured at each point's central load (0.709 ... 0.719 for a tip set up for 0.7,
// data/reference/sweep_explicit_R160.csv). Each row carries its own alpha into a/b_core^0 and
// b_core^0, so every per-point prediction uses it; only the map and the crossovers use the common
// alpha: the LFM rows' if there are any, else the mean. Rows further than 5% from it would put
// the map off by more than that in a/b_core^0, and are refused (std::invalid_argument).
struct MapAlpha {
  double alpha = 0.0;
  double min = 0.0, max = 0.0;  // over all rows
  std::string rule;
};
MapAlpha common_alpha(const std::vector<DataPoint>& pts);

struct LawSource {
  nucleation::PeierlsLaw law;
  // Factor from the law's errors to reported errors (statistics.hpp): t_factor of the scan fit's
  // degrees of freedom (points - 2) for its plain standard errors, 1 for given errors.
  double error_factor = 1.0;
  nlohmann::json json;  // the "peierls" entry of summary.json
};

// The edge fit of a peierls_scan summary, or k1, k2 given (the pair overrides the summary).
LawSource read_law(const Options& o);

// Everything fit_scaling reports, from nucleation/.
struct Analysis {
  MapAlpha map_alpha;
  double alpha = 0.0, nu = 0.0;                  // of the map and the crossovers
  std::vector<std::string> series_names;         // model name of each ScalingPoint::series
  std::vector<nucleation::ScalingPoint> points;  // the data points, in order
  nucleation::RegimeTwoFitOptions fit_options;
  nucleation::RegimeTwoFit fit;
  nucleation::Model model;    // c0 fitted, the law's errors on the reported footing
  std::set<double> window_R;  // R of the points in the Regime II window
  // Points of the Regime II window on a rising branch (simulated Regime III): the automatic
  // window stops before an upturn, a --window given by hand can hold them.
  std::vector<std::size_t> window_rising;
  std::vector<nucleation::PointComparison> comparisons;  // per point
  nucleation::MapAgreement agreement;
  double x_one = 0.0;      // a/b_core^0 where the nucleation condition reaches mu = alpha
  double x_one_two = 0.0;  // the predicted I/II boundary
  std::set<double> Rs;     // R of the data
  std::vector<nucleation::CrossoverEstimate> crossovers;  // II -> III, per R in Rs
  std::vector<nucleation::Upturn> upturns;                // by model name, then R
  nucleation::RegimeThreeFrictionFit fit_three;
  // Options::forecast_R and forecast_a: the II -> III crossover at each R, and the forecast at
  // each (R, a), R by R in the order given.
  std::vector<nucleation::CrossoverEstimate> forecast_crossovers;
  std::vector<nucleation::Forecast> forecasts;
};

// Throws std::invalid_argument when the data allow no Regime II fit or no common alpha.
Analysis analyse(const std::vector<DataPoint>& pts, const LawSource& law, const Options& o);

// The adhesive tables: the adhesive law's fit of c0 with its error (the same window rules,
// bootstrap and checks as the Hertz law's), and the nucleation condition at the fitted c0.
struct AdhesiveAnalysis {
  nucleation::RegimeTwoLaw law = nucleation::adhesive_law();
  std::vector<nucleation::ScalingPoint> points;
  nucleation::RegimeTwoFitOptions fit_options;
  nucleation::RegimeTwoFit fit;
  double x_one = 0.0;  // a/b_core^0 where the nucleation condition reaches tau_fric = tau0
  // The condition's own log-log slope over the window's points at the fitted c0: what its
  // finite-size correction (relative -q/4, q = c0/(a/b_core)) makes of the law's -1/2, to set
  // the data's free slope against.
  double condition_slope = 0.0;
};
// Throws std::invalid_argument when the data allow no fit.
AdhesiveAnalysis analyse_adhesive(const std::vector<DataPoint>& pts, const Options& o);

// A limit's c0 for the mixed rows and where it came from ("" and NaN: none).
struct LimitC0 {
  double c0 = std::numeric_limits<double>::quiet_NaN();
  double error = std::numeric_limits<double>::quiet_NaN();
  std::string source;
};

// A mixed row against both limits (NaN where the limit's c0 is missing).
struct MixedPoint {
  double x_hertz = 0.0;         // c alpha a^2 / (R d): a/b_core^0 of alpha p alone
  double x_adhesive = 0.0;      // a tau0 / (d G): a/b_core^0 of tau0 alone
  double hertz_limit = 0.0;     // mu/alpha of the Hertz condition at x_hertz, c0 of the Hertz law
  double adhesive_limit = 0.0;  // tau_fric/tau0 of the adhesive condition at x_adhesive
  // Fx/F_I of the mixed condition (nucleation::mixed_nucleation_condition) with each c0.
  double mixed_with_c0_hertz = 0.0, mixed_with_c0_adhesive = 0.0;
};
struct MixedAnalysis {
  LimitC0 hertz, adhesive;
  std::vector<MixedPoint> points;
};
MixedAnalysis analyse_mixed(const std::vector<DataPoint>& pts, const LimitC0& hertz,
                            const LimitC0& adhesive);

// forecast.csv: per forecast contact (Analysis::forecasts) the prediction, its error and slope.
void write_forecast(const std::filesystem::path& csv, const Analysis& an);

// predictions.csv: per data point, mu/alpha measured and every prediction, both regimes.
void write_predictions(const std::filesystem::path& csv, const std::vector<DataPoint>& pts,
                       const Analysis& an);
// adhesive_predictions.csv and mixed_predictions.csv: per point, measured and predicted.
void write_adhesive_predictions(const std::filesystem::path& csv, const std::vector<DataPoint>& pts,
                                const AdhesiveAnalysis& an);
void write_mixed_predictions(const std::filesystem::path& csv, const std::vector<DataPoint>& pts,
                             const MixedAnalysis& an);

// adhesive_collapse.png (tau_fric/tau0 against a/b_core^0 with the law and the condition) and
// mixed_limits.png (each mixed point against both limits' laws).
std::filesystem::path write_adhesive_figure(const std::filesystem::path& dir,
                                            const std::vector<DataPoint>& pts,
                                            const AdhesiveAnalysis& an);
std::filesystem::path write_mixed_figure(const std::filesystem::path& dir,
                                         const std::vector<DataPoint>& pts,
                                         const MixedAnalysis& an);

// collapse.png and regime_map.png in `dir`; returns their paths.
std::vector<std::filesystem::path> write_figures(const std::filesystem::path& dir,
                                                 const std::vector<DataPoint>& pts,
                                                 const LawSource& law, const Analysis& an,
                                                 const Options& o);

// What one run of fit_scaling found, per envelope (each null where its tables are absent).
struct Results {
  const ByEnvelope* points = nullptr;
  const LawSource* law = nullptr;  // given or read; required with Hertz tables
  const Analysis* hertz = nullptr;
  const AdhesiveAnalysis* adhesive = nullptr;
  const MixedAnalysis* mixed = nullptr;
};

// summary.json.
void write_summary(const std::filesystem::path& json, const Loaded& data, const Results& res,
                   const Options& o, const std::vector<std::filesystem::path>& figures,
                   double wall_s);

// The results on stdout, a fit that misses its window's points on stderr.
void print_report(const std::filesystem::path& dir, const Results& res, const Options& o,
                  const std::vector<std::filesystem::path>& figures);

}  // namespace asperity::app::fit_scaling
