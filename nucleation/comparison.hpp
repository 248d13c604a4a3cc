// The fitted model against the friction data it was fitted to (MODEL.md 8; fit_scaling reports
// it): per point the prediction, whether the point lies in its simulated regime and whether the
// prediction can decide that at all; the II -> III crossover with its error; the Regime III
// upturns of the data against the prediction, and a fit of k1, k2 to their rising points.
//
// Errors are reported errors (statistics.hpp) throughout: the model's c0 error and the law's
// k1, k2 errors must be on that footing (scaled_errors), so that "2 errors" is the 95.45%
// interval in every test below.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "asperity/nucleation/regime_map.hpp"
#include "asperity/nucleation/regime_three.hpp"
#include "asperity/nucleation/regime_two.hpp"

namespace asperity::nucleation {

// The law with its k1 and k2 errors multiplied by `factor`: a peierls_scan fit gives plain
// standard errors, which t_factor of their degrees of freedom turns into reported errors.
PeierlsLaw scaled_errors(const PeierlsLaw& law, double factor);

// Whether the law is used outside the core widths it was fitted on at b_core^0 = beta: the
// centre's core width is the smallest in the contact (tau_P is largest there), so below the
// window the law is extrapolated where it matters; above it the law is tiny and a regime test of
// it is empty. A bound of 0 is unknown and not tested.
bool law_extrapolated(double beta, const PeierlsLaw& law);

// Whether the prediction cannot decide the regime of a contact (a / b_core^0, beta = b_core^0 /
// d): moving c0 or the (k1, k2) pair along any one independent direction (moved_model) by
// `errors` reported errors, either way, changes the predicted regime or leaves no valid model.
// Such a point lies on a boundary within the fitted parameters' uncertainty.
bool regime_undetermined(double a_over_bcore0, double beta, const Model& model, double c0_error,
                         double errors = 2.0);

// One data point against the model.
struct PointComparison {
  Prediction prediction;
  Regime simulated = Regime::one;  // simulated_regimes()
  double beta = 0.0;               // b_core^0 / d = a / (a / b_core^0)
  bool law_extrapolated = false;   // law_extrapolated(beta)
  bool undetermined = false;       // regime_undetermined() within 2 reported errors
  bool lower_bound = false;        // the data point is a lower bound (ScalingPoint::lower_bound)
  // A lower bound outside Regime III: its simulated regime is its bound's, and its true value
  // may lie in another (simulated_regimes).
  bool simulated_undetermined = false;
  [[nodiscard]] bool agrees() const { return prediction.regime == simulated; }
};

// Every point in the order given (a > 0: the prediction needs b_core^0); `simulated` of the same
// length.
std::vector<PointComparison> compare_points(std::span<const ScalingPoint> points,
                                            std::span<const Regime> simulated, const Model& model,
                                            double c0_error);

// How well the regime map reproduces the simulated regimes.
struct MapAgreement {
  std::size_t points = 0;
  // Predicted regime = simulated regime (not counting lower bounds of unknown regime, which
  // agree with nothing: simulated_undetermined).
  std::size_t agree = 0;
  std::size_t in_law = 0;        // points where the Peierls law is used within its window
  std::size_t agree_in_law = 0;  // of those, in agreement
  std::size_t undetermined = 0;  // points the prediction cannot decide (agreeing or not)
  // Lower bounds whose simulated regime is not known (PointComparison::simulated_undetermined).
  std::size_t simulated_undetermined = 0;
  // Disagreements where the prediction and the data decide: the ones that count against the
  // model.
  std::size_t contradictions = 0;
};
MapAgreement map_agreement(std::span<const PointComparison> comparisons);

// The II -> III crossover at R with the error of its a: c0 and the (k1, k2) pair moved both ways
// along each independent direction by one reported error (moved_model), the larger shift of a
// taken, the three in quadrature. Not included: the law's extrapolation below its fit window, a
// systematic error (docs/nucleation.md).
struct CrossoverEstimate {
  double R = 0.0;  // sphere radius (d)
  Crossover crossover;
  double a_error = 0.0;  // only when crossover.found
  // false when a move leaves no valid model or no crossover in range: the error is then a lower
  // bound.
  bool a_error_complete = true;
};
CrossoverEstimate crossover_with_error(double R, double alpha, double nu, const Model& model,
                                       double c0_error);

// The prediction at a contact that has no data yet (fit_scaling --forecast-R, --forecast-a): what
// a sweep still to be run should find, and where its upturn lies.
// - mu_over_alpha_error: the prediction moved by one reported error of c0 and of the (k1, k2)
//   pair along each independent direction (moved_model), the larger shift of the two ways, the
//   three in quadrature (as crossover_with_error does for a). Not included: the law's
//   extrapolation below its fit window (law_extrapolated), a systematic error.
// - log_slope: d ln(mu/alpha) / d ln a of the prediction at fixed R, by a central difference over
//   a (1 +- 1e-3). The nucleation condition falls with a (about -4/3: a/b_core^0 grows as a^2)
//   and the integrated Regime III law rises (b_core^0 = R / (c alpha a) narrows), so the slope
//   changes sign at the II -> III crossover: an upturn is predicted where it is positive. In
//   Regime I (mu/alpha capped at 1) it is 0. Within a factor 1 +- 1e-3 of the crossover the
//   difference straddles the kink of max(II, III) and gives a mix of the two sides.
struct Forecast {
  double a = 0.0, R = 0.0;     // contact and sphere radius (d)
  double a_over_bcore0 = 0.0;  // control_parameter(a, R, alpha, nu)
  double beta = 0.0;           // b_core^0 / d
  Prediction prediction;
  double mu_over_alpha_error = 0.0;
  bool error_complete = true;  // false: a moved model was not valid, the error is a lower bound
  double log_slope = 0.0;
  bool law_extrapolated = false;  // law_extrapolated(beta)
  bool undetermined = false;      // regime_undetermined() within 2 reported errors
};
// Throws std::invalid_argument for a not positive and finite, or a contact check_contact refuses.
Forecast forecast(double a, double R, double alpha, double nu, const Model& model, double c0_error);

// The Regime III upturn of one branch (series and R) of the data: the branch's lowest point
// before its first rising one, then every point the simulation puts in Regime III, by a.
struct Upturn {
  int series = 0;
  double R = 0.0;
  std::vector<std::size_t> points;  // indices into the points given, by a / b_core^0
  // d ln(mu/alpha) / d ln a over the points (least squares): of the data, of the integrated
  // Regime III law and of the prediction max(II, III).
  double slope_data = 0.0, slope_integrated = 0.0, slope_predicted = 0.0;
  // Largest factor between the data and the integrated law, either way (>= 1), over the
  // measured points (a bound's ratio bounds nothing: the true one may lie on either side of 1).
  double worst_factor = 1.0;
  // Some points are lower bounds (ScalingPoint::lower_bound): slope_data uses their bounds. It
  // is then a lower bound of the data's slope if every bound lies above the mean of ln a
  // (raising such a point only steepens a least-squares line), and says nothing otherwise.
  bool lower_bounds = false;
  bool slope_data_is_lower_bound = false;
  // Whether the sign of the data's slope is known: no bounds, or a positive lower bound of it.
  [[nodiscard]] bool slope_data_sign_known() const {
    return !lower_bounds || (slope_data_is_lower_bound && slope_data > 0.0);
  }
};

// Every branch with an upturn (at least two points), ordered by series, then R. `comparisons`
// from compare_points over the same points.
std::vector<Upturn> regime_three_upturns(std::span<const ScalingPoint> points,
                                         std::span<const PointComparison> comparisons);

// The integrated Regime III law fitted to the rising points of the upturns (not a branch's lowest
// point, which nucleation sets, nor a lower bound), taken in the order of `upturns` and of their
// points.
struct RegimeThreeFrictionFit {
  std::size_t points = 0;  // rising points
  bool attempted = false;  // enough points for errors on 2 degrees of freedom (4)
  std::string reason;      // why not attempted
  RegimeThreeFit fit;      // when attempted (fit.valid and fit.reason say how it went)
};
RegimeThreeFrictionFit fit_regime_three_to_upturns(std::span<const ScalingPoint> points,
                                                   std::span<const PointComparison> comparisons,
                                                   std::span<const Upturn> upturns, double f_P);

}  // namespace asperity::nucleation
