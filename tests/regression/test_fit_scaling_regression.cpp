// Regression tier: fit_scaling on the committed sweeps (issue 9, acceptances 2-4).
// - data/reference/sweep_R535.csv (friction_sweep, default sweep scene, R = 535 d): the Regime II
//   fit gives the stored c0 and its line passes within 10% of every point of its window
//   (recomputed here from predictions.csv, not taken from the tool's own statistic);
// - data/reference/regime3_R1700.csv (R = 1700 d, a = 250 d up) and regime3_R100.csv (R = 100 d,
//   a = 30 ... 50 d): the prediction against the large contacts, and what they show (no upturn
//   in their range);
// - data/reference/regime3_R40.csv (R = 40 d, a = 12 ... 36 d, slid until the peak holds) and
//   regime3_R40_fill.csv (a = 22, 26, 30 d between them): the Regime III upturn, against the
//   prediction built from the project's Peierls scan (acceptance 3);
// - the regime map puts every committed point in its simulated regime, and every simulated
//   Regime III point is predicted so (where the Peierls law is used within its fitted window
//   every point is Regime II: that subset tests the nucleation condition, not the law).
// The Peierls law comes from the project's own peierls_scan (default scene, run by the fixture).
// The R = 1700 d points are tested out of sample, against c0 of the R = 535 d fit alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "asperity/apps/common/output_files.hpp"
#include "asperity/nucleation/regime_three.hpp"
#include "asperity/nucleation/statistics.hpp"

using asperity::app::CsvTable;

namespace {

nlohmann::json summary(const std::string& dir = FIT_DIR) {
  std::ifstream in(dir + "/summary.json");
  return nlohmann::json::parse(in);
}

// The nucleation condition re-derived (regime_two.hpp): (1 - x) sqrt(1 - x^2) = c0 / (a/b_core^0),
// mu/alpha = min(1, 3 (1 - x^2)); bisection to 1e-14.
double nucleation(double a_over_bcore0, double c0) {
  const double q = c0 / a_over_bcore0;
  if (q >= 1.0) return 1.0;
  double lo = 0.0, hi = 1.0;
  while (hi - lo > 1e-14) {
    const double x = 0.5 * (lo + hi);
    ((1.0 - x) * std::sqrt(1.0 - x * x) > q ? lo : hi) = x;
  }
  return std::min(1.0, 3.0 * (1.0 - lo * lo));
}

// Least-squares slope of y against x.
double log_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += x[i] / static_cast<double>(x.size());
    my += y[i] / static_cast<double>(x.size());
  }
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  return sxy / sxx;
}

}  // namespace

TEST(FitScalingRegression, RegimeTwoFitOnTheR535Sweep) {
  const auto s = summary(FIT_R535_DIR);
  const auto& r2 = s["regime_two"];
  // Stored value (the table is committed and the bootstrap seeded: only a change of the fit or
  // its window moves it).
  EXPECT_NEAR(r2["c0"].get<double>(), C0_REFERENCE, 1e-3 * C0_REFERENCE);
  EXPECT_GT(r2["c0_error"].get<double>(), 0.0);
  EXPECT_TRUE(r2["window_automatic"].get<bool>());
  EXPECT_GE(r2["points"].get<int>(), 3);
  const double c0 = r2["c0"].get<double>();
  const CsvTable t = CsvTable::read(FIT_R535_DIR "/predictions.csv");
  int in_window = 0;
  for (std::size_t i = 0; i < t.rows(); ++i) {
    if (t.integer(i, "in_window") == 0) continue;
    ++in_window;
    const double x = t.number(i, "a_over_bcore0"), mu = t.number(i, "mu_over_alpha");
    const double law = 3.0 * std::pow(2.0 * c0, 2.0 / 3.0) * std::pow(x, -2.0 / 3.0);
    EXPECT_LE(std::abs(mu / law - 1.0), 0.10) << "a/b_core^0 = " << x;  // acceptance 2
    EXPECT_EQ(t.number(i, "R"), 535.0);
  }
  EXPECT_EQ(in_window, r2["points"].get<int>());
  // The automatic window trims points until the line is within 10% of the rest, so the check
  // above holds by construction unless trimming went far. Not so over a range fixed in advance,
  // issue 3's Regime II range a/b_core^0 in [10, 60]: every point of the sweep there, in the
  // window or not, must be within 10% of the line.
  int fixed_range = 0;
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const double x = t.number(i, "a_over_bcore0"), mu = t.number(i, "mu_over_alpha");
    if (x < 10.0 || x > 60.0) continue;
    ++fixed_range;
    const double law = 3.0 * std::pow(2.0 * c0, 2.0 / 3.0) * std::pow(x, -2.0 / 3.0);
    EXPECT_LE(std::abs(mu / law - 1.0), 0.10) << "a/b_core^0 = " << x;
  }
  EXPECT_GE(fixed_range, 3);
  std::printf("R = 535 d fit: c0 = %.4f, %d points in the window, %d trimmed, free slope %.3f\n",
              c0, in_window, r2["points_trimmed"].get<int>(), r2["free_slope"].get<double>());
}

