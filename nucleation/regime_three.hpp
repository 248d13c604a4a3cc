// Regime III (MODEL.md sections 6 and 8): friction set by the stress to move arrested loops.
//
// Local Peierls stress under the Hertz pressure p(r) (edge law of the Peierls cell):
//   tau_P(r) = k1 alpha p(r) exp(-k2 b_core(r) / d),  b_core(r) = d G / (alpha p(r)).
// Integrated prediction: a fraction f_P of tau_P over the contact, divided by alpha Fz. With
// p = p0 w, w = sqrt(1 - r^2/a^2), and Fz = 2 pi a^2 p0 / 3 the integral is exact:
//   mu / alpha = 3 f_P k1 int_0^1 w^2 exp(-k2 beta / w) dw = 3 f_P k1 E_4(k2 beta),
// beta = b_core^0 / d = R / (c alpha a), E_n the exponential integral int_1^inf t^-n e^(-x t) dt.
// Central estimate (the centre's core width everywhere): mu / alpha = k1 exp(-k2 beta).
// Both cap tau_P at tau_max (the interface's ideal strength), which a fitted k1 > 1 exceeds at
// core widths below ln(k1) / k2 (about 0.5 d): the integral is then split where the cap starts
// (regime_three.cpp), and the central estimate is min(1, ...). The cap is not in MODEL.md 8; it
// keeps the prediction physical where the fitted law is extrapolated that far. The log errors
// and the LM Jacobian differentiate the capped law (regime_three_log_gradient); where every
// point has its centre capped, the integrated law depends on one combination of k1 and k2 and
// the fit reports them as not determined.
// Both depend on a and R separately, not on a / b_core^0 alone (beta = a / (a / b_core^0)).
//
// fit_regime_three() fits k1, k2 of either form to friction data with Eigen's
// Levenberg-Marquardt on logarithmic residuals (relative scatter), with errors from the
// curvature (J^T J)^-1 s^2 reported as in statistics.hpp.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace asperity::nucleation {

// The fraction f_P of the local Peierls stress the integrated Regime III prediction takes by
// default (MODEL.md 8: "default f_P 0.5").
inline constexpr double kDefaultPeierlsFraction = 0.5;

// E_n(x) for n >= 0 and x > 0 (n = 0, 1 need x > 0; continued fraction for x > 1, series below).
double exponential_integral_en(int n, double x);

// tau_P / tau_max = k1 exp(-k2 b_core / d), with the errors of wherever it came from.
struct PeierlsLaw {
  double k1 = 0.0, k1_error = 0.0;  // dimensionless
  double k2 = 0.0, k2_error = 0.0;  // dimensionless (b_core in units of d)
  // Correlation of the k1 and k2 estimates, in [-1, 1] (0: unknown or independent). A fit on a
  // window of core widths gives near +1 (peierls::ExponentialFit::correlation).
  double correlation = 0.0;
  double b_min = 0.0, b_max = 0.0;  // window of core widths the law was fitted on (d); 0: unknown

  void validate() const;  // k1, k2 > 0, errors >= 0, correlation in [-1, 1], all finite
};

enum class RegimeThreeForm { central, integrated };
std::string to_string(RegimeThreeForm form);

// Throws std::invalid_argument naming `where` ("bcore0", "forecast") if R or alpha is not positive
// and finite, or nu lies outside the range the material allows (elastic::Material: [0, 0.5]).
void check_contact(const std::string& where, double R, double alpha, double nu);

// b_core^0 / d of a Hertz contact: R / (c alpha a), c = 4 / (pi (1 - nu)) (MODEL.md 3). The
// expression is its own inverse in a: bcore0(beta, R, alpha, nu) is the a where b_core^0 = beta.
double bcore0(double a, double R, double alpha, double nu);
// The control parameter a / b_core^0 = c alpha a^2 / R of that contact, and its inverse, the
// contact radius a = sqrt(a_over_bcore0 R / (c alpha)) (d) where it takes a given value.
double control_parameter(double a, double R, double alpha, double nu);
double contact_radius(double a_over_bcore0, double R, double alpha, double nu);

// Local Peierls stress tau_P / G where the envelope is tau_max (in G): the law at the local core
// width b_core / d = G / tau_max (MODEL.md 3, 6), capped at tau_max; 0 outside the contact
// (tau_max <= 0). Beside a stress profile it is the stress an arrested core must stay below.
double local_peierls_stress(double tau_max, const PeierlsLaw& law);

