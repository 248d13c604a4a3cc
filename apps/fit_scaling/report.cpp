// fit_scaling's results: predictions.csv, summary.json and the report on the terminal, all from
// the Analysis.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/settings_cli.hpp"
#include "fit_io.hpp"

namespace asperity::app::fit_scaling {

namespace fs = std::filesystem;
namespace nuc = asperity::nucleation;

void write_predictions(const fs::path& csv, const std::vector<DataPoint>& pts, const Analysis& an) {
  app::CsvTable table({"source",
                       "model",
                       "a",
                       "R",
                       "a_over_bcore0",
                       "bcore0",
                       "mu_over_alpha",
                       "in_window",
                       "regime_two_law",
                       "nucleation",
                       "regime_three_central",
                       "regime_three_integrated",
                       "regime_three_log_error",
                       "predicted",
                       "data_over_predicted",
                       "predicted_regime",
                       "simulated_regime",
                       "law_extrapolated",
                       "regime_undetermined",
                       "mu_is_lower_bound",
                       "simulated_undetermined"});
  std::vector<bool> in_window(pts.size(), false);
  for (std::size_t i : an.fit.used)
    in_window[i] = true;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto& p = pts[i];
    const nuc::PointComparison& c = an.comparisons[i];
    const nuc::Prediction& pr = c.prediction;
    table.add_row({p.source,
                   p.model,
                   p.a,
                   p.R,
                   p.x,
                   c.beta,
                   p.mu,
                   static_cast<long long>(in_window[i]),
                   pr.law_two,
                   pr.nucleation,
                   pr.central,
                   pr.integrated,
                   pr.integrated_log_error,
                   pr.mu_over_alpha,
                   p.mu / pr.mu_over_alpha,
                   nuc::to_string(pr.regime),
                   nuc::to_string(c.simulated),
                   static_cast<long long>(c.law_extrapolated),
                   static_cast<long long>(c.undetermined),
                   static_cast<long long>(c.lower_bound),
                   static_cast<long long>(c.simulated_undetermined)});
  }
  table.write(csv);
}

void write_forecast(const fs::path& csv, const Analysis& an) {
  app::CsvTable table({"a", "R", "a_over_bcore0", "bcore0", "nucleation", "regime_three_integrated",
                       "regime_three_log_error", "predicted", "predicted_error",
                       "predicted_error_complete", "log_slope", "predicted_regime",
                       "law_extrapolated", "regime_undetermined"});
  for (const nuc::Forecast& f : an.forecasts) {
    const nuc::Prediction& pr = f.prediction;
    table.add_row({f.a, f.R, f.a_over_bcore0, f.beta, pr.nucleation, pr.integrated,
                   pr.integrated_log_error, pr.mu_over_alpha, f.mu_over_alpha_error,
                   static_cast<long long>(f.error_complete), f.log_slope, nuc::to_string(pr.regime),
                   static_cast<long long>(f.law_extrapolated),
                   static_cast<long long>(f.undetermined)});
  }
  table.write(csv);
}

void write_adhesive_predictions(const fs::path& csv, const std::vector<DataPoint>& pts,
                                const AdhesiveAnalysis& an) {
  app::CsvTable table({"source", "a", "R", "tau0", "a_over_bcore0", "bcore", "tau_fric_over_tau0",
                       "in_window", "regime_two_law", "nucleation", "data_over_law",
                       "data_over_nucleation", "c0_of_point"});
  std::vector<bool> in_window(pts.size(), false);
  for (std::size_t i : an.fit.used)
    in_window[i] = true;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto& p = pts[i];
    const double law = nuc::regime_two_law(an.law, p.x, an.fit.c0);
    const double cond = nuc::nucleation_condition(an.law, p.x, an.fit.c0).mu_over_alpha;
    table.add_row({p.source, p.a, p.R, p.tau0, p.x, p.a / p.x, p.mu,
                   static_cast<long long>(in_window[i]), law, cond, p.mu / law, p.mu / cond,
                   nuc::c0_of_point(an.law, p.x, p.mu)});
  }
  table.write(csv);
}

