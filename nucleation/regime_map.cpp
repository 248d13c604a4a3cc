// Predictions across regimes and the regime of a point (MODEL.md 5, 8); see regime_map.hpp.
#include "asperity/nucleation/regime_map.hpp"

#include "asperity/core/contact/hertz.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include "asperity/core/common/validate.hpp"

namespace asperity::nucleation {

std::string to_string(Regime r) {
  switch (r) {
    case Regime::one:
      return "I";
    case Regime::two:
      return "II";
    case Regime::three:
      return "III";
  }
  return "?";
}

void Model::validate() const {
  require_positive("Model.c0", c0);
  law.validate();
  if (!(f_P > 0.0 && f_P <= 1.0)) reject("Model.f_P", std::to_string(f_P), "(0, 1]");
}

Regime nearer_of_one_two(double a_over_bcore0, double mu_over_alpha, double c0) {
  const double l = std::log(mu_over_alpha);
  const double to_one = std::abs(l);
  const double to_two = std::abs(l - std::log(regime_two_law(a_over_bcore0, c0)));
  return to_one <= to_two ? Regime::one : Regime::two;
}

Prediction predict(double a_over_bcore0, double beta, const Model& model) {
  model.validate();
  require_positive("predict.beta", beta);
  Prediction p;
  p.nucleation = nucleation_condition(a_over_bcore0, model.c0).mu_over_alpha;
  p.law_two = regime_two_law(a_over_bcore0, model.c0);
  p.central = regime_three_central(beta, model.law);
  p.integrated = regime_three_integrated(beta, model.law, model.f_P);
  p.integrated_log_error = regime_three_log_error(RegimeThreeForm::integrated, beta, model.law);
  p.mu_over_alpha = std::max(p.nucleation, p.integrated);
  p.regime = p.integrated > p.nucleation
                 ? Regime::three
                 : nearer_of_one_two(a_over_bcore0, p.mu_over_alpha, model.c0);
  return p;
}

std::vector<Regime> simulated_regimes(std::span<const ScalingPoint> points, double c0,
                                      double rise_tolerance) {
  std::vector<Regime> out(points.size(), Regime::one);
  std::map<std::pair<int, double>, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < points.size(); ++i)
    groups[{points[i].series, points[i].R}].push_back(i);
  for (auto& [key, idx] : groups) {
    std::stable_sort(idx.begin(), idx.end(), [&](std::size_t i, std::size_t j) {
      return points[i].a_over_bcore0 < points[j].a_over_bcore0;
    });
    double lowest = std::numeric_limits<double>::infinity();
    for (std::size_t i : idx) {
      const ScalingPoint& p = points[i];
      out[i] = rises_past(p.mu_over_alpha, lowest, rise_tolerance)
                   ? Regime::three
                   : nearer_of_one_two(p.a_over_bcore0, p.mu_over_alpha, c0);
      // A lower bound rising past the lowest point is on the rising branch whatever its true
      // value; it cannot be the branch's lowest (its true value may be higher).
      if (!p.lower_bound) lowest = std::min(lowest, p.mu_over_alpha);
    }
  }
  return out;
}

Crossover regime_two_three_crossover(double R, double alpha, double nu, const Model& model,
                                     double a_min, double a_max) {
  model.validate();
  require_positive("regime_two_three_crossover.a_min", a_min);
  if (!(a_max > a_min))
    reject("regime_two_three_crossover.a_max", std::to_string(a_max), "> a_min");
  const double c = contact::bcore_factor(nu);
  // ln(Regime III) - ln(nucleation): increasing in a (III rises, II falls or stays at 1).
  const auto gap = [&](double a) {
    const double x = c * alpha * a * a / R;
    const Prediction p = predict(x, bcore0(a, R, alpha, nu), model);
    return std::log(p.integrated) - std::log(p.nucleation);
  };
  Crossover out;
  const int n = 400;
  double prev_a = a_min, prev = gap(a_min);
  if (prev >= 0.0) return out;  // Regime III from the smallest contact on: no crossover
  for (int k = 1; k <= n; ++k) {
    const double a = a_min * std::pow(a_max / a_min, static_cast<double>(k) / n);
    const double g = gap(a);
    if (g >= 0.0) {
      double lo = prev_a, hi = a;
      for (int it = 0; it < 100 && hi - lo > 1e-12 * hi; ++it) {
        const double mid = 0.5 * (lo + hi);
        (gap(mid) < 0.0 ? lo : hi) = mid;
      }
      out.found = true;
      out.a = 0.5 * (lo + hi);
      out.a_over_bcore0 = c * alpha * out.a * out.a / R;
      out.mu_over_alpha = nucleation_condition(out.a_over_bcore0, model.c0).mu_over_alpha;
      out.small_slope = out.a < 0.1 * R;
      return out;
    }
    prev_a = a;
    prev = g;
  }
  return out;
}

double regime_one_two_boundary(double c0) {
  require_positive("regime_one_two_boundary.c0", c0);
  // 3 (2 c0)^(2/3) x^(-2/3) = 1 (see the header: the nearer asymptote changes there).
  return 2.0 * std::pow(3.0, 1.5) * c0;
}

std::optional<Model> moved_model(const Model& model, double c0_error, int direction,
                                 double errors) {
  if (direction < 0 || direction > 2)
    reject("moved_model.direction", std::to_string(direction), "0 (c0), 1 or 2 (the law's axes)");
  Model m = model;
  if (direction == 0) {
    m.c0 += errors * c0_error;
  } else {
    const double s1 = model.law.k1_error, s2 = model.law.k2_error;
    const double r = model.law.correlation;
    Eigen::Matrix2d cov;
    cov << s1 * s1, r * s1 * s2, r * s1 * s2, s2 * s2;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> axes(cov);
    const int k = direction - 1;
    const Eigen::Vector2d step =
        errors * std::sqrt(std::max(0.0, axes.eigenvalues()(k))) * axes.eigenvectors().col(k);
    m.law.k1 += step(0);
    m.law.k2 += step(1);
  }
  if (m.c0 <= 0.0 || m.law.k1 <= 0.0 || m.law.k2 <= 0.0) return std::nullopt;
  return m;
}

}  // namespace asperity::nucleation
