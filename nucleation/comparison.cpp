// The fitted model against friction data (MODEL.md 8); see comparison.hpp.
#include "asperity/nucleation/comparison.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <utility>

#include "asperity/core/common/line_fit.hpp"
#include "asperity/core/common/validate.hpp"

namespace asperity::nucleation {

namespace {

// Least-squares slope of ln y against ln x.
double log_slope(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<double> lx, ly;
  for (std::size_t i = 0; i < x.size(); ++i) {
    lx.push_back(std::log(x[i]));
    ly.push_back(std::log(y[i]));
  }
  return fit_line(lx, ly).slope;
}

// The error of a quantity from the moved models (moved_model, one reported error): per
// independent direction the larger shift of the two ways, the three in quadrature. `shift(m)` is
// the quantity's shift under model m, nullopt where it has none; `complete` turns false for each
// move without a model or a value (the error is then a lower bound).
template <class Shift>
double moved_model_error(const Model& model, double c0_error, Shift shift, bool& complete) {
  double var = 0.0;
  for (int k = 0; k < 3; ++k) {
    double largest = 0.0;
    for (double sign : {1.0, -1.0}) {
      const std::optional<Model> m = moved_model(model, c0_error, k, sign);
      const std::optional<double> s = m ? shift(*m) : std::nullopt;
      if (!s) {
        complete = false;
        continue;
      }
      largest = std::max(largest, *s);
    }
    var += largest * largest;
  }
  return std::sqrt(var);
}

void require_same_length(const char* what, std::size_t n, std::size_t points) {
  if (n != points)
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(n) + " for " +
                                std::to_string(points) + " points");
}

}  // namespace

PeierlsLaw scaled_errors(const PeierlsLaw& law, double factor) {
  PeierlsLaw out = law;
  out.k1_error *= factor;
  out.k2_error *= factor;
  return out;
}

bool law_extrapolated(double beta, const PeierlsLaw& law) {
  return (law.b_min > 0.0 && beta < law.b_min) || (law.b_max > 0.0 && beta > law.b_max);
}

bool regime_undetermined(double a_over_bcore0, double beta, const Model& model, double c0_error,
                         double errors) {
  const Regime at = predict(a_over_bcore0, beta, model).regime;
  bool open = false;
  for (int k = 0; k < 3 && !open; ++k) {
    for (double e : {errors, -errors}) {
      const std::optional<Model> m = moved_model(model, c0_error, k, e);
      open = open || !m || predict(a_over_bcore0, beta, *m).regime != at;
    }
  }
  return open;
}

std::vector<PointComparison> compare_points(std::span<const ScalingPoint> points,
                                            std::span<const Regime> simulated, const Model& model,
                                            double c0_error) {
  require_same_length("compare_points: simulated regimes", simulated.size(), points.size());
  std::vector<PointComparison> out;
  out.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const ScalingPoint& p = points[i];
    PointComparison c;
    c.beta = p.a / p.a_over_bcore0;
    c.prediction = predict(p.a_over_bcore0, c.beta, model);
    c.simulated = simulated[i];
    c.law_extrapolated = law_extrapolated(c.beta, model.law);
    c.undetermined = regime_undetermined(p.a_over_bcore0, c.beta, model, c0_error);
    c.lower_bound = p.lower_bound;
    c.simulated_undetermined = p.lower_bound && c.simulated != Regime::three;
    out.push_back(c);
  }
  return out;
}

MapAgreement map_agreement(std::span<const PointComparison> comparisons) {
  MapAgreement m;
  m.points = comparisons.size();
  for (const PointComparison& c : comparisons) {
    if (c.undetermined) ++m.undetermined;
    if (!c.law_extrapolated) ++m.in_law;
    // A lower bound of unknown regime is no evidence either way: neither an agreement nor a
    // contradiction.
    if (c.simulated_undetermined) {
      ++m.simulated_undetermined;
      continue;
    }
    if (!c.law_extrapolated && c.agrees()) ++m.agree_in_law;
    if (c.agrees()) {
      ++m.agree;
    } else if (!c.undetermined) {
      ++m.contradictions;
    }
  }
  return m;
}

CrossoverEstimate crossover_with_error(double R, double alpha, double nu, const Model& model,
                                       double c0_error) {
  CrossoverEstimate out{.R = R};
  out.crossover = regime_two_three_crossover(R, alpha, nu, model);
  if (!out.crossover.found) return out;
  out.a_error = moved_model_error(
      model, c0_error,
      [&](const Model& m) -> std::optional<double> {
        const Crossover moved = regime_two_three_crossover(R, alpha, nu, m);
        if (!moved.found) return std::nullopt;
        return std::abs(moved.a - out.crossover.a);
      },
      out.a_error_complete);
  return out;
}

