// Honest errors of the fits of MODEL.md 8 (issue 9, acceptance 1): over 200 seeded synthetic
// trials with noise, the true c0 (and k1, k2) must lie within two reported errors in 90-99% of
// them. The reported error is built to make +-2 errors a 95.45% interval (statistics.hpp), so
// the expected coverage is 95.45% and 200 trials scatter it by +-1.5% (one binomial SD).
// The error of a Regime III prediction from a Peierls law fitted on a window of core widths
// (peierls::fit_exponential) uses the correlation of k1 and k2: for the central form it is the
// line fit's prediction error s sqrt(1/n + (beta - mean_b)^2 / S_bb) (to round-off, 1e-12), and
// the true ln(mu/alpha) lies within 2 reported errors (t factor of n - 2) in 90-99% of 200
// trials at the window's lower end and below it. Taken as independent, k1 and k2 give errors
// 1.9x too large at the lower end (b = 2 d) and 4.1x at the centre (4 d); the 200 trials then
// cover 97-98% (printed), so the exact form is what tells the two apart.
// Also the closed forms behind the predictions: E_n against std::expint and quadrature, the
// integrated Regime III law against a direct integral over the Hertz disk, and the nucleation
// condition against the bonded-disk traction it is built from.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "asperity/nucleation/regime_three.hpp"
#include "asperity/nucleation/regime_two.hpp"
#include "asperity/nucleation/statistics.hpp"
#include "asperity/peierls/fit.hpp"

using namespace asperity::nucleation;

namespace {

constexpr int kTrials = 200;

// Standard normal deviates by Box-Muller on mt19937_64 (std::normal_distribution is
// implementation-defined; these trials are the same everywhere).
struct Normal {
  std::mt19937_64 rng;
  explicit Normal(std::uint64_t seed) : rng(seed) {}
  double operator()() {
    const double u1 = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;
    const double u2 = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }
};

void expect_coverage(int hits, const char* what) {
  const double coverage = static_cast<double>(hits) / kTrials;
  std::printf("coverage of %s within 2 reported errors: %d / %d = %.3f\n", what, hits, kTrials,
              coverage);
  EXPECT_GE(coverage, 0.90) << what;
  EXPECT_LE(coverage, 0.99) << what;
}

}  // namespace

// c0 from n points with 5% log-normal scatter about the Regime II law, for a window of 4 points
// (the t effect is largest there) and one of 8.
TEST(Acceptance1, C0ErrorsAreHonest) {
  const double c0 = 0.21;
  for (const std::vector<double>& xs :
       {std::vector<double>{8, 15, 30, 60}, std::vector<double>{6, 8, 11, 15, 21, 30, 42, 60}}) {
    int hits = 0;
    for (int trial = 0; trial < kTrials; ++trial) {
      Normal noise(1000 + static_cast<std::uint64_t>(trial));
      std::vector<ScalingPoint> points;
      for (double x : xs)
        points.push_back({.a_over_bcore0 = x,
                          .mu_over_alpha = regime_two_law(x, c0) * std::exp(0.05 * noise())});
      const RegimeTwoFit fit = fit_regime_two(points, {.window = std::pair{1.0, 1e3},
                                                       .bootstrap_samples = 2000,
                                                       .seed = static_cast<std::uint64_t>(trial)});
      ASSERT_TRUE(fit.valid);
      if (std::abs(fit.c0 - c0) <= 2.0 * fit.c0_error) ++hits;
    }
    expect_coverage(hits, xs.size() == 4 ? "c0 (4 points)" : "c0 (8 points)");
  }
}