// Acceptance 4 of issue 9 and the third of issue 23: every committed point whose simulated
// regime the data decide is predicted in it. Inside the Peierls fit window (2..6 d of the centre
// core width b_core^0) the Regime III law is small against nucleation, so the check that tests
// the law is that every point the simulation puts in Regime III (friction rising with load) is
// predicted in Regime III. The check is deliberately strict where the prediction cannot decide
// (a point within 2 errors of a boundary): until 2026-11-27 one such point, R = 40 d, a = 28 d,
// disagreed, and it was let through; sampling the branch at a = 22, 26, 30 d showed its lowest
// point is a = 26 d, not 24 d, and a = 28 d rises 4.5% past it
// (data/reference/regime3_R40_fill.md). A table that breaks this again must be explained in its
// note (a point 1-3% above its branch's lowest is classified by how the minimum is sampled), not
// met by moving the 2% rise tolerance (docs/nucleation.md).
namespace {

// Every point of the fit in `dir` whose simulated regime the data decide is predicted in it;
// counts of the points within the law's window, the simulated Regime III points and those the
// prediction or the data cannot decide.
void expect_map_reproduces_simulated_regimes(const std::string& dir) {
  const auto s = summary(dir);
  const auto& map = s["regime_map"];
  const CsvTable t = CsvTable::read(dir + "/predictions.csv");
  EXPECT_EQ(static_cast<std::size_t>(map["points"].get<int>()), t.rows());
  int in_law = 0, simulated_three = 0;
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const bool same = t.text(i, "predicted_regime") == t.text(i, "simulated_regime");
    if (t.text(i, "simulated_regime") == "III") {
      ++simulated_three;
      EXPECT_TRUE(same) << "simulated III: a = " << t.number(i, "a")
                        << ", R = " << t.number(i, "R");
    }
    if (t.integer(i, "law_extrapolated") == 0) {
      ++in_law;
      EXPECT_TRUE(same) << "a = " << t.number(i, "a") << ", R = " << t.number(i, "R");
    }
  }
  EXPECT_GE(in_law, 7);
  EXPECT_GE(simulated_three, 2);
  // Everywhere the data decide, also where the prediction cannot (moving one of c0, k1, k2 by 2
  // reported errors changes its predicted regime: a point on a boundary). The data cannot
  // decide a lower bound that does not rise past its branch's lowest point.
  int undetermined = 0, simulated_open = 0;
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const bool open = t.integer(i, "regime_undetermined") != 0;
    const bool data_open = t.integer(i, "simulated_undetermined") != 0;
    undetermined += open;
    simulated_open += data_open;
    if (!data_open) {
      EXPECT_EQ(t.text(i, "predicted_regime"), t.text(i, "simulated_regime"))
          << "a = " << t.number(i, "a") << " d, R = " << t.number(i, "R")
          << " d, b_core^0 = " << t.number(i, "bcore0") << " d, Peierls law "
          << (t.integer(i, "law_extrapolated") != 0 ? "extrapolated" : "within its window")
          << (open ? ", the prediction undetermined" : "");
    }
  }
  EXPECT_EQ(map["contradictions"].get<int>(), 0);
  EXPECT_EQ(map["undetermined"].get<int>(), undetermined);
  EXPECT_EQ(map["simulated_undetermined"].get<int>(), simulated_open);
  // Not a blanket pass: the boundary points are few.
  EXPECT_LE(undetermined, 3);
  EXPECT_EQ(map["agree_law_in_window"].get<int>(), map["points_law_in_window"].get<int>());
  EXPECT_EQ(map["agree"].get<int>(), map["points"].get<int>() - simulated_open)
      << map["disagreements"].dump();
}

}  // namespace

