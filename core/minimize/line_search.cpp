// Line searches of the line-search methods (lbfgs, newton, cg) and their steepest descent
// fallback, in the pair representation of SOLVERS.md ("Free-boundary contact"); see
// line_search.hpp.
#include "asperity/core/minimize/line_search.hpp"

#include <algorithm>
#include <cmath>

#include "asperity/core/minimize/kernels.hpp"

namespace asperity::minimize::detail {

namespace {

// Line search along (du, df) satisfying the strong Wolfe conditions on the slope, with the
// Armijo condition relaxed by the energy resolution (Nocedal & Wright, algorithms 3.5 and 3.6:
// bracketing by doubling up to t_max, then zoom by safeguarded secant steps on the slope).
// Returns false if no point with an energy within round-off of the start and a flatter slope
// was found.
bool line_search(Evaluator& eval, const Point& x, std::span<const double> du,
                 std::span<const double> df, double d0, double t_init, double t_max, double c2,
                 bool strong, Point& out) {
  constexpr double c1 = 1e-4;
  const double slack = energy_slack(x.e);
  // Fallback when the conditions cannot be met at this precision: of the points whose energy is
  // within round-off of the start, the one with the flattest slope (slopes stay accurate when
  // energy differences are lost).
  double best_t = 0.0, best_slope = std::abs(d0);
  const auto at = [&](double t, double& e, double& d) {
    axpy_into(out.u, x.u, t, du);
    axpy_into(out.f, x.f, t, df);
    e = out.e = eval(out.u, out.f, out.r);
    d = dot(out.r, du);
    if (e <= x.e + slack && std::abs(d) < best_slope) {
      best_slope = std::abs(d);
      best_t = t;
    }
  };
  const auto sufficient = [&](double t, double e) { return e <= x.e + c1 * t * d0 + slack; };
  // Strong Wolfe for CG (its conjugacy needs it); weak Wolfe for the quasi-Newton methods, whose
  // updates only need y.s > 0: an overshooting step that lowered the energy is kept instead of
  // being zoomed (2.5 evaluations per iteration fell to about one).
  const auto curvature_ok = [&](double d) {
    return strong ? std::abs(d) <= -c2 * d0 : d >= c2 * d0;
  };

  const auto zoom = [&](double lo, double e_lo, double d_lo, double hi, double d_hi) {
    for (int k = 0; k < 40; ++k) {
      const double a = std::min(lo, hi), b = std::max(lo, hi);
      if (b - a < 1e-14 * std::max(1.0, b)) return false;
      double t = d_hi != d_lo ? lo - d_lo * (hi - lo) / (d_hi - d_lo) : 0.5 * (a + b);
      const double margin = 0.1 * (b - a);
      if (!(t > a + margin && t < b - margin)) t = 0.5 * (a + b);
      double e = 0.0, d = 0.0;
      at(t, e, d);
      if (!sufficient(t, e) || e > e_lo + slack) {
        hi = t;
        d_hi = d;
      } else {
        if (curvature_ok(d)) return true;
        if (d * (hi - lo) >= 0.0) {
          hi = lo;
          d_hi = d_lo;
        }
        lo = t;
        e_lo = e;
        d_lo = d;
      }
    }
    return false;
  };

  double t_prev = 0.0, e_prev = x.e, d_prev = d0;
  double t = std::min(t_init, t_max);
  for (int k = 0; k < 60; ++k) {
    double e = 0.0, d = 0.0;
    at(t, e, d);
    if (!sufficient(t, e) || (k > 0 && e > e_prev + slack)) {
      if (zoom(t_prev, e_prev, d_prev, t, d)) return true;
      break;
    }
    if (curvature_ok(d)) return true;
    if (d >= 0.0) {
      if (zoom(t, e, d, t_prev, d_prev)) return true;
      break;
    }
    if (t >= t_max) return true;  // capped step: still a descent step
    t_prev = t, e_prev = e, d_prev = d;
    t = std::min(2.0 * t, t_max);
  }
  if (best_t > 0.0) {
    double e = 0.0, d = 0.0;
    at(best_t, e, d);
    return true;
  }
  return false;
}

}  // namespace

bool search_line(Relaxation& run, std::span<const double> du, std::span<const double> df, double d0,
                 double c2, bool strong) {
  const double t_max = run.options.max_displacement / std::max(1e-300, max_abs(du));
  return line_search(run.eval, run.x, du, df, d0, 1.0, t_max, c2, strong, run.trial);
}

double steepest_descent(Relaxation& run, std::vector<double>& z, std::vector<double>& du,
                        std::vector<double>& df) {
  const Point& x = run.x;
  run.problem.compliance(x.r, z);
  each(run.n, [&](std::size_t i) {
    du[i] = -z[i];
    df[i] = -x.r[i];
  });
  return dot(x.r, du);
}

}  // namespace asperity::minimize::detail
