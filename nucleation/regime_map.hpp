// Friction across Regimes I, II and III and the regime of a point (MODEL.md sections 5 and 8).
//
// Prediction: the nucleation condition (Regimes I and II, regime_two.hpp) and the integrated
// Regime III law (regime_three.hpp); friction is the larger of the two, since the contact slides
// only once loops both nucleate and move. The II -> III crossover is where they meet.
//
// Regime of a point, the same rule for a prediction and for a simulated mu / alpha:
// - III: on the rising branch. A prediction is in III where the Regime III law exceeds the
//   nucleation condition; a simulated point where its mu / alpha exceeds, by more than
//   rise_tolerance, the lowest mu / alpha of a smaller contact of the same series and R (friction
//   rising with load).
//   A lower bound (ScalingPoint::lower_bound) that rises past is III whatever its true value;
//   one that does not is classified by the rule below from its bound, which its true value may
//   not keep (PointComparison::simulated_undetermined), and it never counts as the lowest.
// - otherwise I or II, whichever law is nearer in ln(mu / alpha): Regime I's mu / alpha = 1 or the
//   Regime II law 3 (2 c0)^(2/3) (a / b_core^0)^(-2/3). The crossover is gradual; this puts the
//   boundary where a point is as far from one asymptote as from the other, without a threshold.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "asperity/nucleation/regime_three.hpp"
#include "asperity/nucleation/regime_two.hpp"

namespace asperity::nucleation {

enum class Regime { one = 1, two = 2, three = 3 };
std::string to_string(Regime r);  // "I", "II", "III"

struct Model {
  double c0 = 0.0;                       // Regime II nucleation distance / b_core*
  PeierlsLaw law;                        // Regime III
  double f_P = kDefaultPeierlsFraction;  // fraction of the local Peierls stress, (0, 1]

  void validate() const;  // throws std::invalid_argument naming the violated constraint
};

struct Prediction {
  double nucleation = 0.0;            // min(1, 3 (1 - x*^2)): Regimes I and II
  double law_two = 0.0;               // the leading-order Regime II law
  double central = 0.0;               // Regime III, central estimate
  double integrated = 0.0;            // Regime III, integrated f_P tau_P
  double integrated_log_error = 0.0;  // standard error of ln(integrated) from k1, k2 errors
  double mu_over_alpha = 0.0;         // max(nucleation, integrated)
  Regime regime = Regime::one;
};

// a / b_core^0 and beta = b_core^0 / d of the contact.
Prediction predict(double a_over_bcore0, double beta, const Model& model);

// I or II by the nearer asymptote (see above).
Regime nearer_of_one_two(double a_over_bcore0, double mu_over_alpha, double c0);

// a / b_core^0 on the predicted I/II boundary, where nearer_of_one_two() changes along the
// nucleation condition: 2 * 3^(3/2) * c0 = 10.39 c0, where the Regime II law reaches 1. The
// condition lies below the law everywhere (their ratio is ((1 + x*) / 2)^(2/3) < 1), so where
// the law is >= 1 the condition is nearer 1 than the law, and where the law is < 1 it is below
// the law and nearer it: the two asymptotes meet at the boundary. (A simulated point between
// the law and 1 is instead split at mu = sqrt(law).) The condition itself reaches 1 earlier,
// at 9.44 c0 (regime_two.hpp: Regime I by the condition).
double regime_one_two_boundary(double c0);

// The model with its parameters moved by `errors` standard errors along one of three
// independent directions of their uncertainty: direction 0 moves c0 by errors * c0_error;
// directions 1 and 2 move (k1, k2) along the principal axes of their covariance (errors
// k1_error, k2_error, correlation law.correlation), by errors * sqrt(eigenvalue). k1 and k2 come
// from one line fit and are strongly correlated (near +1 for a window at b_core > 0): moved one
// at a time they would overstate the law's errors inside its window up to 4x
// (peierls/fit.hpp); along the axes, in quadrature, linear propagation is exact (with
// correlation 0 the axes are k1 and k2 alone). nullopt if a parameter would be <= 0.
std::optional<Model> moved_model(const Model& model, double c0_error, int direction, double errors);

// Simulated regime of each point (same order); points are grouped by series and R for the
// rising branch.
std::vector<Regime> simulated_regimes(std::span<const ScalingPoint> points, double c0,
                                      double rise_tolerance = 0.02);

struct Crossover {
  bool found = false;
  double a = 0.0;              // contact radius (d)
  double a_over_bcore0 = 0.0;  // there
  double mu_over_alpha = 0.0;  // both predictions there
  bool small_slope = true;     // a < 0.1 R (the continuum theory's range)
};

// The II -> III crossover at sphere radius R: a in [a_min, a_max] where the integrated Regime III
// law meets the nucleation condition (rising minus falling: one sign change at most).
Crossover regime_two_three_crossover(double R, double alpha, double nu, const Model& model,
                                     double a_min = 1.0, double a_max = 1e6);

}  // namespace asperity::nucleation