// What each part of the check tests (an audit, 2026-11-30): inside the law's window every
// committed point is simulated and predicted Regime II, with the Regime III law at most 0.165 of
// the nucleation condition (R = 1700 d, a = 430 d; below 0.015 at most points), so that subset
// checks the nucleation condition and would catch only a law overestimated about six times.
// The law itself is tested by the simulated Regime III points, every one at b_core^0 =
// 0.62-0.93 d where the law is extrapolated (predicted III: the map), and quantitatively by
// RegimeThreePredictionFollowsTheUpturn (the prediction against the measured upturn).
TEST(FitScalingRegression, RegimeMapReproducesEverySimulatedRegime) {
  expect_map_reproduces_simulated_regimes(FIT_DIR);
}

// Every committed sweep table, the explicit model's too (acceptance 4: every committed sweep
// point). The explicit rows carry the potential's alpha measured at each point's central load
// (0.709 ... 0.719 for a tip set up for 0.7), which a/b_core^0 and b_core^0 of each row include;
// the map and the crossovers use the lateral force model's alpha.
TEST(FitScalingRegression, RegimeMapOfEveryCommittedTableBothModels) {
  expect_map_reproduces_simulated_regimes(FIT_ALL_DIR);
  const auto s = summary(FIT_ALL_DIR);
  EXPECT_EQ(s["inputs"]["sweeps"].size(), 10u);  // the 6 LFM tables, R = 800 d, the 3 others
  EXPECT_EQ(s["inputs"]["alpha"].get<double>(), 0.7);
  EXPECT_EQ(s["inputs"]["alpha_rule"].get<std::string>(), "the lateral force model's");
  EXPECT_EQ(s["inputs"]["alpha_range"][0].get<double>(), 0.7);
  EXPECT_GT(s["inputs"]["alpha_range"][1].get<double>(), 0.705);
  const CsvTable t = CsvTable::read(FIT_ALL_DIR "/predictions.csv");
  int explicit_rows = 0;
  for (std::size_t i = 0; i < t.rows(); ++i)
    explicit_rows += t.text(i, "model") == "explicit";
  EXPECT_GE(explicit_rows, 8) << "the explicit model's points are not in the fit";
  // The explicit model's points lie on the LFM's collapse (docs/explicit.md), so adding them
  // moves c0 by less than the reported error of the LFM points' fit (measured 2026-11-27: 0.2180
  // against 0.2178 +- 0.0035; when first added: 0.2164 against 0.2196 +- 0.0042).
  const auto lfm = summary()["regime_two"];
  EXPECT_NEAR(s["regime_two"]["c0"].get<double>(), lfm["c0"].get<double>(),
              lfm["c0_error"].get<double>());
}

