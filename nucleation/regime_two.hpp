// Regimes I and II (MODEL.md sections 3, 5 and 8).
//
// Regime II law: a dislocation loop nucleates at distance c0 b_core* from the contact edge, b_core*
// the local core width there, when the shear stress of the bonded (stuck) contact reaches the
// local strength alpha p. To leading order in b_core^0 / a this gives
//   mu / alpha = 3 (2 c0)^(2/3) (a / b_core^0)^(-2/3),
// which is linear in the single unknown ln c0 after taking logarithms with the slope fixed:
//   ln(mu/alpha) + (2/3) ln(a/b_core^0) - ln 3 = (2/3) ln(2 c0).
// fit_regime_two() estimates m = (2/3) ln(2 c0) as the mean of the left side over the points of a
// window (closed-form least squares), with a bootstrap-over-points standard error (statistics.hpp
// says how it is reported).
//
// The same condition without the expansion: bonded rigid-disk traction (MODEL.md 2)
//   tau(r) = Fx / (2 pi a^2) (1 - r^2/a^2)^(-1/2),  Hertz strength alpha p0 (1 - r^2/a^2)^(1/2),
// equal at r* = x a where the distance to the edge is c0 times the local core width,
//   a (1 - x) = c0 d G / (alpha p(r*))  <=>  (1 - x) sqrt(1 - x^2) = c0 / (a / b_core^0),
// gives Fx / (alpha Fz) = 3 (1 - x^2). The left side falls from 1 at the centre to 0 at the edge,
// so there is one root for c0 < a / b_core^0. The contact cannot carry more than alpha Fz (rigid
// sliding, Regime I), hence mu / alpha = min(1, 3 (1 - x^2)): this also predicts the crossover from
// Regime I, at a / b_core^0 = c0 / ((1 - sqrt(2/3)) / sqrt(3)) = 9.44 c0.
//
// Adhesive envelope (issue 27: tau_max = tau0 inside r < a, b_core = d G / tau0 everywhere): the
// same condition with a constant strength, the bonded disk's tau(x a) = tau0 at the distance
// a (1 - x) = c0 b_core from the edge, gives for the friction stress tau_fric = Fx / (pi a^2)
//   tau_fric / tau0 = 2 sqrt(1 - x^2) = 2 sqrt(q (2 - q)),  q = 1 - x = c0 / (a / b_core),
// to leading order in q the law tau_fric / tau0 = 2 (a / (2 c0 b_core))^(-1/2): friction stress
// falling as a^(-1/2), and no sphere radius anywhere. Regime I crossover (tau_fric = tau0) where
// q (2 - q) = 1/4: a / b_core = c0 / (1 - sqrt(3)/2) = 7.46 c0.
// Both laws are y = P (2 c0)^e (a / b_core^0)^(-e), y the friction over its Regime I value
// (mu / alpha, tau_fric / tau0): P = 3, e = 2/3 (Hertz) and P = 2, e = 1/2 (adhesive), fitted
// alike with the law's e and P (RegimeTwoLaw).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace asperity::nucleation {

// The Regime II law of an envelope, y = prefactor (2 c0)^exponent (a / b_core^0)^(-exponent).
struct RegimeTwoLaw {
  enum class Kind { hertz, adhesive };
  Kind kind = Kind::hertz;
  double prefactor = 3.0;
  double exponent = 2.0 / 3.0;
  double inverse_exponent = 1.5;  // 1 / exponent, exact: c0 = exp(ln(2 c0)) / 2 is written with it
  const char* quantity = "mu/alpha";
  const char* formula = "mu/alpha = 3 (2 c0)^(2/3) (a/b_core^0)^(-2/3)";
};
RegimeTwoLaw hertz_law();     // MODEL.md 8
RegimeTwoLaw adhesive_law();  // tau_fric/tau0 = 2 (a/(2 c0 b_core))^(-1/2) (issue 27)

