// Regime II fit of c0 and the nucleation condition (MODEL.md 8); see regime_two.hpp.
#include "asperity/nucleation/regime_two.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "asperity/core/common/validate.hpp"
#include "asperity/nucleation/statistics.hpp"

namespace asperity::nucleation {

namespace {

// ln(mu/alpha) + (2/3) ln(a/b_core^0) - ln 3 = (2/3) ln(2 c0) for a point on the law (Hertz;
// ln y + e ln(a/b_core^0) - ln P = e ln(2 c0) for the law's e and P).
double log_term(const ScalingPoint& p, const RegimeTwoLaw& law) {
  return std::log(p.mu_over_alpha) + law.exponent * std::log(p.a_over_bcore0) -
         std::log(law.prefactor);
}

struct Estimate {
  double mean = 0.0;  // of log_term: (2/3) ln(2 c0)
  double max_relative_deviation = 0.0;
  double rms_log_residual = 0.0;
};

Estimate estimate(std::span<const ScalingPoint> points, const std::vector<std::size_t>& used,
                  const RegimeTwoLaw& law) {
  Estimate e;
  for (std::size_t i : used)
    e.mean += log_term(points[i], law);
  e.mean /= static_cast<double>(used.size());
  double ss = 0.0;
  for (std::size_t i : used) {
    const double r = log_term(points[i], law) - e.mean;
    ss += r * r;
    e.max_relative_deviation = std::max(e.max_relative_deviation, std::abs(std::expm1(r)));
  }
  e.rms_log_residual = std::sqrt(ss / static_cast<double>(used.size()));
  return e;
}

void check_points(std::span<const ScalingPoint> points) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    const std::string field = "ScalingPoint[" + std::to_string(i) + "]";
    require_positive(field + ".a_over_bcore0", p.a_over_bcore0);
    require_positive(field + ".mu_over_alpha", p.mu_over_alpha);
    if (!std::isfinite(p.a) || p.a < 0.0) reject(field + ".a", std::to_string(p.a), ">= 0");
    if (!std::isfinite(p.R) || p.R < 0.0) reject(field + ".R", std::to_string(p.R), ">= 0");
  }
}

}  // namespace

void WindowOptions::validate() const {
  require_positive("WindowOptions.crossover_max", crossover_max);
  if (!(rise_tolerance >= 0.0) || !std::isfinite(rise_tolerance))
    reject("WindowOptions.rise_tolerance", std::to_string(rise_tolerance), "finite and >= 0");
  require_positive("WindowOptions.max_deviation", max_deviation);
  require_at_least("WindowOptions.min_points", static_cast<long long>(min_points), 2);
  require_at_least("WindowOptions.min_branch_points", static_cast<long long>(min_branch_points), 1);
}

void RegimeTwoFitOptions::validate() const {
  automatic.validate();
  if (window) {
    require_positive("RegimeTwoFitOptions.window.first", window->first);
    require_positive("RegimeTwoFitOptions.window.second", window->second);
    if (!(window->first <= window->second))
      reject("RegimeTwoFitOptions.window",
             std::to_string(window->first) + ".." + std::to_string(window->second),
             "first <= second");
  }
  require_at_least("RegimeTwoFitOptions.bootstrap_samples", bootstrap_samples, 100);
}

RegimeTwoLaw hertz_law() {
  return {};
}

RegimeTwoLaw adhesive_law() {
  return {.kind = RegimeTwoLaw::Kind::adhesive,
          .prefactor = 2.0,
          .exponent = 0.5,
          .inverse_exponent = 2.0,
          .quantity = "tau_fric/tau0",
          .formula =
              "tau_fric/tau0 = 2 (a/(2 c0 b_core))^(-1/2) = 2 (2 c0)^(1/2) "
              "(a/b_core^0)^(-1/2)"};
}

double regime_two_law(double a_over_bcore0, double c0) {
  return 3.0 * std::pow(2.0 * c0, 2.0 / 3.0) * std::pow(a_over_bcore0, -2.0 / 3.0);
}

double regime_two_law(const RegimeTwoLaw& law, double a_over_bcore0, double c0) {
  if (law.kind == RegimeTwoLaw::Kind::hertz) return regime_two_law(a_over_bcore0, c0);
  return law.prefactor * std::pow(2.0 * c0, law.exponent) * std::pow(a_over_bcore0, -law.exponent);
}