// What the committed large contacts at R = 1700 d show: no upturn. mu/alpha falls with every
// larger contact and stays within 10% of the Regime II law with c0 fitted at R = 535 d alone
// (out of sample); at R = 100 d it falls too before the predicted crossover (57 d; past it see
// UpturnAtR100PastTheCrossover). And the predicted II -> III crossover at R = 1700 d lies beyond
// the largest point by more than 2 of its errors (which propagate the correlated k1, k2 of the
// scan, 0.94).
TEST(FitScalingRegression, NoUpturnAtR1700) {
  const auto s = summary();
  EXPECT_GT(s["peierls"]["k1_k2_correlation"].get<double>(), 0.9);
  bool crossover_1700 = false;
  for (const auto& c : s["crossovers_two_three"]) {
    if (c["R"].get<double>() != 1700.0 || !c["found"].get<bool>()) continue;
    crossover_1700 = true;
    EXPECT_TRUE(c["a_error_complete"].get<bool>());
    EXPECT_GT(c["a"].get<double>() - 2.0 * c["a_error"].get<double>(), 510.0);
  }
  EXPECT_TRUE(crossover_1700);
  std::set<double> upturn_R;
  for (const auto& u : s["regime_three_upturns"])
    upturn_R.insert(u["R"].get<double>());
  EXPECT_EQ(upturn_R, (std::set<double>{40.0, 100.0}));
  const double c0 = summary(FIT_R535_DIR)["regime_two"]["c0"].get<double>();
  const CsvTable t = CsvTable::read(FIT_DIR "/predictions.csv");
  for (double R : {100.0, 1700.0}) {
    double last_a = 0.0, last_mu = 2.0;
    int n = 0;
    for (std::size_t i = 0; i < t.rows(); ++i) {
      // The measured points: at R = 100 d the one past the crossover is a lower bound.
      if (t.number(i, "R") != R || t.integer(i, "mu_is_lower_bound") != 0) continue;
      const double a = t.number(i, "a"), x = t.number(i, "a_over_bcore0"),
                   mu = t.number(i, "mu_over_alpha");
      ASSERT_GT(a, last_a);  // the table is sorted by a
      EXPECT_LT(mu, last_mu) << "R = " << R << ", a = " << a;
      const double law = 3.0 * std::pow(2.0 * c0, 2.0 / 3.0) * std::pow(x, -2.0 / 3.0);
      if (R == 1700.0) {
        EXPECT_LE(std::abs(mu / law - 1.0), 0.10) << "R = " << R << ", a = " << a;
      }
      last_a = a;
      last_mu = mu;
      ++n;
    }
    EXPECT_GE(n, 2) << R;
  }
}

namespace {

// The summary's upturn at R, or nullptr.
const nlohmann::json* upturn_at(const nlohmann::json& summary, double R) {
  for (const auto& u : summary["regime_three_upturns"])
    if (u["R"].get<double>() == R) return &u;
  return nullptr;
}

}  // namespace