// The same through the automatic window, which must find the Regime II branch itself and trims
// end points that miss the line by more than 10% (WindowOptions): each trial's branch starts in
// Regime I (mu/alpha = 1 and 0.95) and ends with two Regime III points rising above the law,
// around 8 Regime II points with 5% scatter. Trimming drops genuine scatter too (a 5% point
// misses by 10% about 5% of the time), which narrows the errors; coverage must stay honest.
TEST(Acceptance1, C0ErrorsAreHonestThroughTheAutomaticWindow) {
  const double c0 = 0.21;
  const std::vector<double> xs{6, 8, 11, 15, 21, 30, 42, 60};
  int hits = 0, trimmed = 0, wrong_window = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    Normal noise(5000 + static_cast<std::uint64_t>(trial));
    std::vector<ScalingPoint> points{{.a_over_bcore0 = 0.3, .mu_over_alpha = 1.0},
                                     {.a_over_bcore0 = 1.0, .mu_over_alpha = 0.95}};
    for (double x : xs)
      points.push_back(
          {.a_over_bcore0 = x, .mu_over_alpha = regime_two_law(x, c0) * std::exp(0.05 * noise())});
    for (double rise : {1.3, 1.7})
      points.push_back(
          {.a_over_bcore0 = 60.0 * rise, .mu_over_alpha = points.back().mu_over_alpha * rise});
    const RegimeTwoFit fit = fit_regime_two(
        points, {.bootstrap_samples = 2000, .seed = static_cast<std::uint64_t>(trial)});
    ASSERT_TRUE(fit.valid) << fit.reason;
    trimmed += static_cast<int>(fit.trimmed);
    for (std::size_t i : fit.used)
      if (i < 2 || i >= 2 + xs.size()) ++wrong_window;
    if (std::abs(fit.c0 - c0) <= 2.0 * fit.c0_error) ++hits;
  }
  std::printf("automatic window: %d points trimmed over %d trials\n", trimmed, kTrials);
  EXPECT_EQ(wrong_window, 0);  // no Regime I or III point in any window
  expect_coverage(hits, "c0 (automatic window)");
}

// k1, k2 by Levenberg-Marquardt from 6 points with 10% log-normal scatter, both forms.
TEST(Acceptance1, K1K2ErrorsAreHonest) {
  const PeierlsLaw truth{.k1 = 2.3, .k2 = 1.8};
  const std::vector<double> beta = {1.5, 2.0, 2.5, 3.0, 3.5, 4.0};
  for (RegimeThreeForm form : {RegimeThreeForm::central, RegimeThreeForm::integrated}) {
    int hits1 = 0, hits2 = 0;
    for (int trial = 0; trial < kTrials; ++trial) {
      Normal noise(5000 + static_cast<std::uint64_t>(trial));
      std::vector<double> mu;
      for (double b : beta)
        mu.push_back(regime_three(form, b, truth, 0.5) * std::exp(0.1 * noise()));
      const RegimeThreeFit fit = fit_regime_three(beta, mu, {.form = form, .f_P = 0.5});
      ASSERT_TRUE(fit.valid) << fit.reason;
      if (std::abs(fit.law.k1 - truth.k1) <= 2.0 * fit.law.k1_error) ++hits1;
      if (std::abs(fit.law.k2 - truth.k2) <= 2.0 * fit.law.k2_error) ++hits2;
    }
    const std::string f = to_string(form);
    expect_coverage(hits1, ("k1, " + f).c_str());
    expect_coverage(hits2, ("k2, " + f).c_str());
  }
}