double c0_of_point(double a_over_bcore0, double mu_over_alpha) {
  return 0.5 * std::pow(mu_over_alpha / 3.0, 1.5) * a_over_bcore0;
}

double c0_of_point(const RegimeTwoLaw& law, double a_over_bcore0, double y) {
  if (law.kind == RegimeTwoLaw::Kind::hertz) return c0_of_point(a_over_bcore0, y);
  return 0.5 * std::pow(y / law.prefactor, law.inverse_exponent) * a_over_bcore0;
}

std::vector<std::size_t> automatic_window(std::span<const ScalingPoint> points,
                                          const WindowOptions& options, std::size_t* trimmed,
                                          const RegimeTwoLaw& law) {
  options.validate();
  check_points(points);
  // Per series and R: the descending branch between the crossover and the upturn.
  std::map<std::pair<int, double>, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < points.size(); ++i)
    groups[{points[i].series, points[i].R}].push_back(i);
  std::vector<std::vector<std::size_t>> branches;
  for (auto& [key, idx] : groups) {
    std::stable_sort(idx.begin(), idx.end(), [&](std::size_t i, std::size_t j) {
      return points[i].a_over_bcore0 < points[j].a_over_bcore0;
    });
    std::vector<std::size_t> branch;
    double lowest = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < idx.size(); ++k) {
      const ScalingPoint& p = points[idx[k]];
      // A window holds measured values only. A lower bound that already rises past the lowest
      // point is the upturn whatever its true value, and ends the branch; one that does not
      // says nothing about where the branch goes (simulated_regimes classifies the measured
      // points after it on their own), and neither does one before the branch starts.
      if (p.lower_bound) {
        if (!branch.empty() && rises_past(p.mu_over_alpha, lowest, options.rise_tolerance)) break;
        continue;
      }
      if (branch.empty() && p.mu_over_alpha > options.crossover_max) continue;
      // Against the lowest point so far, not the previous one: a slow upturn (rises under the
      // tolerance, point after point) ends the branch too, where simulated_regimes calls it III.
      if (rises_past(p.mu_over_alpha, lowest, options.rise_tolerance))
        break;  // the upturn: Regime III from here on
      branch.push_back(idx[k]);
      lowest = std::min(lowest, p.mu_over_alpha);
    }
    if (!branch.empty() && branch.size() >= options.min_branch_points)
      branches.push_back(std::move(branch));
  }
  const auto flatten = [&] {
    std::vector<std::size_t> all;
    for (const auto& b : branches)
      all.insert(all.end(), b.begin(), b.end());
    std::sort(all.begin(), all.end());
    return all;
  };
  std::vector<std::size_t> used = flatten();
  const std::size_t candidates = used.size();
  // Trim the branch ends while the fixed-slope law misses a point by more than max_deviation.
  while (used.size() > options.min_points) {
    const Estimate e = estimate(points, used, law);
    if (e.max_relative_deviation <= options.max_deviation) break;
    double worst = -1.0;
    std::size_t worst_branch = 0;
    bool worst_front = true;
    for (std::size_t b = 0; b < branches.size(); ++b) {
      if (branches[b].empty()) continue;
      for (bool front : {true, false}) {
        const std::size_t i = front ? branches[b].front() : branches[b].back();
        const double dev = std::abs(std::expm1(log_term(points[i], law) - e.mean));
        if (dev > worst) {
          worst = dev;
          worst_branch = b;
          worst_front = front;
        }
      }
    }
    auto& br = branches[worst_branch];
    if (worst_front) {
      br.erase(br.begin());
    } else {
      br.pop_back();
    }
    used = flatten();
  }
  if (trimmed != nullptr) *trimmed = candidates - used.size();
  if (used.size() < options.min_points) used.clear();
  return used;
}