// Acceptance 3 on the upturn the simulator produced (R = 40 d): past its lowest point mu/alpha
// rises with a, and the integrated Regime III prediction (f_P = 0.5 of the local edge Peierls
// stress of the project's own scan) rises too and lies within a factor 2 of every point of the
// rising branch. Recomputed here from predictions.csv, and the tool's own summary must agree.
TEST(FitScalingRegression, RegimeThreePredictionFollowsTheUpturn) {
  const CsvTable t = CsvTable::read(FIT_DIR "/predictions.csv");
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < t.rows(); ++i)
    if (t.number(i, "R") == 40.0) rows.push_back(i);
  // By a: the points of R = 40 d come from two tables (regime3_R40_fill.csv fills in between).
  std::ranges::sort(rows, {}, [&](std::size_t i) { return t.number(i, "a"); });
  ASSERT_GE(rows.size(), 5u);
  std::size_t lowest = 0;
  for (std::size_t k = 1; k < rows.size(); ++k)
    if (t.number(rows[k], "mu_over_alpha") < t.number(rows[lowest], "mu_over_alpha")) lowest = k;
  std::vector<double> la, ld, lp;
  for (std::size_t k = lowest; k < rows.size(); ++k) {
    const std::size_t i = rows[k];
    const double a = t.number(i, "a"), mu = t.number(i, "mu_over_alpha"),
                 p3 = t.number(i, "regime_three_integrated");
    std::printf(
        "R = 40 d, a = %g d (b_core^0 = %.2f d): mu/alpha %.4f, Regime III %.4f, ratio %.2f, "
        "simulated %s\n",
        a, t.number(i, "bcore0"), mu, p3, mu / p3, t.text(i, "simulated_regime").c_str());
    if (k > lowest) {
      EXPECT_GT(mu / p3, 0.5) << "a = " << a;
      EXPECT_LT(mu / p3, 2.0) << "a = " << a;
    }
    la.push_back(std::log(a));
    ld.push_back(std::log(mu));
    lp.push_back(std::log(p3));
  }
  ASSERT_GE(la.size(), 3u) << "no rising branch after the lowest point";
  // The integrated Regime III law rises with a at fixed R whatever k1, k2 > 0 are; the full
  // prediction, max(nucleation, Regime III), rises only where the law has overtaken nucleation,
  // so its slope is the test of where the crossover lies. Its magnitude must match the data's
  // within a factor 2 too.
  std::vector<double> lf;
  for (std::size_t k = lowest; k < rows.size(); ++k)
    lf.push_back(std::log(t.number(rows[k], "predicted")));
  const double data = log_slope(la, ld), law = log_slope(la, lp), full = log_slope(la, lf);
  std::printf(
      "R = 40 d upturn: d ln(mu)/d ln(a): data %.3f, Regime III law %.3f, max(II, III) %.3f\n",
      data, law, full);
  EXPECT_GT(data, 0.0);
  EXPECT_GT(full, 0.0);
  EXPECT_GT(full / data, 0.5);
  EXPECT_LT(full / data, 2.0);

  const auto s = summary();
  const nlohmann::json* u = upturn_at(s, 40.0);
  ASSERT_NE(u, nullptr) << "no upturn at R = 40 d in the summary";
  EXPECT_TRUE((*u)["same_sign_of_slope"].get<bool>());
  EXPECT_TRUE((*u)["within_factor_2"].get<bool>());
  EXPECT_FALSE((*u)["lower_bounds"].get<bool>());

  // With four simulated Regime III points (a = 28 ... 36 d, all measured) fit_scaling also fits
  // k1, k2 of the law to the friction itself (docs/nucleation.md reports it beside the scan's).
  const auto& fit = s["regime_three_fit_to_friction"];
  ASSERT_TRUE(fit["valid"].get<bool>());
  EXPECT_GE(fit["points"].get<int>(), static_cast<int>(rows.size() - lowest - 1));  // R = 40 d's
  std::printf("Regime III law fitted to friction: k1 = %.3f +- %.3f, k2 = %.3f +- %.3f\n",
              fit["k1"].get<double>(), fit["k1_error"].get<double>(), fit["k2"].get<double>(),
              fit["k2_error"].get<double>());
}

// The upturn at R = 100 d (issue 23, data/reference/regime3_R100.md): a = 60 and 70 d, past the
// predicted crossover (57 d), reached their 8 d cap with mu/alpha still rising, so their rows are
// lower bounds. Both already rise past a = 50 d, the branch's lowest measured point, by more than
// the 2% rise tolerance (6.9% and 6.2%), so they are simulated Regime III whatever their true
// values, and the prediction puts them in III too (a = 60 d on the boundary within 2 errors:
// 1.95 errors from the crossover). They stay out of the fits: c0 is that of the tables without
// them. The data's slope is a lower bound (the bounds are the upturn's largest a) and has the
// prediction's sign.
TEST(FitScalingRegression, UpturnAtR100PastTheCrossover) {
  const CsvTable t = CsvTable::read(FIT_DIR "/predictions.csv");
  int found = 0;
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const double a = t.number(i, "a");
    if (t.number(i, "R") != 100.0 || (a != 60.0 && a != 70.0)) continue;
    ++found;
    EXPECT_EQ(t.integer(i, "mu_is_lower_bound"), 1) << "a = " << a;
    EXPECT_EQ(t.integer(i, "in_window"), 0) << "a = " << a;
    EXPECT_EQ(t.text(i, "simulated_regime"), "III") << "a = " << a;
    EXPECT_EQ(t.text(i, "predicted_regime"), "III") << "a = " << a;
    EXPECT_EQ(t.integer(i, "simulated_undetermined"), 0) << "a = " << a;
  }
  ASSERT_EQ(found, 2) << "the a = 60 and 70 d, R = 100 d rows in predictions.csv";
  const auto s = summary();
  const nlohmann::json* u = upturn_at(s, 100.0);
  ASSERT_NE(u, nullptr) << "no upturn at R = 100 d in the summary";
  EXPECT_TRUE((*u)["lower_bounds"].get<bool>());
  EXPECT_TRUE((*u)["slope_data_is_lower_bound"].get<bool>());
  EXPECT_GT((*u)["slope_dlnmu_dlna_data"].get<double>(), 0.0);
  EXPECT_TRUE((*u)["same_sign_of_slope"].get<bool>());
  ASSERT_EQ((*u)["points"].size(), 3u);
  EXPECT_EQ((*u)["points"][0]["a"].get<double>(), 50.0);
  EXPECT_FALSE((*u)["points"][0]["mu_is_lower_bound"].get<bool>());
  for (int k : {1, 2})
    EXPECT_TRUE((*u)["points"][k]["mu_is_lower_bound"].get<bool>()) << k;
  // The fit of c0 does not see the bound: the sources count it as one, and c0 is to the bit
  // that of the same tables without it.
  int bounds = 0;
  for (const auto& src : s["inputs"]["sweeps"])
    bounds += src["lower_bounds"].get<int>();
  EXPECT_EQ(bounds, 2);
  const auto measured = summary(FIT_MEASURED_DIR);
  EXPECT_EQ(s["regime_two"]["c0"].get<double>(), measured["regime_two"]["c0"].get<double>());
  EXPECT_EQ(s["regime_two"]["c0_error"].get<double>(),
            measured["regime_two"]["c0_error"].get<double>());
}