void write_mixed_predictions(const fs::path& csv, const std::vector<DataPoint>& pts,
                             const MixedAnalysis& an) {
  app::CsvTable table({"source", "a", "R", "alpha", "tau0", "a_over_bcore0", "a_over_bcore0_hertz",
                       "a_over_bcore0_adhesive", "friction_over_regime_one", "mu_over_alpha",
                       "hertz_limit", "mu_over_alpha_over_hertz_limit", "tau_fric_over_tau0",
                       "adhesive_limit", "tau_fric_over_tau0_over_adhesive_limit",
                       "mixed_condition_c0_hertz", "mixed_condition_c0_adhesive"});
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto& p = pts[i];
    const MixedPoint& m = an.points[i];
    table.add_row({p.source, p.a, p.R, p.alpha, p.tau0, p.x, m.x_hertz, m.x_adhesive, p.mu,
                   p.mu_over_alpha, m.hertz_limit, p.mu_over_alpha / m.hertz_limit,
                   p.tau_fric_over_tau0, m.adhesive_limit, p.tau_fric_over_tau0 / m.adhesive_limit,
                   m.mixed_with_c0_hertz, m.mixed_with_c0_adhesive});
  }
  table.write(csv);
}

namespace {

// Undefined values as null, never NaN.
nlohmann::json num(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

// The fit of c0 of either law (the Hertz entry keeps its keys and their order).
nlohmann::json fit_json(const nuc::RegimeTwoFit& fit, const nuc::RegimeTwoLaw& law,
                        const Options& o) {
  return {{"law", law.formula},
          {"c0", fit.c0},
          {"c0_error", fit.c0_error},
          {"error_kind",
           "bootstrap over points of m = (2/3) ln(2 c0), x sqrt(n/(n-1)) x t_{n-1}(Phi(2))/2, "
           "dc0 = 1.5 c0 dm: +-2 errors is the 95.45% interval"},
          {"c0_se_bootstrap", fit.c0_se_bootstrap},
          {"c0_interval_2_errors", {fit.c0_lo, fit.c0_hi}},
          {"prefactor", fit.prefactor},
          {"prefactor_error", fit.prefactor_error},
          {"window_a_over_bcore0", {fit.window_lo, fit.window_hi}},
          {"window_automatic", fit.window_automatic},
          {"points", fit.points},
          {"dof", fit.dof},
          {"t_factor", fit.t_factor},
          {"points_trimmed", fit.trimmed},
          {"max_relative_deviation", fit.max_relative_deviation},
          {"within_max_deviation", fit.within_max_deviation},
          {"rms_log_residual", fit.rms_log_residual},
          {"free_slope", fit.free_slope},
          {"free_slope_error", fit.free_slope_error},
          {"law_slope", -law.exponent},
          {"c0_lower_half", fit.c0_lower_half},
          {"c0_upper_half", fit.c0_upper_half},
          {"c0_window_spread", fit.c0_window_spread},
          {"bootstrap_samples", o.bootstrap},
          {"seed", o.seed}};
}

nlohmann::json adhesive_json(const AdhesiveAnalysis& an, const Options& o, std::size_t points) {
  nlohmann::json fit = fit_json(an.fit, an.law, o);
  fit["condition_slope_over_window"] = an.condition_slope;
  fit["condition_slope_note"] =
      "log-log slope of the nucleation condition 2 sqrt(q (2 - q)), q = c0/(a/b_core), at the "
      "fitted c0 over the window's points: the law's -1/2 with its finite-size correction";
  return {{"envelope", "adhesive: tau_max = tau0 for r < a, no load"},
          {"quantity", "tau_fric/tau0, tau_fric = Fx/A at the peak, A = N_c d^2"},
          {"points", points},
          {"regime_two", fit},
          {"regime_one_crossover",
           {{"a_over_bcore0_condition_reaches_1", an.x_one},
            {"a_over_bcore0_condition_reaches_1_error", an.x_one * an.fit.c0_error / an.fit.c0},
            {"condition", "tau_fric/tau0 = min(1, 2 sqrt(q (2 - q))), q = c0/(a/b_core)"}}},
          {"predictions", "adhesive_predictions.csv"}};
}

nlohmann::json mixed_json(const std::vector<DataPoint>& pts, const MixedAnalysis& an) {
  const auto limit = [](const LimitC0& l, const char* missing) {
    if (l.source.empty()) return nlohmann::json{{"c0", nullptr}, {"note", missing}};
    return nlohmann::json{{"c0", l.c0}, {"c0_error", num(l.error)}, {"source", l.source}};
  };
  nlohmann::json rows = nlohmann::json::array();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto& p = pts[i];
    const MixedPoint& m = an.points[i];
    rows.push_back({{"a", p.a},
                    {"R", p.R},
                    {"alpha", p.alpha},
                    {"tau0", p.tau0},
                    {"a_over_bcore0", p.x},
                    {"a_over_bcore0_hertz", m.x_hertz},
                    {"a_over_bcore0_adhesive", m.x_adhesive},
                    {"friction_over_regime_one", p.mu},
                    {"mu_over_alpha", num(p.mu_over_alpha)},
                    {"hertz_limit", num(m.hertz_limit)},
                    {"tau_fric_over_tau0", num(p.tau_fric_over_tau0)},
                    {"adhesive_limit", num(m.adhesive_limit)},
                    {"mixed_condition_c0_hertz", num(m.mixed_with_c0_hertz)},
                    {"mixed_condition_c0_adhesive", num(m.mixed_with_c0_adhesive)}});
  }
  return {{"envelope", "mixed: tau_max = tau0 + alpha p inside the Hertz contact"},
          {"quantity",
           "Fx/(alpha Fz + tau0 A) at the peak; against the Hertz limit mu/alpha, against the "
           "adhesive limit tau_fric/tau0"},
          {"c0_hertz", limit(an.hertz, "no Hertz table and no --c0-hertz")},
          {"c0_adhesive", limit(an.adhesive, "no adhesive table and no --c0-adhesive")},
          {"limits",
           "hertz_limit: mu/alpha of the Hertz nucleation condition at a/b_core^0 of alpha p "
           "alone; adhesive_limit: tau_fric/tau0 of the adhesive one at a tau0/(d G); "
           "mixed_condition: Fx/F_I of the condition under tau0 + alpha p, with each c0"},
          {"points", rows},
          {"predictions", "mixed_predictions.csv"}};
}

nlohmann::json regime_two_json(const Analysis& an, const Options& o) {
  nlohmann::json j = fit_json(an.fit, nuc::hertz_law(), o);
  nlohmann::json window_R = nlohmann::json::array();
  for (double R : an.window_R)
    window_R.push_back(R);
  j["window_R"] = window_R;
  nlohmann::json rising = nlohmann::json::array();
  for (std::size_t i : an.window_rising) {
    const nuc::ScalingPoint& p = an.points[i];
    rising.push_back({{"a", p.a}, {"R", p.R}, {"mu_over_alpha", p.mu_over_alpha}});
  }
  j["window_regime_three"] = rising;
  return j;
}

// II -> III per R of the data, with the Regime I contact radius at that R.
nlohmann::json crossovers_json(const Analysis& an) {
  nlohmann::json out = nlohmann::json::array();
  for (const nuc::CrossoverEstimate& e : an.crossovers) {
    const nuc::Crossover& cr = e.crossover;
    nlohmann::json j = {{"R", e.R}, {"found", cr.found}};
    if (cr.found) {
      const double bcore0 = cr.a / cr.a_over_bcore0;
      j.update({{"a_error", e.a_error},
                {"a_error_complete", e.a_error_complete},
                {"a", cr.a},
                {"a_over_bcore0", cr.a_over_bcore0},
                {"mu_over_alpha", cr.mu_over_alpha},
                {"a_below_0.1_R", cr.small_slope},
                {"bcore0", bcore0},
                {"law_extrapolated", nuc::law_extrapolated(bcore0, an.model.law)}});
    }
    j["regime_one_a"] = nuc::contact_radius(an.x_one, e.R, an.alpha, an.nu);
    out.push_back(j);
  }
  return out;
}

// The forecast: the crossover at each of its R, then its table's name (the rows are in it).
nlohmann::json forecast_json(const Analysis& an) {
  if (an.forecasts.empty()) return nullptr;
  nlohmann::json crossovers = nlohmann::json::array();
  for (const nuc::CrossoverEstimate& e : an.forecast_crossovers) {
    nlohmann::json j = {{"R", e.R}, {"found", e.crossover.found}};
    if (e.crossover.found)
      j.update({{"a", e.crossover.a},
                {"a_error", e.a_error},
                {"a_error_complete", e.a_error_complete},
                {"mu_over_alpha", e.crossover.mu_over_alpha}});
    crossovers.push_back(j);
  }
  return {{"crossovers_two_three", crossovers},
          {"points", an.forecasts.size()},
          {"table", "forecast.csv"}};
}

// The Regime III upturns against the prediction, point by point.
nlohmann::json upturns_json(const std::vector<DataPoint>& pts, const Analysis& an) {
  nlohmann::json out = nlohmann::json::array();
  for (const nuc::Upturn& u : an.upturns) {
    nlohmann::json rows = nlohmann::json::array();
    for (std::size_t i : u.points) {
      const nuc::Prediction& pr = an.comparisons[i].prediction;
      rows.push_back({{"a", pts[i].a},
                      {"a_over_bcore0", pts[i].x},
                      {"mu_over_alpha", pts[i].mu},
                      {"regime_three_integrated", pr.integrated},
                      {"regime_three_central", pr.central},
                      {"predicted", pr.mu_over_alpha},
                      {"data_over_integrated", pts[i].mu / pr.integrated},
                      {"mu_is_lower_bound", pts[i].lower_bound}});
    }
    out.push_back(
        {{"R", u.R},
         {"model", an.series_names[static_cast<std::size_t>(u.series)]},
         {"a_range", {pts[u.points.front()].a, pts[u.points.back()].a}},
         {"points", rows},
         {"slope_dlnmu_dlna_data", u.slope_data},
         {"slope_dlnmu_dlna_integrated", u.slope_integrated},
         {"slope_dlnmu_dlna_predicted", u.slope_predicted},
         // null where the bounds leave the data's sign open
         {"same_sign_of_slope", u.slope_data_sign_known()
                                    ? nlohmann::json((u.slope_data > 0) == (u.slope_integrated > 0))
                                    : nlohmann::json(nullptr)},
         {"worst_factor_data_vs_integrated", u.worst_factor},
         {"within_factor_2", u.worst_factor <= 2.0},
         {"lower_bounds", u.lower_bounds},
         {"slope_data_is_lower_bound", u.slope_data_is_lower_bound}});
  }
  return out;
}

nlohmann::json fit_three_json(const nuc::RegimeThreeFrictionFit& f) {
  nlohmann::json out = {{"points", f.points}};
  if (!f.attempted) {
    out["reason"] = f.reason;
    return out;
  }
  const nuc::RegimeThreeFit& f3 = f.fit;
  out["form"] = "integrated";
  out["valid"] = f3.valid;
  if (f3.valid) {
    out.update({{"k1", f3.law.k1},
                {"k1_error", f3.law.k1_error},
                {"k2", f3.law.k2},
                {"k2_error", f3.law.k2_error},
                {"k1_se", f3.k1_se},
                {"k2_se", f3.k2_se},
                {"correlation", f3.correlation},
                {"window_bcore0", {f3.beta_min, f3.beta_max}},
                {"dof", f3.dof},
                {"t_factor", f3.t_factor},
                {"rms_log_residual", f3.rms_log_residual}});
  } else {
    out["reason"] = f3.reason;
  }
  return out;
}

nlohmann::json regime_map_json(const std::vector<DataPoint>& pts, const Analysis& an) {
  nlohmann::json disagreements = nlohmann::json::array();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto& p = pts[i];
    const nuc::PointComparison& c = an.comparisons[i];
    if (c.agrees()) continue;
    disagreements.push_back({{"a", p.a},
                             {"R", p.R},
                             {"a_over_bcore0", p.x},
                             {"mu_over_alpha", p.mu},
                             {"predicted", nuc::to_string(c.prediction.regime)},
                             {"simulated", nuc::to_string(c.simulated)},
                             {"bcore0", c.beta},
                             {"law_extrapolated", c.law_extrapolated},
                             {"regime_undetermined", c.undetermined},
                             {"mu_is_lower_bound", c.lower_bound},
                             {"simulated_undetermined", c.simulated_undetermined}});
  }
  const nuc::MapAgreement& m = an.agreement;
  return {{"points", pts.size()},
          {"agree", m.agree},
          {"all_agree", m.agree == pts.size()},
          {"points_law_in_window", m.in_law},
          {"agree_law_in_window", m.agree_in_law},
          {"undetermined", m.undetermined},
          {"simulated_undetermined", m.simulated_undetermined},
          {"lower_bounds",
           std::count_if(pts.begin(), pts.end(), [](const DataPoint& p) { return p.lower_bound; })},
          {"contradictions", m.contradictions},
          {"disagreements", disagreements},
          {"rule",
           "III: rising branch (simulated; a lower bound rising past counts) / Regime III law "
           "above the nucleation condition (predicted); else I or II by the nearer asymptote"}};
}

}  // namespace