RegimeTwoFit fit_regime_two(std::span<const ScalingPoint> points,
                            const RegimeTwoFitOptions& options) {
  options.validate();
  check_points(points);
  RegimeTwoFit fit;
  fit.window_automatic = !options.window.has_value();
  if (options.window) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double x = points[i].a_over_bcore0;
      if (x >= options.window->first && x <= options.window->second && !points[i].lower_bound)
        fit.used.push_back(i);
    }
  } else {
    fit.used = automatic_window(points, options.automatic, &fit.trimmed, options.law);
  }
  fit.points = fit.used.size();
  if (fit.used.size() < 2) {
    fit.reason = fit.window_automatic
                     ? "fewer than min_points points past the Regime I crossover and before the "
                       "Regime III upturn"
                     : "fewer than 2 points in the given window";
    return fit;
  }
  const RegimeTwoLaw& law = options.law;
  const Estimate e = estimate(points, fit.used, law);
  std::vector<double> terms;
  fit.window_lo = points[fit.used.front()].a_over_bcore0;
  fit.window_hi = fit.window_lo;
  for (std::size_t i : fit.used) {
    terms.push_back(log_term(points[i], law));
    fit.window_lo = std::min(fit.window_lo, points[i].a_over_bcore0);
    fit.window_hi = std::max(fit.window_hi, points[i].a_over_bcore0);
  }
  const double n = static_cast<double>(terms.size());
  const double se_boot = bootstrap_se_of_mean(terms, options.bootstrap_samples, options.seed);
  fit.dof = n - 1.0;
  fit.t_factor = t_factor(fit.dof);
  const double err_mean = se_boot * std::sqrt(n / (n - 1.0)) * fit.t_factor;
  const double k = law.inverse_exponent;  // c0 = exp(k ln-term mean) / 2
  fit.c0 = 0.5 * std::exp(k * e.mean);
  fit.c0_se_bootstrap = k * fit.c0 * se_boot;
  fit.c0_error = k * fit.c0 * err_mean;
  fit.c0_lo = 0.5 * std::exp(k * (e.mean - 2.0 * err_mean));
  fit.c0_hi = 0.5 * std::exp(k * (e.mean + 2.0 * err_mean));
  fit.prefactor = law.prefactor * std::exp(e.mean);
  fit.prefactor_error = fit.prefactor * err_mean;
  fit.max_relative_deviation = e.max_relative_deviation;
  fit.within_max_deviation = e.max_relative_deviation <= options.automatic.max_deviation;
  fit.rms_log_residual = e.rms_log_residual;
  // Checks of the fixed slope over the window. Free slope: ln(mu/alpha) = A + s ln(a/b_core^0)
  // by least squares, s with its reported error (t_factor(n - 2)); a fixed-slope fit is only
  // as good as s is near -2/3. Halves: c0 of the lower and the upper half in a / b_core^0 (the
  // middle point in both when n is odd); their half difference is the spread of c0 over the
  // window, which the bootstrap, resampling points as if the scatter were random, leaves out.
  if (fit.used.size() >= 3) {
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    for (std::size_t i : fit.used) {
      const double x = std::log(points[i].a_over_bcore0), y = std::log(points[i].mu_over_alpha);
      sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    const double sxx_c = sxx - sx * sx / n;
    if (sxx_c > 0.0) {
      fit.free_slope = (sxy - sx * sy / n) / sxx_c;
      const double intercept = (sy - fit.free_slope * sx) / n;
      double ss = 0.0;
      for (std::size_t i : fit.used) {
        const double r = std::log(points[i].mu_over_alpha) - intercept -
                         fit.free_slope * std::log(points[i].a_over_bcore0);
        ss += r * r;
      }
      fit.free_slope_error = std::sqrt(ss / (n - 2.0) / sxx_c) * t_factor(n - 2.0);
    }
    std::vector<std::size_t> sorted = fit.used;
    std::sort(sorted.begin(), sorted.end(), [&](std::size_t i, std::size_t j) {
      return points[i].a_over_bcore0 < points[j].a_over_bcore0;
    });
    const std::size_t half = (sorted.size() + 1) / 2;
    const std::vector<std::size_t> lower(sorted.begin(), sorted.begin() + half),
        upper(sorted.end() - half, sorted.end());
    fit.c0_lower_half = 0.5 * std::exp(k * estimate(points, lower, law).mean);
    fit.c0_upper_half = 0.5 * std::exp(k * estimate(points, upper, law).mean);
    fit.c0_window_spread = 0.5 * std::abs(fit.c0_upper_half - fit.c0_lower_half);
  }
  fit.valid = true;
  return fit;
}

bool rises_past(double mu_over_alpha, double lowest, double rise_tolerance) {
  return mu_over_alpha > lowest * (1.0 + rise_tolerance);
}