// Acceptance 3 over the committed large-contact range: the prediction built from the project's
// own Peierls scan, max(nucleation condition, integrated Regime III law), against the R = 1700 d
// points: the same sign of d ln(mu)/d ln(a) and every point within a factor 2. Out of sample:
// the nucleation condition with c0 of the R = 535 d fit alone.
TEST(FitScalingRegression, PredictionFollowsTheLargeContacts) {
  const CsvTable t = CsvTable::read(FIT_DIR "/predictions.csv");
  const double c0 = summary(FIT_R535_DIR)["regime_two"]["c0"].get<double>();
  std::vector<double> la, ld, lp;
  for (std::size_t i = 0; i < t.rows(); ++i) {
    if (t.number(i, "R") != 1700.0) continue;
    const double prediction = std::max(nucleation(t.number(i, "a_over_bcore0"), c0),
                                       t.number(i, "regime_three_integrated"));
    const double ratio = t.number(i, "mu_over_alpha") / prediction;
    EXPECT_GT(ratio, 0.5) << "a = " << t.number(i, "a");
    EXPECT_LT(ratio, 2.0) << "a = " << t.number(i, "a");
    la.push_back(std::log(t.number(i, "a")));
    ld.push_back(std::log(t.number(i, "mu_over_alpha")));
    lp.push_back(std::log(prediction));
  }
  // data/reference/regime3_R1700.csv's six points (a = 250 ... 510 d): a lost row fails here
  // rather than turning the slope comparison into a skip.
  ASSERT_EQ(la.size(), 6u);
  const double data = log_slope(la, ld), predicted = log_slope(la, lp);
  std::printf("R = 1700 d: d ln(mu)/d ln(a): data %.3f, prediction %.3f\n", data, predicted);
  EXPECT_EQ(data > 0.0, predicted > 0.0);
  EXPECT_GT(predicted / data, 0.5);
  EXPECT_LT(predicted / data, 2.0);
}