void write_summary(const fs::path& json, const Loaded& data, const Results& res, const Options& o,
                   const std::vector<fs::path>& figures, double wall_s) {
  nlohmann::json figure_names = nlohmann::json::array();
  for (const auto& f : figures)
    figure_names.push_back(f.filename().string());
  nlohmann::json out = {{"tool", "fit_scaling"}};
  if (res.hertz) {
    const Analysis& an = *res.hertz;
    const LawSource& law = *res.law;
    const std::vector<DataPoint>& pts = res.points->hertz;
    const double x_one = an.x_one, x_one_two = an.x_one_two, c0 = an.fit.c0;
    out.update({{"inputs",
                 {{"sweeps", data.sources},
                  {"alpha", an.alpha},
                  {"alpha_rule", an.map_alpha.rule},
                  {"alpha_range", {an.map_alpha.min, an.map_alpha.max}},
                  {"nu", an.nu}}},
                {"regime_two", regime_two_json(an, o)},
                {"regime_one_crossover",
                 {{"a_over_bcore0_condition_reaches_1", x_one},
                  {"a_over_bcore0_condition_reaches_1_error", x_one * an.fit.c0_error / c0},
                  {"a_over_bcore0_boundary", x_one_two},
                  {"a_over_bcore0_boundary_error", x_one_two * an.fit.c0_error / c0},
                  {"boundary_rule", "nearer asymptote in ln(mu/alpha): 1 or the Regime II law"}}},
                {"peierls", law.json},
                {"f_P", o.f_P},
                {"crossovers_two_three", crossovers_json(an)},
                {"regime_three_upturns", upturns_json(pts, an)},
                {"regime_three_fit_to_friction", fit_three_json(an.fit_three)},
                {"regime_map", regime_map_json(pts, an)},
                {"predictions", "predictions.csv"}});
    if (!an.forecasts.empty()) out["forecast"] = forecast_json(an);
  } else {
    out["inputs"] = {{"sweeps", data.sources}};
  }
  if (res.adhesive) out["adhesive"] = adhesive_json(*res.adhesive, o, res.points->adhesive.size());
  if (res.mixed) out["mixed"] = mixed_json(res.points->mixed, *res.mixed);
  // Every setting as the run used it, by its key (Options::settings(); `fit_scaling
  // --list-settings`): the flags given and the defaults.
  out["settings"] = app::settings_echo(o, Options::settings());
  out["envelopes"] = {{"hertz", res.points->hertz.size()},
                      {"adhesive", res.points->adhesive.size()},
                      {"mixed", res.points->mixed.size()}};
  out["figures"] = figure_names;
  out["run"] = {{"wall_s", wall_s}, {"provenance", app::provenance_json()}};
  app::write_json(json, out);
}