// One friction measurement. a and R are needed by the Regime III prediction (which depends on
// b_core^0 = a / (a / b_core^0), not on a / b_core^0 alone) and to group points into branches:
// the points of one series (one model) at one R, along which friction falls and then rises.
struct ScalingPoint {
  double a_over_bcore0 = 0.0;  // control parameter a / b_core^0 (MODEL.md 3)
  double mu_over_alpha = 0.0;  // static friction over its Regime I value: mu / alpha (Hertz),
                               // tau_fric / tau0 (adhesive law)
  double a = 0.0;              // contact radius (d); 0: unknown
  double R = 0.0;              // sphere radius (d); 0: unknown (all such points are one group)
  int series = 0;              // model of the point (e.g. 0 LFM, 1 explicit): branches per series
  // mu_over_alpha is a lower bound: the slide reached its distance cap with friction still
  // rising (friction_sweep's mu_is_lower_bound). Never fitted; its regime is known only where
  // the bound already rises past the branch's lowest point (simulated_regimes).
  bool lower_bound = false;
};

// Mu / alpha of the leading-order Regime II law (or y of `law`).
double regime_two_law(double a_over_bcore0, double c0);
double regime_two_law(const RegimeTwoLaw& law, double a_over_bcore0, double c0);
// The Regime III upturn in data: mu / alpha of a contact more than rise_tolerance (relative)
// above the lowest of the smaller contacts of its branch (same series and R).
bool rises_past(double mu_over_alpha, double lowest, double rise_tolerance);

// c0 of a point that lies exactly on the law.
double c0_of_point(double a_over_bcore0, double mu_over_alpha);
double c0_of_point(const RegimeTwoLaw& law, double a_over_bcore0, double y);

// Automatic Regime II window, per branch (series and R; points sorted by a / b_core^0):
// - starts at the first point with mu / alpha <= crossover_max (past the crossover from
//   Regime I, where mu / alpha leaves 1);
// - ends at the last point before mu / alpha rises by more than rise_tolerance (relative) above
//   the lowest point of the branch so far (rises_past): the Regime III upturn, by the rule that
//   also marks simulated Regime III points (simulated_regimes);
// - a branch of fewer than min_branch_points points is left out: one point cannot show whether
//   the upturn has begun at its R;
// - then, while the fixed-slope fit misses a point by more than max_deviation (relative), the end
//   point that deviates most is dropped, down to min_points.
struct WindowOptions {
  double crossover_max = 0.75;        // mu / alpha at or below which a point is past the crossover
  double rise_tolerance = 0.02;       // relative rise of mu / alpha that marks the upturn
  double max_deviation = 0.10;        // relative |data - fit| / fit allowed over the window
  std::size_t min_points = 3;         // at least this many points in the window
  std::size_t min_branch_points = 2;  // points a branch (one R) needs to take part

  void validate() const;  // throws std::invalid_argument naming the violated constraint
};

struct RegimeTwoFitOptions {
  RegimeTwoLaw law = hertz_law();  // the envelope's law; the points' mu_over_alpha is its y
  // Window in a / b_core^0 (inclusive); empty: automatic (WindowOptions).
  std::optional<std::pair<double, double>> window;
  WindowOptions automatic;
  int bootstrap_samples = 4000;   // resamples of the points (>= 100)
  std::uint64_t seed = 20240909;  // bootstrap generator seed: the same data give the same error

  void validate() const;  // throws std::invalid_argument naming the violated constraint
};