// The forecast (--forecast-R 800,1700 over a grid of a) is the same model as the data's
// predictions: where the grid meets a committed point (R = 800 d: a = 200, 250; R = 1700 d: 250,
// 275, 300, 360, 430, 510) its prediction is that point's (to the round-off of a/b_core^0, which
// the table gives to 17 digits). Its slope in a is negative before the II -> III crossover and
// positive after it, so the lowest forecast of each R sits on a grid point beside the crossover
// (the summary's, the same as the data's crossover at that R), and the forecast rises at every
// grid point past it: the upturn predicted at R = 800 d from a = 319 d.
TEST(FitScalingRegression, ForecastIsTheDataPredictionAndTurnsUpAtTheCrossover) {
  const CsvTable f = CsvTable::read(FIT_FORECAST_DIR "/forecast.csv");
  const CsvTable p = CsvTable::read(FIT_FORECAST_DIR "/predictions.csv");
  const nlohmann::json s = summary(FIT_FORECAST_DIR);
  // The run's settings, echoed by key (Options::settings()): the flags given, the defaults, and
  // null for the Peierls law's k1 and k2, not given (the law is --peierls').
  EXPECT_EQ(s["settings"]["forecast_R"], nlohmann::json::array({800.0, 1700.0}));
  EXPECT_EQ(s["settings"]["f_P"].get<double>(), 0.5);
  EXPECT_TRUE(s["settings"]["k1"].is_null());
  EXPECT_TRUE(s["settings"]["k2"].is_null());
  EXPECT_EQ(s["settings"]["forecast_a"].size(), f.rows() / 2);
  std::size_t matched = 0;
  for (std::size_t i = 0; i < f.rows(); ++i) {
    for (std::size_t j = 0; j < p.rows(); ++j) {
      if (p.number(j, "R") != f.number(i, "R") || p.number(j, "a") != f.number(i, "a")) continue;
      ++matched;
      EXPECT_NEAR(f.number(i, "predicted"), p.number(j, "predicted"),
                  1e-9 * p.number(j, "predicted"))
          << "a = " << f.number(i, "a") << ", R = " << f.number(i, "R");
      EXPECT_EQ(f.text(i, "predicted_regime"), p.text(j, "predicted_regime"));
    }
  }
  // 8 data points lie on the grid today; more as issue 23's points are committed.
  EXPECT_GE(matched, 8u);
  for (const double R : {800.0, 1700.0}) {
    double crossover = 0.0;
    for (const auto& c : s["forecast"]["crossovers_two_three"])
      if (c["R"].get<double>() == R) crossover = c["a"].get<double>();
    ASSERT_GT(crossover, 0.0) << "R = " << R;
    // Where the two predictions meet, found here from the forecast's own columns: ln(Regime III
    // / nucleation) changes sign between two grid points 10 d apart, and linear interpolation
    // of it puts the crossing within 0.2 d of the tool's root (the log ratio's slope changes by
    // about 5% over 10 d, so the chord misses the root by about 0.06 d). The nucleation
    // condition there is re-derived by this file's own bisection from the fitted c0.
    const double c0 = s["regime_two"]["c0"].get<double>();
    double previous_a = 0.0, previous_log = 0.0;
    bool bracketed = false;
    for (std::size_t i = 0; i < f.rows(); ++i) {
      if (f.number(i, "R") != R) continue;
      const double own = nucleation(f.number(i, "a_over_bcore0"), c0);
      EXPECT_NEAR(f.number(i, "nucleation"), own, 1e-9 * own) << "a = " << f.number(i, "a");
      const double log_ratio = std::log(f.number(i, "regime_three_integrated") / own);
      if (previous_a > 0.0 && previous_log < 0.0 && log_ratio >= 0.0) {
        bracketed = true;
        const double a = f.number(i, "a");
        const double chord =
            previous_a + (a - previous_a) * -previous_log / (log_ratio - previous_log);
        EXPECT_NEAR(crossover, chord, 0.2) << "R = " << R;
        EXPECT_LT(previous_a, crossover);
        EXPECT_GE(a, crossover);
      }
      previous_a = f.number(i, "a");
      previous_log = log_ratio;
    }
    EXPECT_TRUE(bracketed) << "the forecast grid does not bracket the crossover at R = " << R;
    bool data_crossover = false;
    for (const auto& c : s["crossovers_two_three"]) {
      if (c["R"].get<double>() != R) continue;
      data_crossover = true;
      // The data's crossover at this R is the forecast's (one model); its mu/alpha is the
      // nucleation condition there, re-derived.
      const double own = nucleation(c["a_over_bcore0"].get<double>(), c0);
      EXPECT_NEAR(c["mu_over_alpha"].get<double>(), own, 1e-9 * own) << "R = " << R;
      EXPECT_NEAR(c["a"].get<double>(), crossover, 1e-9 * crossover) << "R = " << R;
    }
    EXPECT_TRUE(data_crossover) << "no crossover of the data at R = " << R;
    std::vector<double> a, mu;
    for (std::size_t i = 0; i < f.rows(); ++i) {
      if (f.number(i, "R") != R) continue;
      a.push_back(f.number(i, "a"));
      mu.push_back(f.number(i, "predicted"));
      const double slope = f.number(i, "log_slope");
      if (a.back() < crossover) {
        EXPECT_LT(slope, -1.0) << "a = " << a.back() << ", R = " << R;  // about -4/3
        EXPECT_EQ(f.text(i, "predicted_regime"), "II");
      } else {
        EXPECT_GT(slope, 0.0) << "a = " << a.back() << ", R = " << R;
        EXPECT_EQ(f.text(i, "predicted_regime"), "III");
      }
      EXPECT_GT(f.number(i, "predicted_error"), 0.0);
    }
    const std::size_t lowest =
        static_cast<std::size_t>(std::min_element(mu.begin(), mu.end()) - mu.begin());
    const bool beside =
        (a[lowest] <= crossover && (lowest + 1 == a.size() || a[lowest + 1] > crossover)) ||
        (a[lowest] >= crossover && (lowest == 0 || a[lowest - 1] < crossover));
    EXPECT_TRUE(beside) << "R = " << R << ": lowest at a = " << a[lowest] << ", crossover "
                        << crossover;
    for (std::size_t k = lowest + 1; k < a.size(); ++k) {
      if (a[k - 1] > crossover) {
        EXPECT_GT(mu[k], mu[k - 1]) << "a = " << a[k] << ", R = " << R;
      }
    }
  }
}