namespace {

void print_hertz(const LawSource& law, const Analysis& an, const Options& o) {
  const nuc::RegimeTwoFit& fit = an.fit;
  std::printf("c0 = %.4f +- %.4f (a/b_core^0 in [%g, %g], %zu points%s; fit within %.1f%%)\n",
              fit.c0, fit.c0_error, fit.window_lo, fit.window_hi, fit.points,
              fit.window_automatic
                  ? (", automatic window, " + std::to_string(fit.trimmed) + " trimmed").c_str()
                  : "",
              100.0 * fit.max_relative_deviation);
  if (!an.window_rising.empty())
    std::fprintf(stderr,
                 "fit_scaling: warning: %zu point%s of the window (--window) lie%s on a rising "
                 "branch, simulated Regime III: the Regime II law does not hold there "
                 "(summary.json: regime_two.window_regime_three)\n",
                 an.window_rising.size(), an.window_rising.size() == 1 ? "" : "s",
                 an.window_rising.size() == 1 ? "s" : "");
  if (!fit.within_max_deviation)
    std::fprintf(stderr,
                 "fit_scaling: warning: the Regime II law misses a point of the window by "
                 "%.1f%%, more than %.0f%%%s: the data do not follow the law there\n",
                 100.0 * fit.max_relative_deviation, 100.0 * an.fit_options.automatic.max_deviation,
                 fit.window_automatic ? " even with the window trimmed to its minimum" : "");
  if (fit.free_slope_error > 0.0)
    std::printf(
        "  free log-log slope %.3f +- %.3f (law: -2/3); c0 lower / upper half of the "
        "window %.4f / %.4f\n",
        fit.free_slope, fit.free_slope_error, fit.c0_lower_half, fit.c0_upper_half);
  // The reported errors, on c0's footing (the scan's plain standard errors times the t factor).
  std::printf(
      "Peierls law: k1 = %.4g +- %.2g, k2 = %.4g +- %.2g (reported errors: plain x %.3g); "
      "f_P = %g\n",
      an.model.law.k1, an.model.law.k1_error, an.model.law.k2, an.model.law.k2_error,
      law.error_factor, o.f_P);
  std::printf("Regime I boundary: a/b_core^0 = %.3g (condition reaches mu = alpha at %.3g)\n",
              an.x_one_two, an.x_one);
  for (const nuc::CrossoverEstimate& e : an.crossovers) {
    const nuc::Crossover& cr = e.crossover;
    if (cr.found) {
      const double bcore0 = cr.a / cr.a_over_bcore0;
      std::printf(
          "II -> III crossover at R = %g d: a = %.4g +- %.2g d (a/b_core^0 = %.4g, "
          "b_core^0 = %.3g d%s, mu/alpha = %.4g)\n",
          e.R, cr.a, e.a_error, cr.a_over_bcore0, bcore0,
          nuc::law_extrapolated(bcore0, an.model.law) ? ", below the Peierls fit window" : "",
          cr.mu_over_alpha);
    }
  }
  // The forecast, R by R: where the upturn is predicted, then each contact.
  std::size_t next = 0;
  for (const nuc::CrossoverEstimate& e : an.forecast_crossovers) {
    if (e.crossover.found) {
      std::printf(
          "forecast at R = %g d: II -> III crossover at a = %.4g +- %.2g d, mu/alpha = %.4g\n", e.R,
          e.crossover.a, e.a_error, e.crossover.mu_over_alpha);
    } else {
      std::printf("forecast at R = %g d: no II -> III crossover\n", e.R);
    }
    for (; next < an.forecasts.size() && an.forecasts[next].R == e.R; ++next) {
      const nuc::Forecast& f = an.forecasts[next];
      std::printf("  a = %g d: mu/alpha = %.4g +- %.2g%s, dln(mu)/dln(a) = %+.3f, Regime %s%s%s\n",
                  f.a, f.prediction.mu_over_alpha, f.mu_over_alpha_error,
                  f.error_complete ? "" : " (error a lower bound)", f.log_slope,
                  nuc::to_string(f.prediction.regime).c_str(),
                  f.undetermined ? " (undetermined)" : "",
                  f.law_extrapolated ? ", law extrapolated" : "");
    }
  }
  for (const nuc::Upturn& u : an.upturns) {
    std::printf(
        "upturn at R = %g d: slope dln(mu)/dln(a) data %s%.3f, prediction %.3f; worst "
        "factor %.3g%s\n",
        u.R, u.slope_data_is_lower_bound ? ">= " : "", u.slope_data, u.slope_integrated,
        u.worst_factor, u.lower_bounds ? " (with lower bounds)" : "");
  }
  const nuc::MapAgreement& m = an.agreement;
  std::printf(
      "regime map: %zu of %zu points in their simulated regime (%zu of %zu where the "
      "Peierls law is used within its window); %zu disagree where the prediction decides "
      "(%zu points within 2 errors of a boundary, %zu lower bounds of unknown regime)\n",
      m.agree, m.points, m.agree_in_law, m.in_law, m.contradictions, m.undetermined,
      m.simulated_undetermined);
}

void print_adhesive(const AdhesiveAnalysis& an) {
  const nuc::RegimeTwoFit& fit = an.fit;
  std::printf(
      "adhesive: c0 = %.4f +- %.4f (tau_fric/tau0 = 2 (a/(2 c0 b_core))^(-1/2); a/b_core in "
      "[%g, %g], %zu points%s; fit within %.1f%%)\n",
      fit.c0, fit.c0_error, fit.window_lo, fit.window_hi, fit.points,
      fit.window_automatic
          ? (", automatic window, " + std::to_string(fit.trimmed) + " trimmed").c_str()
          : "",
      100.0 * fit.max_relative_deviation);
  if (!fit.within_max_deviation)
    std::fprintf(stderr,
                 "fit_scaling: warning: the adhesive law misses a point of the window by %.1f%%, "
                 "more than %.0f%%\n",
                 100.0 * fit.max_relative_deviation,
                 100.0 * an.fit_options.automatic.max_deviation);
  if (fit.free_slope_error > 0.0)
    std::printf(
        "  free log-log slope of tau_fric %.3f +- %.3f (law: -1/2; the nucleation condition's "
        "over the same points: %.3f); c0 lower / upper half of the window %.4f / %.4f\n",
        fit.free_slope, fit.free_slope_error, an.condition_slope, fit.c0_lower_half,
        fit.c0_upper_half);
  std::printf("  Regime I: the condition reaches tau_fric = tau0 at a/b_core = %.3g\n", an.x_one);
}

void print_mixed(const std::vector<DataPoint>& pts, const MixedAnalysis& an) {
  const auto source = [](const LimitC0& l) {
    return l.source.empty() ? std::string("none") : fmt("%.4f", l.c0) + " (" + l.source + ")";
  };
  std::printf("mixed: %zu points; c0 of the Hertz law %s, of the adhesive law %s\n", pts.size(),
              source(an.hertz).c_str(), source(an.adhesive).c_str());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto& p = pts[i];
    const MixedPoint& m = an.points[i];
    std::printf(
        "  a = %g d, R = %g d, tau0 = %g: Fx/F_I = %.4f; mu/alpha %.4f against the Hertz limit "
        "%.4f (a/b_core^0 %.3g); tau_fric/tau0 %.4f against the adhesive limit %.4f (a/b_core "
        "%.3g); mixed condition %.4f .. %.4f\n",
        p.a, p.R, p.tau0, p.mu, p.mu_over_alpha, m.hertz_limit, m.x_hertz, p.tau_fric_over_tau0,
        m.adhesive_limit, m.x_adhesive, m.mixed_with_c0_hertz, m.mixed_with_c0_adhesive);
  }
}

}  // namespace

void print_report(const fs::path& dir, const Results& res, const Options& o,
                  const std::vector<fs::path>& figures) {
  if (res.hertz) print_hertz(*res.law, *res.hertz, o);
  if (res.adhesive) print_adhesive(*res.adhesive);
  if (res.mixed) print_mixed(res.points->mixed, *res.mixed);
  std::printf("results: %s\n", fs::absolute(dir / "summary.json").c_str());
  for (const auto& f : figures)
    std::printf("figure:  %s\n", fs::absolute(f).c_str());
}

}  // namespace asperity::app::fit_scaling
