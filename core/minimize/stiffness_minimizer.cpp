// Preconditioned L-BFGS with slope-only line searches; see stiffness_minimizer.hpp.
#include "asperity/core/minimize/stiffness_minimizer.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <stdexcept>
#include <string>

#include "asperity/core/common/validate.hpp"

namespace asperity::minimize {

const settings::Table<StiffnessOptions>& StiffnessOptions::settings() {
  using R = settings::Range;
  using O = StiffnessOptions;
  static const settings::Table<O> table = {
      settings::integer<O>(
          "max_iterations", [](auto& o) -> auto& { return o.max_iterations; },
          R::closed(1, 100000000), "", "iterations per minimisation"),
      settings::integer<O>(
          "memory", [](auto& o) -> auto& { return o.memory; }, R::closed(1, 100), "",
          "L-BFGS pairs kept"),
      settings::number<O>(
          "max_displacement", [](auto& o) -> auto& { return o.max_displacement; },
          R::open_closed(0.0, 1.0), "d", "largest displacement of a site in one iteration"),
      settings::integer<O>(
          "refresh_interval", [](auto& o) -> auto& { return o.refresh_interval; }, R::at_least(1),
          "", "recompute K u every this many iterations (drift)"),
      settings::integer<O>(
          "stall_window", [](auto& o) -> auto& { return o.stall_window; }, R::at_least(10), "",
          "stalled when the best residual has not fallen by 1% over this many iterations")};
  return table;
}

void StiffnessOptions::validate() const {
  settings::validate(*this, settings());
  if (!(force_tolerance >= 0.0) || !std::isfinite(force_tolerance)) {
    throw std::invalid_argument("StiffnessOptions.force_tolerance: got " +
                                std::to_string(force_tolerance) + ", allowed: finite and >= 0");
  }
  if (!(stall_band >= 1.0))
    reject("StiffnessOptions.stall_band", std::to_string(stall_band), ">= 1");
}

namespace {

double dot(std::span<const double> a, std::span<const double> b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i)
    s += a[i] * b[i];
  return s;
}

double max_abs(std::span<const double> a) {
  double m = 0.0;
  for (double v : a) {
    if (!std::isfinite(v)) return std::numeric_limits<double>::infinity();
    m = std::max(m, std::abs(v));
  }
  return m;
}

struct Pair {
  std::vector<double> s, y;
  double rho = 0.0;
};

}  // namespace