// A law fitted like peierls_scan's edge fit: b_core = 2..6 d, 5 points, 5% log-normal scatter.
TEST(Acceptance1, PredictionErrorsOfAFittedLawUseItsCorrelation) {
  const double k1 = 2.3, k2 = 1.8;
  const std::vector<double> b = {2.0, 3.0, 4.0, 5.0, 6.0};
  const double n = static_cast<double>(b.size());
  double mean = 0.0, sbb = 0.0;
  for (double x : b)
    mean += x / n;
  for (double x : b)
    sbb += (x - mean) * (x - mean);
  const double t = t_factor(n - 2.0);
  const std::vector<double> betas = {2.0, 1.5};  // the window's lower end, and below it
  std::vector<int> hits(betas.size(), 0), hits_uncorrelated(betas.size(), 0);
  for (int trial = 0; trial < kTrials; ++trial) {
    Normal noise(9000 + static_cast<std::uint64_t>(trial));
    std::vector<double> ratio;
    for (double x : b)
      ratio.push_back(k1 * std::exp(-k2 * x + 0.05 * noise()));
    const auto f = asperity::peierls::fit_exponential(b, ratio, 0.0, 100.0);
    ASSERT_TRUE(f.valid);
    EXPECT_GT(f.correlation, 0.9) << "a window at b_core > 0";
    double ssr = 0.0;
    for (std::size_t i = 0; i < b.size(); ++i) {
      const double r = std::log(ratio[i]) - (std::log(f.k1) - f.k2 * b[i]);
      ssr += r * r;
    }
    const double s = std::sqrt(ssr / (n - 2.0));
    const PeierlsLaw law{.k1 = f.k1,
                         .k1_error = f.k1_error,
                         .k2 = f.k2,
                         .k2_error = f.k2_error,
                         .correlation = f.correlation};
    PeierlsLaw independent = law;
    independent.correlation = 0.0;
    for (std::size_t j = 0; j < betas.size(); ++j) {
      const double beta = betas[j];
      const double error = regime_three_log_error(RegimeThreeForm::central, beta, law);
      const double line = s * std::sqrt(1.0 / n + (beta - mean) * (beta - mean) / sbb);
      EXPECT_NEAR(error, line, 1e-12 * line) << "beta = " << beta;
      const double truth = std::log(regime_three_central(beta, PeierlsLaw{.k1 = k1, .k2 = k2}));
      const double predicted = std::log(regime_three_central(beta, law));
      if (std::abs(predicted - truth) <= 2.0 * t * error) ++hits[j];
      if (std::abs(predicted - truth) <=
          2.0 * t * regime_three_log_error(RegimeThreeForm::central, beta, independent))
        ++hits_uncorrelated[j];
    }
  }
  for (std::size_t j = 0; j < betas.size(); ++j) {
    expect_coverage(hits[j], ("ln mu/alpha at beta = " + std::to_string(betas[j])).c_str());
    std::printf("  (k1, k2 taken as independent: %d / %d)\n", hits_uncorrelated[j], kTrials);
  }
}

// E_1 = -Ei(-x) (std::expint) to 1e-13; E_n by quadrature of int_1^inf t^-n e^(-x t) dt.
TEST(ClosedForms, ExponentialIntegral) {
  for (double x : {0.01, 0.3, 1.0, 1.5, 5.0, 20.0})
    EXPECT_NEAR(exponential_integral_en(1, x) / -std::expint(-x), 1.0, 1e-13) << x;
  for (int n : {2, 3, 4}) {
    for (double x : {0.2, 1.0, 3.0, 8.0}) {
      // t = 1/w: int_0^1 w^(n-2) e^(-x/w) dw, composite Simpson on 20000 intervals.
      const int m = 20000;
      double sum = 0.0;
      for (int i = 0; i <= m; ++i) {
        const double w = static_cast<double>(i) / m;
        const double f = w > 0.0 ? std::pow(w, n - 2) * std::exp(-x / w) : 0.0;
        sum += f * (i == 0 || i == m ? 1.0 : (i % 2 ? 4.0 : 2.0));
      }
      EXPECT_NEAR(exponential_integral_en(n, x) / (sum / (3.0 * m)), 1.0, 1e-9) << n << " " << x;
    }
  }
}

// mu/alpha = f_P int tau_P dA / (alpha Fz), done directly over r for a Hertz contact a = 300 d,
// R = 1700 d: tau_P = k1 alpha p exp(-k2 d G / (alpha p)), Fz = 2 pi a^2 p0 / 3.
TEST(ClosedForms, IntegratedRegimeThreeIsTheHertzDiskIntegral) {
  const PeierlsLaw law{.k1 = 2.3, .k2 = 1.8};
  const double a = 300, R = 1700, alpha = 0.7, G = 1.0, f_P = 0.5;
  const double p0 = 2.0 * a * 4.0 * G / (std::numbers::pi * R);  // E* = 4 G at nu = 0.5
  const int m = 200000;
  double sum = 0.0;
  for (int i = 0; i < m; ++i) {
    const double r = (i + 0.5) * a / m;
    const double p = p0 * std::sqrt(1.0 - r * r / (a * a));
    sum += law.k1 * alpha * p * std::exp(-law.k2 * G / (alpha * p)) * 2.0 * std::numbers::pi * r *
           (a / m);
  }
  const double Fz = 2.0 * std::numbers::pi * a * a * p0 / 3.0;
  const double direct = f_P * sum / (alpha * Fz);
  const double closed = regime_three_integrated(bcore0(a, R, alpha, 0.5), law, f_P);
  EXPECT_NEAR(closed / direct, 1.0, 1e-6);
}