// The per-point error of the integrated Regime III law is a reported error like c0's: the
// scan's plain standard errors of k1, k2 (with their correlation) propagated, times the t factor
// of the scan's degrees of freedom (5 points: 3; statistics.hpp). Both are recomputed here
// without the module's error functions: the factor is t_3(Phi(2)) / 2 = 1.6534110875 (scipy's
// stats.t.ppf(stats.norm.cdf(2), 3) / 2), the gradient of ln(mu/alpha) in (k1, k2) a central
// difference of the law (steps 1e-6 relative: truncation and round-off both near 1e-10 of it).
TEST(FitScalingRegression, RegimeThreeLogErrorsAreReportedErrors) {
  namespace nuc = asperity::nucleation;
  const auto s = summary();
  const auto p = s["peierls"];
  ASSERT_EQ(p["points"].get<int>(), 5);  // 3 degrees of freedom: the factor below
  const double factor = p["reported_error_factor"].get<double>();
  EXPECT_NEAR(factor, 1.6534110875, 1e-9);
  const double f_P = s["f_P"].get<double>();
  const nuc::PeierlsLaw law{.k1 = p["k1"].get<double>(), .k2 = p["k2"].get<double>()};
  const double s1 = p["k1_error"].get<double>(), s2 = p["k2_error"].get<double>();
  const double rho = p["k1_k2_correlation"].get<double>();
  const CsvTable t = CsvTable::read(FIT_DIR "/predictions.csv");
  ASSERT_GT(t.rows(), 0u);
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const double beta = t.number(i, "bcore0");
    const auto ln = [&](double k1, double k2) {
      return std::log(nuc::regime_three_integrated(beta, {.k1 = k1, .k2 = k2}, f_P));
    };
    const double h1 = 1e-6 * law.k1, h2 = 1e-6 * law.k2;
    const double g1 = (ln(law.k1 + h1, law.k2) - ln(law.k1 - h1, law.k2)) / (2 * h1);
    const double g2 = (ln(law.k1, law.k2 + h2) - ln(law.k1, law.k2 - h2)) / (2 * h2);
    const double variance = g1 * g1 * s1 * s1 + g2 * g2 * s2 * s2 + 2 * rho * g1 * g2 * s1 * s2;
    const double expected = factor * std::sqrt(variance);
    EXPECT_NEAR(t.number(i, "regime_three_log_error"), expected, 1e-6 * expected)
        << "a = " << t.number(i, "a") << ", R = " << t.number(i, "R");
  }
}

TEST(FitScalingRegression, FiguresWritten) {
  for (const char* f : {"collapse.png", "regime_map.png"})
    EXPECT_GT(std::filesystem::file_size(std::filesystem::path(FIT_DIR) / f), 10000u) << f;
}
