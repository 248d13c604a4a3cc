// fit_scaling's results: predictions.csv, summary.json and the report on the terminal, all from
// the Analysis.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "asperity/apps/common/cli.hpp"
#include "asperity/apps/common/output_files.hpp"
#include "fit_io.hpp"

namespace asperity::app::fit_scaling {

namespace fs = std::filesystem;
namespace nuc = asperity::nucleation;

void write_predictions(const fs::path& csv, const std::vector<DataPoint>& pts, const Analysis& an) {
  app::CsvTable table({"source", "model", "a", "R", "a_over_bcore0", "bcore0", "mu_over_alpha",
                       "in_window", "regime_two_law", "nucleation", "regime_three_central",
                       "regime_three_integrated", "regime_three_log_error", "predicted",
                       "data_over_predicted", "predicted_regime", "simulated_regime",
                       "law_extrapolated", "regime_undetermined"});
  std::vector<bool> in_window(pts.size(), false);
  for (std::size_t i : an.fit.used)
    in_window[i] = true;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto& p = pts[i];
    const nuc::PointComparison& c = an.comparisons[i];
    const nuc::Prediction& pr = c.prediction;
    table.add_row({p.source, p.model, p.a, p.R, p.x, c.beta, p.mu,
                   static_cast<long long>(in_window[i]), pr.law_two, pr.nucleation, pr.central,
                   pr.integrated, pr.integrated_log_error, pr.mu_over_alpha,
                   p.mu / pr.mu_over_alpha, nuc::to_string(pr.regime), nuc::to_string(c.simulated),
                   static_cast<long long>(c.law_extrapolated),
                   static_cast<long long>(c.undetermined)});
  }
  table.write(csv);
}

namespace {

nlohmann::json regime_two_json(const Analysis& an, const Options& o) {
  const nuc::RegimeTwoFit& fit = an.fit;
  nlohmann::json window_R = nlohmann::json::array();
  for (double R : an.window_R)
    window_R.push_back(R);
  return {{"law", "mu/alpha = 3 (2 c0)^(2/3) (a/b_core^0)^(-2/3)"},
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
          {"window_R", window_R},
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
          {"seed", o.seed}};
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
                      {"data_over_integrated", pts[i].mu / pr.integrated}});
    }
    out.push_back({{"R", u.R},
                   {"model", an.series_names[static_cast<std::size_t>(u.series)]},
                   {"a_range", {pts[u.points.front()].a, pts[u.points.back()].a}},
                   {"points", rows},
                   {"slope_dlnmu_dlna_data", u.slope_data},
                   {"slope_dlnmu_dlna_integrated", u.slope_integrated},
                   {"slope_dlnmu_dlna_predicted", u.slope_predicted},
                   {"same_sign_of_slope", (u.slope_data > 0) == (u.slope_integrated > 0)},
                   {"worst_factor_data_vs_integrated", u.worst_factor},
                   {"within_factor_2", u.worst_factor <= 2.0}});
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
                {"correlation", f3.correlation},
                {"window_bcore0", {f3.beta_min, f3.beta_max}},
                {"dof", f3.dof},
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
                             {"regime_undetermined", c.undetermined}});
  }
  const nuc::MapAgreement& m = an.agreement;
  return {{"points", pts.size()},
          {"agree", m.agree},
          {"all_agree", m.agree == pts.size()},
          {"points_law_in_window", m.in_law},
          {"agree_law_in_window", m.agree_in_law},
          {"undetermined", m.undetermined},
          {"contradictions", m.contradictions},
          {"disagreements", disagreements},
          {"rule",
           "III: rising branch (simulated) / Regime III law above the nucleation condition "
           "(predicted); else I or II by the nearer asymptote"}};
}

}  // namespace

void write_summary(const fs::path& json, const Loaded& data, const LawSource& law,
                   const Analysis& an, const Options& o, const std::vector<fs::path>& figures,
                   double wall_s) {
  nlohmann::json figure_names = nlohmann::json::array();
  for (const auto& f : figures)
    figure_names.push_back(f.filename().string());
  const double x_one = an.x_one, x_one_two = an.x_one_two, c0 = an.fit.c0;
  app::write_json(
      json, {{"tool", "fit_scaling"},
             {"inputs",
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
             {"regime_three_upturns", upturns_json(data.points, an)},
             {"regime_three_fit_to_friction", fit_three_json(an.fit_three)},
             {"regime_map", regime_map_json(data.points, an)},
             {"predictions", "predictions.csv"},
             {"figures", figure_names},
             {"run", {{"wall_s", wall_s}, {"provenance", app::provenance_json()}}}});
}

void print_report(const fs::path& dir, const LawSource& law, const Analysis& an, const Options& o,
                  const std::vector<fs::path>& figures) {
  const nuc::RegimeTwoFit& fit = an.fit;
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
                 100.0 * fit.max_relative_deviation, 100.0 * an.fit_options.automatic.max_deviation,
                 fit.window_automatic ? " even with the window trimmed to its minimum" : "");
  if (fit.free_slope_error > 0.0)
    std::printf(
        "  free log-log slope %.3f +- %.3f (law: -2/3); c0 lower / upper half of the "
        "window %.4f / %.4f\n",
        fit.free_slope, fit.free_slope_error, fit.c0_lower_half, fit.c0_upper_half);
  std::printf("Peierls law: k1 = %.4g +- %.2g, k2 = %.4g +- %.2g; f_P = %g\n", law.law.k1,
              law.law.k1_error, law.law.k2, law.law.k2_error, o.f_P);
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
  for (const nuc::Upturn& u : an.upturns) {
    std::printf(
        "upturn at R = %g d: slope dln(mu)/dln(a) data %.3f, prediction %.3f; worst "
        "factor %.3g\n",
        u.R, u.slope_data, u.slope_integrated, u.worst_factor);
  }
  const nuc::MapAgreement& m = an.agreement;
  std::printf(
      "regime map: %zu of %zu points in their simulated regime (%zu of %zu where the "
      "Peierls law is used within its window); %zu disagree where the prediction decides "
      "(%zu points within 2 errors of a boundary)\n",
      m.agree, m.points, m.agree_in_law, m.in_law, m.contradictions, m.undetermined);
  std::printf("results: %s\n", fs::absolute(dir / "summary.json").c_str());
  for (const auto& f : figures)
    std::printf("figure:  %s\n", fs::absolute(f).c_str());
}

}  // namespace asperity::app::fit_scaling