// At the nucleation site r* = x a the bonded traction Fx/(2 pi a^2)(1 - x^2)^(-1/2) with
// Fx = mu alpha Fz equals alpha p(r*), and a (1 - x) = c0 b_core(r*).
TEST(ClosedForms, NucleationConditionSatisfiesItsDefinition) {
  const double c0 = 0.21, alpha = 0.7, R = 535;
  for (double a : {40.0, 80.0, 134.0}) {
    const double p0 = 2.0 * a * 4.0 / (std::numbers::pi * R);
    const double x_ratio = 8.0 / std::numbers::pi * alpha * a * a / R;  // a / b_core^0
    const NucleationSolution s = nucleation_condition(x_ratio, c0);
    ASSERT_FALSE(s.rigid);
    const double Fz = 2.0 * std::numbers::pi * a * a * p0 / 3.0;
    const double Fx = s.mu_over_alpha * alpha * Fz;
    const double r = s.x * a;
    const double tau = Fx / (2.0 * std::numbers::pi * a * a) / std::sqrt(1.0 - s.x * s.x);
    const double p = p0 * std::sqrt(1.0 - s.x * s.x);
    EXPECT_NEAR(tau / (alpha * p), 1.0, 1e-10) << a;
    EXPECT_NEAR((a - r) / (c0 / (alpha * p)), 1.0, 1e-10) << a;
  }
}

// The adhesive law's c0 (issue 27) with honest errors as the Hertz one's: 200 trials of 5
// points with 5% log-normal scatter about tau_fric/tau0 = 2 (2 c0)^(1/2) (a/b_core)^(-1/2).
TEST(Acceptance1, AdhesiveC0ErrorsAreHonest) {
  const double c0 = 0.2;
  const RegimeTwoLaw law = adhesive_law();
  int hits = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    Normal noise(5000 + static_cast<std::uint64_t>(trial));
    std::vector<ScalingPoint> points;
    for (double x : {4.0, 8.0, 16.0, 32.0, 64.0})
      points.push_back({.a_over_bcore0 = x,
                        .mu_over_alpha = regime_two_law(law, x, c0) * std::exp(0.05 * noise())});
    const RegimeTwoFit fit = fit_regime_two(points, {.law = law,
                                                     .window = std::pair{1.0, 1e3},
                                                     .bootstrap_samples = 2000,
                                                     .seed = static_cast<std::uint64_t>(trial)});
    ASSERT_TRUE(fit.valid);
    if (std::abs(fit.c0 - c0) <= 2.0 * fit.c0_error) ++hits;
  }
  expect_coverage(hits, "adhesive c0 (5 points)");
}

// The adhesive condition from its definition: the bonded traction Fx/(2 pi a^2)(1 - x^2)^(-1/2)
// with Fx = (tau_fric/tau0) tau0 pi a^2 equals tau0 at r* = x a, and a (1 - x) = c0 d G / tau0.
TEST(ClosedForms, AdhesiveNucleationConditionSatisfiesItsDefinition) {
  const double c0 = 0.2, tau0 = 0.2;  // b_core = 5 d
  for (double a : {20.0, 80.0, 300.0}) {
    const NucleationSolution s = nucleation_condition(adhesive_law(), a * tau0, c0);
    ASSERT_FALSE(s.rigid);
    const double Fx = s.mu_over_alpha * tau0 * std::numbers::pi * a * a;
    const double tau = Fx / (2.0 * std::numbers::pi * a * a) / std::sqrt(1.0 - s.x * s.x);
    EXPECT_NEAR(tau / tau0, 1.0, 1e-12) << a;
    EXPECT_NEAR(a * (1.0 - s.x) / (c0 / tau0), 1.0, 1e-12) << a;
  }
}