StiffnessResult minimize_stiffness(StiffnessProblem& problem, std::span<const double> f_ext,
                                   std::vector<double>& u, const StiffnessOptions& options,
                                   const StiffnessObserver& observer) {
  options.validate();
  const std::size_t n = problem.size();
  if (u.size() != n || f_ext.size() != n) {
    throw std::invalid_argument("minimize_stiffness: u has " + std::to_string(u.size()) +
                                " and f_ext " + std::to_string(f_ext.size()) +
                                " entries; the problem has " + std::to_string(n));
  }
  StiffnessResult result;
  std::vector<double> Ku(n), f_int(n), g(n), d(n), Kd(n), ut(n), gt(n), q(n), z(n);
  const auto gradient = [&](std::span<const double> x, std::span<const double> Kx, double t,
                            std::span<const double> Kdir, std::span<double> out) {
    problem.interface_force(x, f_int);
    ++result.interface_evaluations;
    for (std::size_t i = 0; i < n; ++i)
      out[i] = Kx[i] + t * Kdir[i] - f_int[i] - f_ext[i];
  };
  const auto refresh = [&] {
    problem.stiffness(u, Ku);
    ++result.stiffness_applications;
    gradient(u, Ku, 0.0, Ku, g);
  };
  refresh();

  std::deque<Pair> memory;
  double best = std::numeric_limits<double>::infinity();
  double window_best = best;
  int window_start = 0;
  // Strong Wolfe curvature parameter: a step is accepted once |phi'(t)| <= c2 |phi'(0)|.
  constexpr double c2 = 0.9;
  constexpr int max_line_steps = 30;

  for (int it = 0;; ++it) {
    const double gmax = max_abs(g);
    result.max_force = gmax;
    result.iterations = it;
    if (!std::isfinite(gmax)) {
      result.termination = Termination::diverged;
      break;
    }
    best = std::min(best, gmax);
    result.best_max_force = best;
    if (gmax <= options.force_tolerance) {
      result.termination = Termination::converged;
      break;
    }
    if (best < 0.99 * window_best) {
      window_best = best;
      window_start = it;
    } else if (it - window_start >= options.stall_window && gmax <= options.stall_band * best) {
      result.termination = Termination::stalled;
      break;
    }
    if (it >= options.max_iterations) {
      result.termination = Termination::max_iterations;
      break;
    }
    if (observer && observer(it, u)) {
      result.termination = Termination::interrupted;
      break;
    }
    if (it > 0 && it % options.refresh_interval == 0) refresh();

    // Two-loop recursion with H0 = P (one preconditioner application).
    for (std::size_t i = 0; i < n; ++i)
      q[i] = -g[i];
    std::vector<double> alpha(memory.size());
    for (std::size_t k = memory.size(); k-- > 0;) {
      alpha[k] = memory[k].rho * dot(memory[k].s, q);
      for (std::size_t i = 0; i < n; ++i)
        q[i] -= alpha[k] * memory[k].y[i];
    }
    problem.precondition(q, d);
    ++result.stiffness_applications;
    for (std::size_t k = 0; k < memory.size(); ++k) {
      const double beta = memory[k].rho * dot(memory[k].y, d);
      for (std::size_t i = 0; i < n; ++i)
        d[i] += memory[k].s[i] * (alpha[k] - beta);
    }
    double phi0 = dot(g, d);
    if (!(phi0 < 0.0)) {
      // Not a descent direction (curvature pairs gone stale): restart from P(-g).
      memory.clear();
      for (std::size_t i = 0; i < n; ++i)
        q[i] = -g[i];
      problem.precondition(q, d);
      ++result.stiffness_applications;
      phi0 = dot(g, d);
      if (!(phi0 < 0.0)) {
        result.termination = Termination::stalled;
        break;
      }
    }
    problem.stiffness(d, Kd);
    ++result.stiffness_applications;

    const double dmax = problem.max_site_norm(d);
    const double t_cap = dmax > 0.0 ? options.max_displacement / dmax : 1.0;
    double t = std::min(1.0, t_cap);
    double lo = 0.0, slope_lo = phi0;
    double hi = std::numeric_limits<double>::infinity(), slope_hi = 0.0;
    bool accepted = false;
    for (int ls = 0; ls < max_line_steps; ++ls) {
      for (std::size_t i = 0; i < n; ++i)
        ut[i] = u[i] + t * d[i];
      gradient(ut, Ku, t, Kd, gt);
      const double slope = dot(gt, d);
      if (!std::isfinite(slope)) {
        hi = t;
        slope_hi = std::abs(phi0);
        t = 0.5 * (lo + hi);
        continue;
      }
      if (std::abs(slope) <= c2 * std::abs(phi0) || (slope < 0.0 && t >= t_cap)) {
        accepted = true;
        break;
      }
      if (slope < 0.0) {
        lo = t;
        slope_lo = slope;
      } else {
        hi = t;
        slope_hi = slope;
      }
      if (std::isinf(hi)) {
        t = std::min(t_cap, 4.0 * t);
      } else {
        // Secant on the slope, kept inside the middle 80% of the bracket.
        const double secant = lo - slope_lo * (hi - lo) / (slope_hi - slope_lo);
        const double margin = 0.1 * (hi - lo);
        t = std::clamp(secant, lo + margin, hi - margin);
      }
    }
    if (!accepted) {
      if (lo <= 0.0) {
        // No point with a negative slope beyond 0: the direction is useless; restart.
        if (memory.empty()) {
          result.termination = Termination::stalled;
          break;
        }
        memory.clear();
        continue;
      }
      t = lo;  // the slope was negative all the way to lo: the energy fell
      for (std::size_t i = 0; i < n; ++i)
        ut[i] = u[i] + t * d[i];
      gradient(ut, Ku, t, Kd, gt);
    }

    Pair p;
    p.s.resize(n);
    p.y.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      p.s[i] = t * d[i];
      p.y[i] = gt[i] - g[i];
      u[i] = ut[i];
      Ku[i] += t * Kd[i];
    }
    g.swap(gt);
    const double sy = dot(p.s, p.y);
    if (sy > 0.0) {
      p.rho = 1.0 / sy;
      memory.push_back(std::move(p));
      if (memory.size() > static_cast<std::size_t>(options.memory)) memory.pop_front();
    }
  }
  return result;
}

}  // namespace asperity::minimize