Forecast forecast(double a, double R, double alpha, double nu, const Model& model,
                  double c0_error) {
  require_positive("forecast.a", a);
  check_contact("forecast", R, alpha, nu);
  Forecast out{.a = a, .R = R};
  // The prediction at a contact radius a_ of the same sphere (for the slope).
  const auto at = [&](double a_) {
    return predict(control_parameter(a_, R, alpha, nu), bcore0(a_, R, alpha, nu), model)
        .mu_over_alpha;
  };
  out.a_over_bcore0 = control_parameter(a, R, alpha, nu);
  out.beta = bcore0(a, R, alpha, nu);
  out.prediction = predict(out.a_over_bcore0, out.beta, model);
  out.law_extrapolated = law_extrapolated(out.beta, model.law);
  out.undetermined = regime_undetermined(out.a_over_bcore0, out.beta, model, c0_error);
  constexpr double h = 1e-3;
  out.log_slope = (std::log(at(a * (1.0 + h))) - std::log(at(a * (1.0 - h)))) /
                  (std::log1p(h) - std::log1p(-h));
  out.mu_over_alpha_error = moved_model_error(
      model, c0_error,
      [&](const Model& m) -> std::optional<double> {
        return std::abs(predict(out.a_over_bcore0, out.beta, m).mu_over_alpha -
                        out.prediction.mu_over_alpha);
      },
      out.error_complete);
  return out;
}

std::vector<Upturn> regime_three_upturns(std::span<const ScalingPoint> points,
                                         std::span<const PointComparison> comparisons) {
  require_same_length("regime_three_upturns: comparisons", comparisons.size(), points.size());
  // Branches in index order within each: the sort below then sees them as the data give them.
  std::map<std::pair<int, double>, std::vector<std::size_t>> branches;
  for (std::size_t i = 0; i < points.size(); ++i)
    branches[{points[i].series, points[i].R}].push_back(i);
  std::vector<Upturn> out;
  for (auto& [key, idx] : branches) {
    // By a / b_core^0, as simulated_regimes walks a branch (an explicit row carries its own
    // alpha, so the order by a could differ).
    std::stable_sort(idx.begin(), idx.end(), [&](std::size_t i, std::size_t j) {
      return points[i].a_over_bcore0 < points[j].a_over_bcore0;
    });
    Upturn u{.series = key.first, .R = key.second};
    for (std::size_t k = 0; k < idx.size(); ++k) {
      if (comparisons[idx[k]].simulated != Regime::three) continue;
      if (u.points.empty()) {
        // The branch starts at the lowest point before the first rising one (a measured one:
        // simulated_regimes never takes a lower bound for the lowest).
        std::optional<std::size_t> lowest;
        for (std::size_t m = 0; m < k; ++m) {
          if (points[idx[m]].lower_bound) continue;
          if (!lowest || points[idx[m]].mu_over_alpha < points[*lowest].mu_over_alpha)
            lowest = idx[m];
        }
        if (lowest) u.points.push_back(*lowest);
      }
      u.points.push_back(idx[k]);
    }
    if (u.points.size() < 2) continue;
    std::vector<double> a, mu_data, mu_int, mu_comb;
    for (std::size_t i : u.points) {
      const Prediction& pr = comparisons[i].prediction;
      a.push_back(points[i].a);
      mu_data.push_back(points[i].mu_over_alpha);
      mu_int.push_back(pr.integrated);
      mu_comb.push_back(pr.mu_over_alpha);
      if (points[i].lower_bound) continue;
      const double ratio = points[i].mu_over_alpha / pr.integrated;
      u.worst_factor = std::max(u.worst_factor, std::max(ratio, 1.0 / ratio));
    }
    u.slope_data = log_slope(a, mu_data);
    double mean_ln_a = 0.0;
    for (double x : a)
      mean_ln_a += std::log(x) / static_cast<double>(a.size());
    bool above = true;
    for (std::size_t i : u.points) {
      if (!points[i].lower_bound) continue;
      u.lower_bounds = true;
      above = above && std::log(points[i].a) > mean_ln_a;
    }
    u.slope_data_is_lower_bound = u.lower_bounds && above;
    u.slope_integrated = log_slope(a, mu_int);
    u.slope_predicted = log_slope(a, mu_comb);
    out.push_back(std::move(u));
  }
  return out;
}

RegimeThreeFrictionFit fit_regime_three_to_upturns(std::span<const ScalingPoint> points,
                                                   std::span<const PointComparison> comparisons,
                                                   std::span<const Upturn> upturns, double f_P) {
  require_same_length("fit_regime_three_to_upturns: comparisons", comparisons.size(),
                      points.size());
  std::vector<double> beta, mu;
  for (const Upturn& u : upturns) {
    for (std::size_t i : u.points) {
      // A lower bound would pull the fit low.
      if (comparisons[i].simulated != Regime::three || points[i].lower_bound) continue;
      beta.push_back(points[i].a / points[i].a_over_bcore0);
      mu.push_back(points[i].mu_over_alpha);
    }
  }
  RegimeThreeFrictionFit out;
  out.points = beta.size();
  // Two parameters: at least 4 points, so that the errors rest on 2 degrees of freedom.
  if (beta.size() < 4) {
    out.reason = "fewer than 4 simulated Regime III points";
    return out;
  }
  out.attempted = true;
  out.fit = fit_regime_three(beta, mu, {.form = RegimeThreeForm::integrated, .f_P = f_P});
  return out;
}

}  // namespace asperity::nucleation