struct RegimeTwoFit {
  bool valid = false;
  std::string reason;  // why there is no fit, when !valid
  double c0 = 0.0;
  // Reported error: bootstrap standard error of the window mean m = (2/3) ln(2 c0), scaled by
  // sqrt(n / (n - 1)) (the bootstrap's small-sample bias) and by t_factor(n - 1), carried to c0
  // by dc0 = 1.5 c0 dm (c0 = exp(1.5 m) / 2).
  double c0_error = 0.0;
  double c0_se_bootstrap = 0.0;     // the plain bootstrap standard error of c0
  double c0_lo = 0.0, c0_hi = 0.0;  // c0 at m -+ 2 reported errors (asymmetric interval)
  double prefactor = 0.0, prefactor_error = 0.0;  // 3 (2 c0)^(2/3) and its reported error
  double window_lo = 0.0, window_hi = 0.0;        // a / b_core^0 of the first and last point used
  bool window_automatic = true;
  std::vector<std::size_t> used;  // indices of the points in the window
  std::size_t points = 0;
  // Automatic window: branch points dropped to bring the fit within max_deviation; trimming
  // stops at min_points, so the window may still miss it (within_max_deviation false: the data
  // do not follow the law over any window of min_points, which the caller should say).
  std::size_t trimmed = 0;
  double dof = 0.0, t_factor = 0.0;
  double max_relative_deviation = 0.0;  // max |data - fit| / fit over the window
  bool within_max_deviation = true;     // max_relative_deviation <= WindowOptions::max_deviation
  double rms_log_residual = 0.0;
  // Checks of the fixed slope -2/3 over the window (3 points at least; else 0): the free
  // log-log slope with its reported error, and c0 of the lower and upper halves of the window
  // with half their difference, a systematic spread not in c0_error (regime_two.cpp).
  double free_slope = 0.0, free_slope_error = 0.0;
  double c0_lower_half = 0.0, c0_upper_half = 0.0, c0_window_spread = 0.0;
};

// Throws std::invalid_argument if options are invalid or a point is not finite and positive
// (R and a may be 0).
RegimeTwoFit fit_regime_two(std::span<const ScalingPoint> points,
                            const RegimeTwoFitOptions& options = {});

// Indices of the automatic window (empty if fewer than min_points qualify); trimmed, if given,
// receives the number of branch points dropped by the max_deviation rule (judged against `law`).
std::vector<std::size_t> automatic_window(std::span<const ScalingPoint> points,
                                          const WindowOptions& options,
                                          std::size_t* trimmed = nullptr,
                                          const RegimeTwoLaw& law = hertz_law());

// The nucleation condition without the small-b_core expansion.
struct NucleationSolution {
  double mu_over_alpha = 1.0;         // min(1, 3 (1 - x^2))
  double x = 0.0;                     // r* / a of the nucleation site (0 if there is no root)
  double bonded_mu_over_alpha = 0.0;  // 3 (1 - x^2) before the cap
  bool rigid = true;  // Regime I: the bonded contact slides as a whole before any nucleation
};
// c0 > 0 and a / b_core^0 > 0. If c0 >= a / b_core^0 the site would lie beyond the centre: no
// root, bonded_mu_over_alpha = 3 (the value at the centre) and the contact is rigid.
NucleationSolution nucleation_condition(double a_over_bcore0, double c0);
// The same for `law`'s envelope: the Hertz one above, or the adhesive one, x = 1 - q,
// y = min(1, 2 sqrt(q (2 - q))) (bonded_mu_over_alpha 2 at the centre, q >= 1).
NucleationSolution nucleation_condition(const RegimeTwoLaw& law, double a_over_bcore0, double c0);

// The condition of the mixed envelope tau_max = tau0 + alpha p (issue 27), of which the two above
// are the limits: the bonded traction reaches tau_max(r*) where a (1 - x) = c0 b_core(r*),
// b_core(r) = d G / tau_max(r), i.e.
//   (1 - x) (x_A + x_H w) = c0,  w = sqrt(1 - x^2),
// x_A = a tau0 / (d G) and x_H = a alpha p0 / (d G) the two parts of a / b_core^0 (x_H the Hertz
// control parameter c alpha a^2 / (R d)); then Fx / F_I = 2 w (x_A + x_H w) / (x_A + 2 x_H / 3),
// F_I = tau0 pi a^2 + alpha Fz the Regime I force, capped at 1. x_A = 0 gives the Hertz
// condition, x_H = 0 the adhesive one (bonded_mu_over_alpha at the centre: 2 x_A + 2 x_H over
// x_A + 2 x_H / 3, when c0 >= x_A + x_H).
NucleationSolution mixed_nucleation_condition(double x_adhesive, double x_hertz, double c0);

// a / b_core^0 where the nucleation condition reaches mu / alpha = 1: below it, Regime I.
double regime_one_crossover(double c0);
double regime_one_crossover(const RegimeTwoLaw& law, double c0);  // adhesive: c0 / (1 - sqrt3/2)

}  // namespace asperity::nucleation