// One line angle's Peierls stress (MODEL.md 6): the cell's values at the core widths it was
// computed at (a peierls_scan table's resolved rows at that angle) and the law fitted to them.
// The local stress at tau_max (b_core = d G / tau_max) is interpolated between the two samples
// around b_core, log-linearly (the law's own form between two points), inside the samples'
// range; outside it, the law if there is one, else NaN (no extrapolation of samples). A fit
// over a window of 2-6 d misses the high-index directions at the narrower cores of large
// contacts by up to 2x (data/reference/peierls_narrow_cores.md), where samples do not.
// Capped at tau_max; 0 outside the contact (tau_max <= 0).
struct AngleLaw {
  double theta_deg = 0.0;             // line angle: 0 screw, 90 edge
  std::optional<PeierlsLaw> law;      // the fit at this angle, if valid
  std::vector<double> b_core, ratio;  // samples: b_core ascending (d), tau_P / tau_max (> 0)

  void validate() const;  // throws std::invalid_argument: sizes, order, positivity, finiteness
};
double local_peierls_stress(double tau_max, const AngleLaw& angle);

// The least local Peierls stress over line angles: the weakest straight segment, which is what
// a curved loop's hold rests on (at the narrow cores of large contacts high-index directions
// are several times weaker than edge). Angles with no value at tau_max (NaN) are skipped.
// Returns that stress and its angle; {NaN, NaN} if no angle has a value; outside the contact
// (tau_max <= 0) {0, NaN}: no registry holds a core there, and no angle is the weakest.
struct WeakestSegment {
  double tau_P = 0.0;      // in G
  double theta_deg = 0.0;  // its angle
};
WeakestSegment weakest_local_peierls_stress(double tau_max, std::span<const AngleLaw> angles);

// The local Peierls stress of the scanned angle nearest a segment's angle theta_deg (folded
// into [0, 90]; ties: the first in `angles`), and that angle: the straight line a piece of a
// curved front is compared with (tracking::front_stresses). No interpolation between angles:
// at narrow cores tau_P jumps between neighbouring directions (a high-index direction can be
// several times weaker than its neighbours, data/reference/peierls_narrow_cores.md), so what
// lies between two scanned angles is not known from them. The angle is always the nearest one;
// tau_P is NaN where that angle has no value at tau_max and 0 outside the contact (tau_max <=
// 0). {NaN, NaN} without angles or for a non-finite theta_deg.
WeakestSegment nearest_angle_local_peierls_stress(double tau_max, std::span<const AngleLaw> angles,
                                                  double theta_deg);

// mu / alpha of the two forms at beta = b_core^0 / d.
double regime_three_central(double beta, const PeierlsLaw& law);
double regime_three_integrated(double beta, const PeierlsLaw& law, double f_P);
double regime_three(RegimeThreeForm form, double beta, const PeierlsLaw& law, double f_P);
// Gradient of ln(mu / alpha) in (k1, k2), of the capped law (tau_P <= tau_max): where the cap
// holds, the capped part does not move with k1 or k2 (the central form is then flat).
std::array<double, 2> regime_three_log_gradient(RegimeThreeForm form, double beta,
                                                const PeierlsLaw& law);

// Standard error of ln(mu / alpha) from the errors of k1 and k2 and their correlation (linear
// propagation: for the central form and a law fitted by peierls::fit_exponential this is the
// line fit's prediction error at b_core = beta, s sqrt(1/n + (beta - mean_b)^2 / S_bb)).
double regime_three_log_error(RegimeThreeForm form, double beta, const PeierlsLaw& law);

struct RegimeThreeFitOptions {
  RegimeThreeForm form = RegimeThreeForm::integrated;
  // fraction of the local Peierls stress (integrated form only), in (0, 1]
  double f_P = kDefaultPeierlsFraction;
  int max_function_evaluations = 2000;  // LM cap

  void validate() const;  // throws std::invalid_argument naming the violated constraint
};

struct RegimeThreeFit {
  bool valid = false;
  std::string reason;
  PeierlsLaw law;                         // k1, k2 and their reported errors (statistics.hpp)
  double k1_se = 0.0, k2_se = 0.0;        // plain standard errors
  double correlation = 0.0;               // of k1 and k2
  double beta_min = 0.0, beta_max = 0.0;  // window: b_core^0 / d of the points
  std::size_t points = 0;
  double dof = 0.0, t_factor = 0.0;
  double rms_log_residual = 0.0;
  int evaluations = 0;
};

// beta = b_core^0 / d and mu / alpha per point (same length, >= 3 points, all finite and > 0).
RegimeThreeFit fit_regime_three(std::span<const double> beta, std::span<const double> mu_over_alpha,
                                const RegimeThreeFitOptions& options = {});

}  // namespace asperity::nucleation