NucleationSolution nucleation_condition(double a_over_bcore0, double c0) {
  require_positive("nucleation_condition.a_over_bcore0", a_over_bcore0);
  require_positive("nucleation_condition.c0", c0);
  NucleationSolution s;
  const double q = c0 / a_over_bcore0;
  if (q >= 1.0) {
    s.bonded_mu_over_alpha = 3.0;
    return s;
  }
  // g(x) = (1 - x) sqrt(1 - x^2) falls monotonically from 1 to 0 on [0, 1]: bisection to
  // round-off (the root moves towards the edge as q -> 0, where g ~ sqrt(2) (1 - x)^(3/2)).
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
    const double x = 0.5 * (lo + hi);
    const double g = (1.0 - x) * std::sqrt((1.0 - x) * (1.0 + x));
    (g > q ? lo : hi) = x;
  }
  s.x = 0.5 * (lo + hi);
  s.bonded_mu_over_alpha = 3.0 * (1.0 - s.x) * (1.0 + s.x);
  s.rigid = s.bonded_mu_over_alpha >= 1.0;
  s.mu_over_alpha = std::min(1.0, s.bonded_mu_over_alpha);
  return s;
}

NucleationSolution nucleation_condition(const RegimeTwoLaw& law, double a_over_bcore0, double c0) {
  if (law.kind == RegimeTwoLaw::Kind::hertz) return nucleation_condition(a_over_bcore0, c0);
  require_positive("nucleation_condition.a_over_bcore0", a_over_bcore0);
  require_positive("nucleation_condition.c0", c0);
  NucleationSolution s;
  // The site at the distance c0 b_core from the edge, the same core width everywhere.
  const double q = c0 / a_over_bcore0;
  if (q >= 1.0) {
    s.bonded_mu_over_alpha = 2.0;
    return s;
  }
  s.x = 1.0 - q;
  s.bonded_mu_over_alpha = 2.0 * std::sqrt(q * (2.0 - q));
  s.rigid = s.bonded_mu_over_alpha >= 1.0;
  s.mu_over_alpha = std::min(1.0, s.bonded_mu_over_alpha);
  return s;
}

NucleationSolution mixed_nucleation_condition(double x_adhesive, double x_hertz, double c0) {
  if (!(x_adhesive >= 0.0) || !(x_hertz >= 0.0) || !(x_adhesive + x_hertz > 0.0) ||
      !std::isfinite(x_adhesive + x_hertz)) {
    reject("mixed_nucleation_condition.x_adhesive + x_hertz",
           std::to_string(x_adhesive) + " + " + std::to_string(x_hertz), "each >= 0, sum > 0");
  }
  require_positive("mixed_nucleation_condition.c0", c0);
  const double xa = x_adhesive, xh = x_hertz;
  const auto friction = [&](double w) { return 2.0 * w * (xa + xh * w) / (xa + 2.0 * xh / 3.0); };
  NucleationSolution s;
  if (c0 >= xa + xh) {
    s.bonded_mu_over_alpha = friction(1.0);
    return s;
  }
  // g(x) = (1 - x)(x_A + x_H sqrt(1 - x^2)) falls monotonically from x_A + x_H to 0 on [0, 1].
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
    const double x = 0.5 * (lo + hi);
    const double g = (1.0 - x) * (xa + xh * std::sqrt((1.0 - x) * (1.0 + x)));
    (g > c0 ? lo : hi) = x;
  }
  s.x = 0.5 * (lo + hi);
  s.bonded_mu_over_alpha = friction(std::sqrt((1.0 - s.x) * (1.0 + s.x)));
  s.rigid = s.bonded_mu_over_alpha >= 1.0;
  s.mu_over_alpha = std::min(1.0, s.bonded_mu_over_alpha);
  return s;
}

double regime_one_crossover(const RegimeTwoLaw& law, double c0) {
  if (law.kind == RegimeTwoLaw::Kind::hertz) return regime_one_crossover(c0);
  require_positive("regime_one_crossover.c0", c0);
  // 2 sqrt(q (2 - q)) = 1 at q = 1 - sqrt(3)/2.
  return c0 / (1.0 - 0.5 * std::sqrt(3.0));
}

double regime_one_crossover(double c0) {
  require_positive("regime_one_crossover.c0", c0);
  // 3 (1 - x^2) = 1 at x = sqrt(2/3), where (1 - x) sqrt(1 - x^2) = (1 - sqrt(2/3)) / sqrt(3).
  return c0 * std::sqrt(3.0) / (1.0 - std::sqrt(2.0 / 3.0));
}

}  // namespace asperity::nucleation
