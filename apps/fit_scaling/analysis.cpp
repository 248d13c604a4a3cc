// fit_scaling's analysis: the data handed to nucleation/ (fit, model, comparison, crossovers,
// upturns) in the order the tool reports them.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "asperity/nucleation/regime_three.hpp"
#include "fit_io.hpp"

namespace asperity::app::fit_scaling {

namespace nuc = asperity::nucleation;

namespace {

// The data as the fits' points, each in the series `series(p)` says: the automatic window
// follows each branch (falling, then rising) per series and R.
template <class Series>
std::vector<nuc::ScalingPoint> scaling_points(const std::vector<DataPoint>& pts, Series series) {
  std::vector<nuc::ScalingPoint> out;
  for (const auto& p : pts)
    out.push_back({.a_over_bcore0 = p.x,
                   .mu_over_alpha = p.mu,
                   .a = p.a,
                   .R = p.R,
                   .series = series(p),
                   .lower_bound = p.lower_bound});
  return out;
}

// The fit of c0 to `law` as the options ask: bootstrap, seed, the rise that ends a branch, and
// a window if one is given.
nuc::RegimeTwoFitOptions fit_options(const nuc::RegimeTwoLaw& law, const Options& o) {
  nuc::RegimeTwoFitOptions f{
      .law = law, .bootstrap_samples = o.bootstrap, .seed = static_cast<std::uint64_t>(o.seed)};
  f.automatic.rise_tolerance = o.rise_tolerance;
  if (!o.window.empty()) f.window = std::pair{o.window[0], o.window[1]};
  return f;
}

}  // namespace

Analysis analyse(const std::vector<DataPoint>& pts, const LawSource& law, const Options& o) {
  Analysis an;
  an.map_alpha = common_alpha(pts);
  an.alpha = an.map_alpha.alpha;
  an.nu = pts.front().nu;

  // Branches (falling, then rising) are per model and R: one series per model, numbered in the
  // order the models first appear.
  std::map<std::string, int> series_of;
  for (const auto& p : pts)
    series_of.emplace(p.model, static_cast<int>(series_of.size()));
  an.series_names.resize(series_of.size());
  for (const auto& [name, series] : series_of)
    an.series_names[static_cast<std::size_t>(series)] = name;
  an.points = scaling_points(pts, [&](const DataPoint& p) { return series_of.at(p.model); });

  // Regime II fit.
  an.fit_options = fit_options(nuc::hertz_law(), o);
  an.fit = nuc::fit_regime_two(an.points, an.fit_options);
  if (!an.fit.valid)
    throw std::invalid_argument("no Regime II fit: " + an.fit.reason +
                                " (give --window, or add points)");
  // k1 and k2 errors of a peierls_scan summary are plain standard errors: on the footing of
  // c0's reported error they are multiplied by t_factor of their degrees of freedom
  // (statistics.hpp), in the model too, so that the per-point regime_three_log_error is a
  // reported error like every other (+-2 of them: the 95.45% interval).
  an.model = {.c0 = an.fit.c0, .law = nuc::scaled_errors(law.law, law.error_factor), .f_P = o.f_P};
  for (std::size_t i : an.fit.used)
    an.window_R.insert(pts[i].R);

  // Per point: predictions and regimes.
  const std::vector<nuc::Regime> simulated =
      nuc::simulated_regimes(an.points, an.fit.c0, o.rise_tolerance);
  an.comparisons = nuc::compare_points(an.points, simulated, an.model, an.fit.c0_error);
  for (std::size_t i : an.fit.used)
    if (simulated[i] == nuc::Regime::three) an.window_rising.push_back(i);
  an.agreement = nuc::map_agreement(an.comparisons);

  // Crossovers: Regime I (a/b_core^0, any R), II -> III per R of the data.
  for (const auto& p : pts)
    an.Rs.insert(p.R);
  an.x_one = nuc::regime_one_crossover(an.fit.c0);
  an.x_one_two = nuc::regime_one_two_boundary(an.fit.c0);
  for (double R : an.Rs)
    an.crossovers.push_back(
        nuc::crossover_with_error(R, an.alpha, an.nu, an.model, an.fit.c0_error));

  // Regime III: the upturn of each branch against the prediction, and a fit of k1, k2 to the
  // rising points where there are enough. Listed, and fitted, by model name and R: the
  // summaries have always listed them so, and the fit's sums run in this order.
  an.upturns = nuc::regime_three_upturns(an.points, an.comparisons);
  std::stable_sort(an.upturns.begin(), an.upturns.end(), [&](const auto& u, const auto& v) {
    const auto& name_u = an.series_names[static_cast<std::size_t>(u.series)];
    const auto& name_v = an.series_names[static_cast<std::size_t>(v.series)];
    return std::tie(name_u, u.R) < std::tie(name_v, v.R);
  });
  an.fit_three = nuc::fit_regime_three_to_upturns(an.points, an.comparisons, an.upturns, o.f_P);

  // The forecast for contacts without data, in the map's alpha and nu (as the crossovers).
  for (double R : o.forecast_R) {
    an.forecast_crossovers.push_back(
        nuc::crossover_with_error(R, an.alpha, an.nu, an.model, an.fit.c0_error));
    for (double a : o.forecast_a)
      an.forecasts.push_back(nuc::forecast(a, R, an.alpha, an.nu, an.model, an.fit.c0_error));
  }
  return an;
}

AdhesiveAnalysis analyse_adhesive(const std::vector<DataPoint>& pts, const Options& o) {
  AdhesiveAnalysis an;
  // The automatic window follows each branch (series and R) from the crossover to an upturn.
  // The adhesive rows have no sphere (they carry contact.R's default), so a branch is one tau0:
  // the rows of two strengths interleave in a/b_core, and one falling branch made of both would
  // see an "upturn" wherever the stronger one's point lies a little above the weaker one's.
  std::map<double, int> series_of;
  for (const auto& p : pts)
    series_of.emplace(p.tau0, static_cast<int>(series_of.size()));
  an.points = scaling_points(pts, [&](const DataPoint& p) { return series_of.at(p.tau0); });
  an.fit_options = fit_options(an.law, o);
  an.fit = nuc::fit_regime_two(an.points, an.fit_options);
  if (!an.fit.valid)
    throw std::invalid_argument("no Regime II fit of the adhesive law: " + an.fit.reason +
                                " (give --window, or add points)");
  an.x_one = nuc::regime_one_crossover(an.law, an.fit.c0);
  // The condition's least-squares log-log slope over the window's points.
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  for (std::size_t i : an.fit.used) {
    const double x = std::log(an.points[i].a_over_bcore0);
    const double y = std::log(
        nuc::nucleation_condition(an.law, an.points[i].a_over_bcore0, an.fit.c0).mu_over_alpha);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double n = static_cast<double>(an.fit.used.size());
  an.condition_slope = (sxy - sx * sy / n) / (sxx - sx * sx / n);
  return an;
}

MixedAnalysis analyse_mixed(const std::vector<DataPoint>& pts, const LimitC0& hertz,
                            const LimitC0& adhesive) {
  MixedAnalysis an{.hertz = hertz, .adhesive = adhesive};
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  const bool with_h = std::isfinite(hertz.c0), with_a = std::isfinite(adhesive.c0);
  for (const auto& p : pts) {
    MixedPoint m;
    m.x_hertz = nuc::control_parameter(p.a, p.R, p.alpha, p.nu);
    m.x_adhesive = p.a * p.tau0 / p.G;  // d = 1: tables are in lattice spacings
    m.hertz_limit = with_h ? nuc::nucleation_condition(m.x_hertz, hertz.c0).mu_over_alpha : nan;
    m.adhesive_limit =
        with_a ? nuc::nucleation_condition(nuc::adhesive_law(), m.x_adhesive, adhesive.c0)
                     .mu_over_alpha
               : nan;
    m.mixed_with_c0_hertz =
        with_h ? nuc::mixed_nucleation_condition(m.x_adhesive, m.x_hertz, hertz.c0).mu_over_alpha
               : nan;
    m.mixed_with_c0_adhesive =
        with_a ? nuc::mixed_nucleation_condition(m.x_adhesive, m.x_hertz, adhesive.c0).mu_over_alpha
               : nan;
    an.points.push_back(m);
  }
  return an;
}

}  // namespace asperity::app::fit_scaling
