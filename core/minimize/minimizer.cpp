// Minimisers of SOLVERS.md in the pair representation; see minimizer.hpp for the methods.
#include "minimize/minimizer.hpp"

#include "common/parallel.hpp"
#include "common/validate.hpp"
#include "solve/newton_krylov.hpp"

#include <Spectra/SymEigsSolver.h>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <limits>
#include <random>
#include <stdexcept>

namespace asperity::minimize {

namespace {

// Vector kernels through Eigen maps: its reductions are vectorised and unrolled, which plain
// loops are not without reassociation (these passes are a fifth of a large slide's time).
Eigen::Map<const Eigen::VectorXd> view(std::span<const double> a) {
  return {a.data(), static_cast<Eigen::Index>(a.size())};
}
Eigen::Map<Eigen::VectorXd> view(std::span<double> a) {
  return {a.data(), static_cast<Eigen::Index>(a.size())};
}

double dot(std::span<const double> a, std::span<const double> b) {
  return view(a).dot(view(b));
}

// Threads for the element-wise passes of the minimisation running on this thread: set by
// minimize() from Problem::threads() for its duration (a thread of its own per caller, so
// minimisations on different threads do not share it). Dot products stay serial (par::).
thread_local int pass_threads = 1;

class PassThreads {
 public:
  explicit PassThreads(int threads) : saved_(pass_threads) { pass_threads = std::max(1, threads); }
  ~PassThreads() { pass_threads = saved_; }
  PassThreads(const PassThreads&) = delete;
  PassThreads& operator=(const PassThreads&) = delete;

 private:
  int saved_;
};

// f(i) for every i in [0, n), on the pass threads.
template <class F>
void each(std::size_t n, F&& f) {
  par::for_ranges(n, pass_threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      f(i);
  });
}

// Largest |a_i|; a NaN anywhere is returned (Eigen's default maximum keeps whichever operand
// its comparison favours, so a NaN would show or not depending on where the ranges split).
double max_abs(std::span<const double> a) {
  if (a.empty()) return 0.0;
  return par::max_over_ranges(a.size(), pass_threads, [&](std::size_t b, std::size_t e) {
    return view(a.subspan(b, e - b)).cwiseAbs().maxCoeff<Eigen::PropagateNaN>();
  });
}

// x = a + t b
void axpy_into(std::span<double> x, std::span<const double> a, double t,
               std::span<const double> b) {
  par::for_ranges(x.size(), pass_threads, [&](std::size_t i, std::size_t e) {
    view(x.subspan(i, e - i)) = view(a.subspan(i, e - i)) + t * view(b.subspan(i, e - i));
  });
}

// x += t b
void axpy(std::span<double> x, double t, std::span<const double> b) {
  par::for_ranges(x.size(), pass_threads, [&](std::size_t i, std::size_t e) {
    view(x.subspan(i, e - i)) += t * view(b.subspan(i, e - i));
  });
}

// x *= t
void scale(std::span<double> x, double t) {
  par::for_ranges(x.size(), pass_threads,
                  [&](std::size_t i, std::size_t e) { view(x.subspan(i, e - i)) *= t; });
}

// Energy and gradient at a pair, with the bookkeeping of evaluations.
class Evaluator {
 public:
  explicit Evaluator(Problem& p) : p_(p), fint_(p.size()) {}

  double operator()(std::span<const double> u, std::span<const double> f, std::span<double> r) {
    const double v = p_.interface(u, fint_);
    each(r.size(), [&](std::size_t i) { r[i] = f[i] - fint_[i]; });
    ++evaluations;
    return 0.5 * dot(f, u) + v;
  }

  std::size_t evaluations = 0;

 private:
  Problem& p_;
  std::vector<double> fint_;
};

// Energies of a whole contact are resolved only to round-off: a rise below this is noise, and
// the derivative conditions decide (SOLVERS.md: slopes, not energy differences).
double energy_slack(double e) {
  return 1e-12 * std::max(1.0, std::abs(e));
}

struct Point {
  std::vector<double> u, f, r;
  double e = 0.0;
};

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

// A = G + G H G, the Hessian K + H in force coordinates (congruent, same inertia).
class HessianOp {
 public:
  using Scalar = double;
  HessianOp(Problem& p, std::span<const double> h) : p_(&p), h_(h), z_(p.size()), t_(p.size()) {}
  [[nodiscard]] Eigen::Index rows() const { return static_cast<Eigen::Index>(h_.size()); }
  [[nodiscard]] Eigen::Index cols() const { return rows(); }
  void perform_op(const double* x, double* y) const {
    const std::size_t n = h_.size();
    p_->compliance({x, n}, z_);
    for (std::size_t i = 0; i < n; ++i)
      t_[i] = h_[i] * z_[i];
    p_->compliance(t_, {y, n});
    for (std::size_t i = 0; i < n; ++i)
      y[i] += z_[i];
  }

 private:
  Problem* p_;
  std::span<const double> h_;
  mutable std::vector<double> z_, t_;
};

// Newton-Krylov on F(f) = f - f_int(G f): the unknowns are the forces, so the pair stays
// consistent (u = G f). J v = v + H_int (G v). Returns true if it converged (x is then updated).
bool newton_finish(Problem& problem, Point& x, const MinimizerOptions& options) {
  const std::size_t n = x.f.size();
  std::vector<double> f = x.f, u(n), fint(n), h(n), gv(n), at(n);
  bool have_h = false;
  const auto residual = [&](std::span<const double> fin, std::span<double> F) {
    problem.compliance(fin, u);
    problem.interface(u, fint);
    for (std::size_t i = 0; i < n; ++i)
      F[i] = fin[i] - fint[i];
  };
  const auto jtimes = [&](std::span<const double> fin, std::span<const double> v,
                          std::span<double> jv) {
    if (!have_h || !std::equal(fin.begin(), fin.end(), at.begin())) {  // new Newton iterate
      problem.compliance(fin, u);
      problem.curvature(u, h);
      std::copy(fin.begin(), fin.end(), at.begin());
      have_h = true;
    }
    problem.compliance(v, gv);
    for (std::size_t i = 0; i < n; ++i)
      jv[i] = v[i] + h[i] * gv[i];
  };
  const auto r = solve::newton_krylov(f, residual, jtimes,
                                      {.tolerance = options.force_tolerance, .max_iterations = 30});
  if (r.termination != Termination::converged) return false;
  x.f = std::move(f);
  problem.compliance(x.f, x.u);
  return true;
}

// The overdamped flow du/dt = -G r, df/dt = -r (the pair stays exact; minimizer.hpp), or with
// the interface filter as part of the mobility, du/dt = -G M r, df/dt = -M r (the flow in the
// metric K + c of the filter: long wavelengths of a pinned contact move slower; not the
// reference, a candidate for production that the path tier holds to it). Integrated under error
// control by one of two schemes:
// - euler: explicit Euler with the ODE12r estimate e = h/2 |F(new) - F(old)|; one mobility
//   application per step. Its step is bounded by the fastest mode: the spectral radius rho of
//   the Jacobian is about 140 at a = 46 d, R = 100 d in the G metric (the collective mode of the
//   pinned contact, rho ~ 0.6 a 2 pi tau_max), so steps of about 0.01 for a slip of duration 1000.
// - rkc: the second-order Runge-Kutta-Chebyshev method (Sommeijer, Shampine & Verwer, J. Comput.
//   Appl. Math. 88, 315, 1997), damping 2/13, with s stages chosen so that h rho <= 0.653 s^2:
//   the spectrum of the Jacobian is real (the mobility is self-adjoint, nearly so with the
//   filter), so s ~ sqrt(h rho) mobility applications buy a step limited by accuracy alone. rho
//   is estimated by power iteration in force space on w -> P (w + H G w) (P = I, or M with the
//   filter: the Jacobian of df/dt) every 25 steps and after a rejection, with a margin of 1.2.
//   Local error (their eq. 2.14): (12 (y_n - y_n+1) + 6 h (F_n + F_n+1)) / 15.
// Both accept a step only if its local error (largest displacement of a site, d) is within the
// tolerance. rkc also rejects a step that raises the energy (the flow descends); euler instead
// requires that the energy still falls at the end of the step (r_new . G P r >= 0), which also
// keeps it below its stability limit near a minimum (rkc damps there by construction). euler
// caps a step's largest displacement at max_displacement; rkc does not: its error control bounds
// a step.
class Flow {
 public:
  enum class Outcome { accepted, rejected, stationary, failed };

  Flow(Problem& p, Evaluator& eval, const MinimizerOptions& o, std::size_t n, bool filter,
       MinimizeResult& res)
      : p_(p),
        eval_(eval),
        o_(o),
        res_(res),
        filter_(filter),
        Fu_(n),
        Ff_(n),
        Fu_new_(n),
        Ff_new_(n),
        y1u_(n),
        y1f_(n),
        y2u_(n),
        y2f_(n),
        gu_(n),
        gf_(n),
        h_(n),
        v_(n),
        w_(n),
        z_(n) {}

  void invalidate() { fresh_ = false; }

  // The integrator's state after an accepted step (FlowPause), and back.
  void save(FlowPause& out) const {
    out.velocity_u = Fu_, out.velocity_f = Ff_;
    out.step = step_, out.radius = radius_, out.since_estimate = since_estimate_;
    out.power = have_vector_ ? v_ : std::vector<double>{};
  }
  void restore(const FlowPause& in) {
    const std::size_t n = Fu_.size();
    const auto finite = [](const std::vector<double>& v) {
      return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
    };
    // A step or radius past 1e100 would overflow the stage count (int) of the next RKC step.
    if (in.velocity_u.size() != n || in.velocity_f.size() != n ||
        (!in.power.empty() && in.power.size() != n) || !(in.step > 0.0 && in.step < 1e100) ||
        !(in.radius >= 0.0 && in.radius < 1e100) || in.since_estimate < 0 ||
        !finite(in.velocity_u) || !finite(in.velocity_f) || !finite(in.power)) {
      throw std::invalid_argument(
          "minimize: the flow's pause does not fit this problem (its velocity and power vectors "
          "must have " +
          std::to_string(n) +
          " finite values, its step and spectral radius must be finite, the step > 0)");
    }
    Fu_ = in.velocity_u, Ff_ = in.velocity_f;
    step_ = in.step, radius_ = in.radius, since_estimate_ = in.since_estimate;
    rejected_last_ = false;  // a pause follows an accepted step
    have_vector_ = !in.power.empty();
    if (have_vector_) v_ = in.power;
    fresh_ = true;
  }

  Outcome step(Point& x, Point& trial) {
    if (!fresh_) {
      mobility(x.r, Fu_, Ff_);
      fresh_ = true;
    }
    const double pmax = max_abs(Fu_);
    if (!(pmax > 0.0)) return Outcome::stationary;
    // First step: the Euler error h^2/2 |d(G r)/dt| with d(G r)/dt ~ G r; at most 1, the
    // relaxation time of the half-space alone (flow time is dimensionless: G K = I), so that a
    // start near equilibrium does not begin with hundreds of stages.
    if (step_ <= 0.0) step_ = std::min(1.0, std::sqrt(2.0 * o_.flow_tolerance / pmax));
    return o_.flow_scheme == FlowScheme::euler ? euler(x, trial, pmax) : rkc(x, trial);
  }

 private:
  // The velocity at residual r is -(u_dot, f_dot) = (G P r, P r), P = I or M.
  void mobility(std::span<const double> r, std::vector<double>& u_dot, std::vector<double>& f_dot) {
    if (filter_) {
      p_.filter(r, f_dot);
      ++res_.filter_applications;
    } else {
      std::copy(r.begin(), r.end(), f_dot.begin());
    }
    p_.compliance(f_dot, u_dot);
  }

  Outcome euler(Point& x, Point& trial, double pmax) {
    const std::size_t n = Fu_.size();
    const double h = std::min(step_, o_.max_displacement / pmax);
    axpy_into(trial.u, x.u, -h, Fu_);
    axpy_into(trial.f, x.f, -h, Ff_);
    trial.e = eval_(trial.u, trial.f, trial.r);
    mobility(trial.r, Fu_new_, Ff_new_);  // the slope at the new point: the next step's, if kept
    double err = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      err = std::max(err, std::abs(Fu_new_[i] - Fu_[i]));
    err *= 0.5 * h;
    // A finite state with a non-finite energy or slope is a fault of the problem.
    if (!std::isfinite(trial.e) || !std::isfinite(err)) return Outcome::failed;
    const bool overshoot = dot(trial.r, Fu_) < 0.0;
    const bool accepted = err <= o_.flow_tolerance && !overshoot;
    const double factor = err > 0.0 ? 0.9 * std::sqrt(o_.flow_tolerance / err) : 4.0;
    if (!accepted) {
      ++res_.rejected_steps;
      step_ = h * std::clamp(overshoot ? std::min(factor, 0.5) : factor, 0.1, 0.5);
      rejected_last_ = true;
      if (step_ * pmax < 1e-14 * o_.flow_tolerance) return Outcome::failed;
      return Outcome::rejected;
    }
    // No growth right after a rejection: at the stability limit a rejected step followed by a
    // fourfold one wasted four steps in ten (a = 46 d, R = 100 d).
    step_ = h * std::clamp(factor, 0.2, rejected_last_ ? 1.0 : 2.0);
    rejected_last_ = false;
    std::swap(x, trial);
    std::swap(Fu_, Fu_new_);
    std::swap(Ff_, Ff_new_);
    return Outcome::accepted;
  }

  // Spectral radius of the Jacobian of df/dt, w -> P (w + H G w), by power iteration
  // warm-started from the last vector.
  void estimate_radius(const Point& x) {
    const std::size_t n = v_.size();
    p_.curvature(x.u, h_);
    if (!have_vector_) {
      for (std::size_t i = 0; i < n; ++i)
        v_[i] = 1.0 + 0.5 * std::sin(1.7 * static_cast<double>(i));  // not an eigenvector
      have_vector_ = true;
    }
    double est = 0.0;
    for (int k = 0; k < 10; ++k) {
      const double norm = std::sqrt(dot(v_, v_));
      if (!(norm > 0.0)) break;
      view(std::span<double>(v_)) /= norm;
      p_.compliance(v_, gu_);
      for (std::size_t i = 0; i < n; ++i)
        z_[i] = v_[i] + h_[i] * gu_[i];
      if (filter_) {
        p_.filter(z_, w_);
        ++res_.filter_applications;
      } else {
        std::swap(z_, w_);
      }
      const double next = std::sqrt(dot(w_, w_));
      std::swap(v_, w_);
      const bool settled = std::abs(next - est) <= 0.01 * next;
      est = next;
      if (settled && k >= 2) break;
    }
    radius_ = 1.2 * std::max(est, 1.0);
    since_estimate_ = 0;
  }

  Outcome rkc(Point& x, Point& trial) {
    const std::size_t n = Fu_.size();
    if (radius_ <= 0.0 || since_estimate_ >= 25) estimate_radius(x);
    constexpr int kMaxStages = 400;
    double h = step_;
    // Stages for stability: h rho <= 0.653 s^2 (damping 2/13).
    int s = 1 + static_cast<int>(std::sqrt(1.0 + 1.54 * h * radius_));
    if (s > kMaxStages) {
      s = kMaxStages;
      h = (static_cast<double>(s - 1) * (s - 1) - 1.0) / (1.54 * radius_);
    }
    s = std::max(s, 2);
    // Chebyshev coefficients (their section 2): T_j, T_j', T_j'' at w0.
    const double eps = 2.0 / 13.0;
    const double w0 = 1.0 + eps / (static_cast<double>(s) * s);
    const auto m = static_cast<std::size_t>(s) + 1;
    T_.assign(m, 0.0), dT_.assign(m, 0.0), ddT_.assign(m, 0.0), b_.assign(m, 0.0);
    T_[0] = 1.0, T_[1] = w0, dT_[1] = 1.0;
    for (std::size_t j = 2; j < m; ++j) {
      T_[j] = 2.0 * w0 * T_[j - 1] - T_[j - 2];
      dT_[j] = 2.0 * T_[j - 1] + 2.0 * w0 * dT_[j - 1] - dT_[j - 2];
      ddT_[j] = 4.0 * dT_[j - 1] + 2.0 * w0 * ddT_[j - 1] - ddT_[j - 2];
    }
    const double w1 = dT_[m - 1] / ddT_[m - 1];
    for (std::size_t j = 2; j < m; ++j)
      b_[j] = ddT_[j] / (dT_[j] * dT_[j]);
    b_[0] = b_[1] = b_[2];
    // Y0 = x, Y1 = Y0 + mu1~ h F0; then Y_j from Y_{j-1} (y1) and Y_{j-2} (y2) into trial.
    y2u_ = x.u, y2f_ = x.f;
    const double mt1 = b_[1] * w1;
    axpy_into(y1u_, x.u, -mt1 * h, Fu_);
    axpy_into(y1f_, x.f, -mt1 * h, Ff_);
    for (std::size_t j = 2; j < m; ++j) {
      eval_(y1u_, y1f_, trial.r);
      mobility(trial.r, gu_, gf_);  // -F(Y_{j-1})
      const double mu = 2.0 * b_[j] * w0 / b_[j - 1], nu = -b_[j] / b_[j - 2];
      const double mt = 2.0 * b_[j] * w1 / b_[j - 1], gt = -(1.0 - b_[j - 1] * T_[j - 1]) * mt;
      const double c0 = 1.0 - mu - nu;
      const auto c = [](const std::vector<double>& a) { return view(std::span<const double>(a)); };
      view(std::span<double>(trial.u)) =
          c0 * c(x.u) + mu * c(y1u_) + nu * c(y2u_) - (mt * h) * c(gu_) - (gt * h) * c(Fu_);
      view(std::span<double>(trial.f)) =
          c0 * c(x.f) + mu * c(y1f_) + nu * c(y2f_) - (mt * h) * c(gf_) - (gt * h) * c(Ff_);
      std::swap(y2u_, y1u_);
      std::swap(y2f_, y1f_);
      std::swap(y1u_, trial.u);
      std::swap(y1f_, trial.f);
    }
    std::swap(trial.u, y1u_);
    std::swap(trial.f, y1f_);
    trial.e = eval_(trial.u, trial.f, trial.r);
    mobility(trial.r, Fu_new_, Ff_new_);
    double err = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      // y_n - y_n+1 + h/2 (F_n + F_n+1), with F = -(G P r).
      err = std::max(err, std::abs(12.0 * (x.u[i] - trial.u[i]) - 6.0 * h * (Fu_[i] + Fu_new_[i])));
    }
    err /= 15.0;
    // A non-finite stage is most likely an underestimated spectral radius (the stages then grow
    // without bound): a rejected step, with rho estimated again.
    if (!std::isfinite(trial.e) || !std::isfinite(err)) err = 1e300;
    const bool rises = trial.e > x.e + energy_slack(x.e);
    const bool accepted = err <= o_.flow_tolerance && !rises;
    const double factor = err > 0.0 ? 0.8 * std::cbrt(o_.flow_tolerance / err) : 10.0;
    if (!accepted) {
      ++res_.rejected_steps;
      step_ = h * std::clamp(rises ? std::min(factor, 0.5) : factor, 0.1, 0.5);
      rejected_last_ = true;
      radius_ = 0.0;  // re-estimate: an underestimate shows as a rejected step
      if (step_ * max_abs(Fu_) < 1e-14 * o_.flow_tolerance) return Outcome::failed;
      return Outcome::rejected;
    }
    step_ = h * std::clamp(factor, 0.1, rejected_last_ ? 1.0 : 4.0);
    rejected_last_ = false;
    ++since_estimate_;
    std::swap(x, trial);
    std::swap(Fu_, Fu_new_);
    std::swap(Ff_, Ff_new_);
    return Outcome::accepted;
  }

  Problem& p_;
  Evaluator& eval_;
  const MinimizerOptions& o_;
  MinimizeResult& res_;
  bool filter_;
  // -F at x and at the trial: (G P r, P r).
  std::vector<double> Fu_, Ff_, Fu_new_, Ff_new_;
  std::vector<double> y1u_, y1f_, y2u_, y2f_, gu_, gf_;  // RKC stages
  std::vector<double> h_, v_, w_, z_;                    // power iteration
  std::vector<double> T_, dT_, ddT_, b_;                 // Chebyshev coefficients
  bool fresh_ = false, have_vector_ = false, rejected_last_ = false;
  double step_ = 0.0, radius_ = 0.0;
  int since_estimate_ = 0;
};

}  // namespace

std::string to_string(Method m) {
  switch (m) {
    case Method::lbfgs:
      return "lbfgs";
    case Method::cg:
      return "cg";
    case Method::fire:
      return "fire";
    case Method::newton:
      return "newton";
    case Method::flow:
      return "flow";
  }
  return "lbfgs";
}

std::string to_string(FlowScheme s) {
  return s == FlowScheme::euler ? "euler" : "rkc";
}

FlowScheme flow_scheme_from_string(const std::string& name) {
  if (name == "rkc") return FlowScheme::rkc;
  if (name == "euler") return FlowScheme::euler;
  throw std::invalid_argument("flow scheme: got '" + name + "', allowed: rkc, euler");
}

std::string to_string(StabilityCheck c) {
  switch (c) {
    case StabilityCheck::none:
      return "none";
    case StabilityCheck::perturb:
      return "perturb";
    case StabilityCheck::lanczos:
      return "lanczos";
  }
  return "perturb";
}

StabilityCheck stability_from_string(const std::string& name) {
  if (name == "none") return StabilityCheck::none;
  if (name == "perturb") return StabilityCheck::perturb;
  if (name == "lanczos") return StabilityCheck::lanczos;
  throw std::invalid_argument("stability check: got '" + name +
                              "', allowed: none, perturb, lanczos");
}

std::string to_string(Preconditioner p) {
  switch (p) {
    case Preconditioner::elastic:
      return "elastic";
    case Preconditioner::interface:
      return "interface";
    case Preconditioner::automatic:
      return "auto";
  }
  return "auto";
}

Preconditioner preconditioner_from_string(const std::string& name) {
  if (name == "elastic") return Preconditioner::elastic;
  if (name == "interface") return Preconditioner::interface;
  if (name == "auto") return Preconditioner::automatic;
  throw std::invalid_argument("preconditioner: got '" + name +
                              "', allowed: auto, elastic, interface");
}

Method method_from_string(const std::string& name) {
  if (name == "lbfgs") return Method::lbfgs;
  if (name == "cg") return Method::cg;
  if (name == "fire") return Method::fire;
  if (name == "newton") return Method::newton;
  if (name == "flow") return Method::flow;
  throw std::invalid_argument("minimizer method: got '" + name +
                              "', allowed: lbfgs, cg, fire, newton, flow");
}

const settings::Table<MinimizerOptions>& MinimizerOptions::settings() {
  using R = settings::Range;
  using O = MinimizerOptions;
  static const settings::Table<O> table = {
      settings::choice<O>(
          "method", [](auto& o) -> auto& { return o.method; },
          {"lbfgs", "cg", "fire", "newton", "flow"}, [](Method m) { return to_string(m); },
          method_from_string,
          "lbfgs | cg (reference) | fire | newton (lbfgs + Newton-Krylov finish) | flow (the "
          "overdamped path: slow, faithful)",
          "--solver"),
      settings::number<O>(
          "tolerance", [](auto& o) -> auto& { return o.force_tolerance; }, R::open(0.0, 1.0),
          "G d^2", "largest residual force per site at convergence", "--tolerance"),
      settings::integer<O>(
          "max_iterations", [](auto& o) -> auto& { return o.max_iterations; }, R::at_least(1), "",
          "iterations per minimisation, escapes included"),
      settings::integer<O>(
          "memory", [](auto& o) -> auto& { return o.memory; }, R::closed(1, 100), "",
          "L-BFGS pairs kept"),
      settings::number<O>(
          "newton_start", [](auto& o) -> auto& { return o.newton_start; }, R::positive(), "G d^2",
          "newton: switch to Newton-Krylov below this residual"),
      settings::number<O>(
          "max_displacement", [](auto& o) -> auto& { return o.max_displacement; },
          R::open_closed(0.0, 0.5), "d",
          "largest displacement of a site in one iteration (half a period at most)"),
      settings::choice<O>(
          "preconditioner", [](auto& o) -> auto& { return o.preconditioner; },
          {"auto", "elastic", "interface"}, [](Preconditioner p) { return to_string(p); },
          preconditioner_from_string,
          "lbfgs, newton: auto (interface from a/b_core^0 = 10) | elastic (G) | interface (G "
          "with the interface filter)",
          "--preconditioner"),
      settings::integer<O>(
          "refresh_interval", [](auto& o) -> auto& { return o.refresh_interval; }, R::at_least(1),
          "", "recompute u = G f every this many iterations (drift)"),
      settings::choice<O>(
          "stability", [](auto& o) -> auto& { return o.stability; }, {"perturb", "lanczos", "none"},
          [](StabilityCheck c) { return to_string(c); }, stability_from_string,
          "check of converged states: perturb (push and relax) | lanczos | none"),
      settings::integer<O>(
          "max_escapes", [](auto& o) -> auto& { return o.max_escapes; }, R::at_least(0), "",
          "escapes from unstable states per minimisation"),
      settings::number<O>(
          "escape_displacement", [](auto& o) -> auto& { return o.escape_displacement; },
          R::positive(), "d", "largest displacement of the push off an unstable state"),
      settings::number<O>(
          "perturbation", [](auto& o) -> auto& { return o.perturbation; }, R::positive(), "d",
          "largest displacement of the random push of the perturb check"),
      settings::number<O>(
          "flow_tolerance", [](auto& o) -> auto& { return o.flow_tolerance; },
          R::open_closed(0.0, 1.0), "d",
          "flow: largest local error of one step, as a displacement of a site", "--flow-tolerance"),
      settings::choice<O>(
          "flow_scheme", [](auto& o) -> auto& { return o.flow_scheme; }, {"rkc", "euler"},
          [](FlowScheme f) { return to_string(f); }, flow_scheme_from_string,
          "flow: the integrator, rkc (stabilised Runge-Kutta-Chebyshev) | euler"),
      settings::boolean<O>(
          "curvature_reset", [](auto& o) -> auto& { return o.curvature_reset; },
          "lbfgs, newton: clear the pairs whenever a site changes the half of its well "
          "(experimental)")};
  return table;
}

void MinimizerOptions::validate() const {
  settings::validate(*this, settings());
}

Stability lowest_mode(Problem& problem, std::span<const double> u) {
  const std::size_t n = problem.size();
  const std::size_t gf0 = problem.gf_applications();
  std::vector<double> h(n);
  problem.curvature(u, h);
  HessianOp op(problem, h);
  Stability s;
  Eigen::VectorXd w;
  if (n <= 60) {  // small problems: the dense matrix, column by column
    Eigen::MatrixXd a(n, n);
    Eigen::VectorXd e = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
    for (std::size_t j = 0; j < n; ++j) {
      e.setZero();
      e(static_cast<Eigen::Index>(j)) = 1.0;
      op.perform_op(e.data(), a.col(static_cast<Eigen::Index>(j)).data());
    }
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (a + a.transpose()));
    s.lowest = es.eigenvalues()(0);
    w = es.eigenvectors().col(0);
    s.converged = true;
  } else {
    const auto ncv = static_cast<Eigen::Index>(std::min<std::size_t>(n, 30));
    Spectra::SymEigsSolver<HessianOp> eigs(op, 1, ncv);
    eigs.init();
    eigs.compute(Spectra::SortRule::SmallestAlge, 300, 1e-6, Spectra::SortRule::SmallestAlge);
    s.converged = eigs.info() == Spectra::CompInfo::Successful;
    if (eigs.eigenvalues().size() > 0) {
      s.lowest = eigs.eigenvalues()(0);
      w = eigs.eigenvectors().col(0);
    } else {
      s.lowest = std::numeric_limits<double>::quiet_NaN();
    }
  }
  if (w.size() == static_cast<Eigen::Index>(n)) {
    s.direction_f.assign(w.data(), w.data() + n);
    s.direction_u.resize(n);
    problem.compliance(s.direction_f, s.direction_u);
  }
  s.gf_applications = problem.gf_applications() - gf0;
  return s;
}

MinimizeResult minimize(Problem& problem, std::vector<double>& u, std::vector<double>& f,
                        const MinimizerOptions& options, const Observer& observer,
                        const FlowPause* resume, const FlowPauses* pauses) {
  options.validate();
  const std::size_t n = problem.size();
  if (u.size() != n || f.size() != n) {
    throw std::invalid_argument("minimize: the pair has " + std::to_string(u.size()) + " and " +
                                std::to_string(f.size()) + " values for " + std::to_string(n) +
                                " unknowns");
  }
  if (resume && (options.method != Method::flow || resume->u.size() != n || resume->f.size() != n ||
                 resume->iteration < 0 || resume->iteration > options.max_iterations)) {
    throw std::invalid_argument("minimize: a pause can only continue a flow relaxation (method " +
                                to_string(options.method) + ") of " + std::to_string(n) +
                                " unknowns within " + std::to_string(options.max_iterations) +
                                " iterations; it has " + std::to_string(resume->u.size()) +
                                " at iteration " + std::to_string(resume->iteration));
  }
  std::size_t gf0 = problem.gf_applications();
  MinimizeResult res;
  res.lowest_eigenvalue = std::numeric_limits<double>::quiet_NaN();
  const PassThreads pass_threads_guard(problem.threads());
  Evaluator eval(problem);
  Point x{resume ? resume->u : u, resume ? resume->f : f, std::vector<double>(n), 0.0};
  Point trial{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n), 0.0};
  // The energy and residual of the pair are those the paused run had (the same evaluation);
  // on resume they are not counted again.
  x.e = eval(x.u, x.f, x.r);

  // L-BFGS memory and the CG/FIRE state.
  struct Pair {
    std::vector<double> s, df, y;
    double rho;
  };
  std::deque<Pair> memory;
  // The storage of the next pair: the oldest pair's, once the memory is full, so that an
  // iteration allocates no vector (three of 13 MB each per iteration at a = 510 d).
  Pair spare;
  std::vector<double> du(n), df(n), q(n), z(n), alpha_coef;
  std::vector<std::uint8_t> unstable_half;  // curvature_reset: sites in the unstable half
  // H0 = G M with the interface filter M (quasi-Newton methods only: CG is the classic
  // reference, and FIRE's dynamics are defined by G).
  const bool quasi_newton = options.method == Method::lbfgs || options.method == Method::newton;
  const bool use_filter = quasi_newton && options.preconditioner != Preconditioner::elastic &&
                          problem.wants_filter(options.preconditioner == Preconditioner::automatic);
  res.filtered = use_filter;
  // After a failed line search the retry is plain G steepest descent, as without the filter:
  // G r . r > 0 always, whereas G M, not symmetric on the contact sites, only nearly so.
  bool plain_next = false;
  std::vector<double> w_filter(use_filter ? n : 0);
  // z = H0 v (one GF application); v becomes the K-image of z (v itself without the filter).
  const auto apply_h0 = [&](std::vector<double>& v, std::vector<double>& zout) {
    if (use_filter && !plain_next) {
      problem.filter(v, w_filter);
      ++res.filter_applications;
      problem.compliance(w_filter, zout);
      std::swap(v, w_filter);
    } else {
      problem.compliance(v, zout);
    }
  };
  std::vector<double> du_prev(n, 0.0), df_prev(n, 0.0), z_prev(n, 0.0), r_prev(n, 0.0);
  double rz_prev = 0.0;
  bool restart = true;
  // FIRE state.
  std::vector<double> vu(n, 0.0), vf(n, 0.0);
  double dt = 0.1, fire_alpha = 0.1;
  // The flow's mobility is G (the reference) unless the filter is asked for explicitly.
  const bool flow_filter = options.method == Method::flow &&
                           options.preconditioner == Preconditioner::interface &&
                           problem.wants_filter(false);
  if (flow_filter) res.filtered = true;
  Flow flow(problem, eval, options, options.method == Method::flow ? n : 0, flow_filter, res);
  if (resume) {
    flow.restore(*resume);
    res = resume->done;
    res.filtered = flow_filter;
    eval.evaluations = resume->done.interface_evaluations;
    gf0 -= resume->done.gf_applications;  // the work before the pause counts
  }
  int fire_positive = 0;
  constexpr double dt_max = 1.0, fire_alpha0 = 0.1;

  const auto finite = [](std::span<const double> a) {
    for (double v : a) {
      if (!std::isfinite(v)) return false;
    }
    return true;
  };

  bool newton_tried = false;
  int it = resume ? resume->iteration : 0;
  // Every exit from the loop sets its termination; running out of iterations leaves this one.
  res.termination = n == 0 ? Termination::converged : Termination::max_iterations;
  for (; n > 0 && it < options.max_iterations; ++it) {
    if (!std::isfinite(x.e) || !finite(x.r)) {
      res.termination = Termination::diverged;
      break;
    }
    res.max_force = max_abs(x.r);
    if (res.max_force <= options.force_tolerance) {
      if (options.stability == StabilityCheck::none) {
        res.termination = Termination::converged;
        break;
      }
      std::vector<double> h(n);
      problem.curvature(x.u, h);
      if (*std::min_element(h.begin(), h.end()) >= 0.0) {  // K + H_int > 0 trivially
        res.termination = Termination::converged;
        break;
      }
      res.stability_checked = true;
      bool unstable = false;
      bool use_push = options.stability == StabilityCheck::perturb;
      if (!use_push) {
        Stability st = lowest_mode(problem, x.u);
        res.lowest_eigenvalue = st.lowest;
        if (!st.converged || !std::isfinite(st.lowest) || st.direction_u.empty()) {
          use_push = true;  // Lanczos undecided: the push decides instead
        } else {
          // Scale of A: its Rayleigh quotient along the mode's own G-image is ~ |G|.
          const double scale =
              std::max(1e-300, dot(st.direction_u, st.direction_f) /
                                   std::max(1e-300, dot(st.direction_f, st.direction_f)));
          unstable = st.lowest < -1e-8 * scale;
          if (unstable) {
            // Leave the saddle along its unstable mode, on the side of lower energy.
            const double eta =
                options.escape_displacement / std::max(1e-300, max_abs(st.direction_u));
            double best_e = std::numeric_limits<double>::infinity();
            double best_sign = 1.0;
            for (double sign : {1.0, -1.0}) {
              axpy_into(trial.u, x.u, sign * eta, st.direction_u);
              axpy_into(trial.f, x.f, sign * eta, st.direction_f);
              const double e = eval(trial.u, trial.f, trial.r);
              if (e < best_e) best_e = e, best_sign = sign;
            }
            axpy_into(x.u, x.u, best_sign * eta, st.direction_u);
            axpy_into(x.f, x.f, best_sign * eta, st.direction_f);
            x.e = eval(x.u, x.f, x.r);
          }
        }
      }
      if (use_push) {
        // Push, relax without a check (on a budget of its own), and compare. A relaxation that
        // ends lower in energy than the state, converged or not, shows the state was not a
        // minimum: the lower state is kept and minimised on.
        std::mt19937 gen(static_cast<unsigned>(n + static_cast<std::size_t>(it)));
        std::uniform_real_distribution<double> dist(-1.0, 1.0);
        for (double& v : q)
          v = dist(gen);
        problem.compliance(q, z);
        // The push must also unbalance the state by more than the tolerance (10x), or the
        // relaxation after it would stop at once and the check would be blind at loose
        // tolerances: the residual it adds is about eta max|q|.
        const double eta = std::max(options.perturbation / std::max(1e-300, max_abs(z)),
                                    10.0 * options.force_tolerance / std::max(1e-300, max_abs(q)));
        const double pushed = eta * max_abs(z);  // largest displacement of the push (d)
        std::vector<double> pu(n), pf(n);
        axpy_into(pu, x.u, eta, z);
        axpy_into(pf, x.f, eta, q);
        MinimizerOptions inner = options;
        inner.stability = StabilityCheck::none;
        inner.max_iterations = std::min(options.max_iterations, 2000);
        const MinimizeResult again = minimize(problem, pu, pf, inner);
        it += again.iterations;
        eval.evaluations += again.interface_evaluations;
        res.filter_applications += again.filter_applications;
        double moved = 0.0;
        for (std::size_t i = 0; i < n; ++i)
          moved = std::max(moved, std::abs(pu[i] - x.u[i]));
        const bool lower = std::isfinite(again.energy) && again.energy < x.e - energy_slack(x.e);
        unstable = lower && (moved > 10.0 * pushed || again.termination != Termination::converged);
        if (unstable) {
          x.u = std::move(pu);
          x.f = std::move(pf);
          x.e = eval(x.u, x.f, x.r);
        }
      }
      if (!unstable) {
        res.termination = Termination::converged;
        break;
      }
      res.lowest_eigenvalue = std::numeric_limits<double>::quiet_NaN();  // of a state left
      if (++res.escapes > options.max_escapes) {
        res.termination = Termination::unstable;
        break;
      }
      memory.clear();
      restart = true;
      flow.invalidate();
      std::fill(vu.begin(), vu.end(), 0.0);
      std::fill(vf.begin(), vf.end(), 0.0);
      continue;
    }

    if (options.method == Method::newton && !newton_tried &&
        res.max_force <= std::max(options.newton_start, options.force_tolerance)) {
      newton_tried = true;
      if (newton_finish(problem, x, options)) {
        x.e = eval(x.u, x.f, x.r);
        memory.clear();
        restart = true;
        continue;  // converged: the check above (stability included) decides
      }
    }

    if (it > 0 && it % options.refresh_interval == 0) {  // remove drift of the pair
      problem.compliance(x.f, x.u);
      x.e = eval(x.u, x.f, x.r);
      flow.invalidate();
    }

    if (options.method == Method::flow) {
      // The reference path (minimizer.hpp): du/dt = -G r under error control.
      const auto outcome = flow.step(x, trial);
      if (outcome == Flow::Outcome::stationary) {
        res.termination = Termination::converged;  // r is numerically zero in the G metric
        break;
      }
      if (outcome == Flow::Outcome::failed) {
        res.termination = Termination::diverged;
        break;
      }
      if (outcome == Flow::Outcome::rejected) continue;
      if (observer && observer(it + 1, x.u, x.f)) {
        res.termination = Termination::interrupted;
        ++it;
        break;
      }
      if (pauses && pauses->due && pauses->due(it + 1)) {
        FlowPause here{.iteration = it + 1, .u = x.u, .f = x.f, .done = res};
        flow.save(here);
        here.done.iterations = it + 1;
        here.done.gf_applications = problem.gf_applications() - gf0;
        here.done.interface_evaluations = eval.evaluations;
        if (pauses->pause && pauses->pause(here)) {
          res.termination = Termination::interrupted;
          ++it;
          break;
        }
      }
      continue;
    }

    if (options.method == Method::fire) {
      // Preconditioned force: -G r in u, -r in f.
      problem.compliance(x.r, z);
      for (std::size_t i = 0; i < n; ++i)
        q[i] = -x.r[i];  // K-image of -z
      const double power = -dot(x.r, vu);
      if (power > 0.0) {
        const double vnorm = std::sqrt(std::max(0.0, dot(vu, vf)));
        const double fnorm = std::sqrt(std::max(1e-300, dot(z, x.r)));
        for (std::size_t i = 0; i < n; ++i) {
          vu[i] = (1.0 - fire_alpha) * vu[i] - fire_alpha * vnorm / fnorm * z[i];
          vf[i] = (1.0 - fire_alpha) * vf[i] + fire_alpha * vnorm / fnorm * q[i];
        }
        if (++fire_positive > 5) {
          dt = std::min(1.1 * dt, dt_max);
          fire_alpha *= 0.99;
        }
      } else {
        std::fill(vu.begin(), vu.end(), 0.0);
        std::fill(vf.begin(), vf.end(), 0.0);
        dt *= 0.5;
        fire_alpha = fire_alpha0;
        fire_positive = 0;
      }
      for (std::size_t i = 0; i < n; ++i) {
        vu[i] -= dt * z[i];
        vf[i] += dt * q[i];
      }
      const double cap =
          std::min(1.0, options.max_displacement / std::max(1e-300, dt * max_abs(vu)));
      axpy_into(trial.u, x.u, cap * dt, vu);
      axpy_into(trial.f, x.f, cap * dt, vf);
      trial.e = eval(trial.u, trial.f, trial.r);
      if (trial.e > x.e + energy_slack(x.e)) {  // no ascent: stop and restart slower
        std::fill(vu.begin(), vu.end(), 0.0);
        std::fill(vf.begin(), vf.end(), 0.0);
        dt *= 0.5;
        fire_alpha = fire_alpha0;
        fire_positive = 0;
        if (dt < 1e-8) {
          res.termination = Termination::diverged;
          break;
        }
        continue;
      }
      std::swap(x, trial);
      if (observer && observer(it + 1, x.u, x.f)) {
        res.termination = Termination::interrupted;
        ++it;
        break;
      }
      continue;
    }

    // Search direction (du, df) with df = K du.
    if (quasi_newton && !memory.empty()) {
      alpha_coef.assign(memory.size(), 0.0);
      for (std::size_t k = memory.size(); k-- > 0;) {
        // The newest pair reads r itself and writes q = r - alpha y in one pass: the same
        // values as copying r into q first (a + t b either way), without the copy.
        const bool newest_pair = k + 1 == memory.size();
        alpha_coef[k] = memory[k].rho * dot(memory[k].s, newest_pair ? x.r : q);
        if (newest_pair)
          axpy_into(q, x.r, -alpha_coef[k], memory[k].y);
        else
          axpy(q, -alpha_coef[k], memory[k].y);
      }
      apply_h0(q, z);
      std::vector<double>& zf = q;  // K-image of z, built in place
      // H0 = gamma G with gamma = s.K s / s.y of the newest pair: the elastic curvature along
      // the last step over the total one (free: K s is the stored force change). The interface
      // softens the problem as a state nears an instability, and unscaled G steps fell short.
      // With the filter, H0 = gamma G M: the same scale, measured rather than derived (M already
      // holds a uniform interface stiffness, so gamma then corrects for its difference from the
      // actual one; slides at a / b_core^0 = 20 to 64 ran at gamma 0.2 to 5).
      const Pair& newest = memory.back();
      const double gamma = std::clamp(dot(newest.s, newest.df) * newest.rho, 0.1, 10.0);
      // Built negated, so that z and zf become the direction (du, df) without a pass to negate
      // them: negation is exact and commutes with every product and sum here, so the result is
      // bit for bit -(the recursion's z), and c is the recursion's c.
      scale(z, -gamma);
      scale(zf, -gamma);
      for (std::size_t k = 0; k < memory.size(); ++k) {
        const double c = alpha_coef[k] + memory[k].rho * dot(memory[k].y, z);
        axpy(z, -c, memory[k].s);
        alpha_coef[k] = -c;  // zf's coefficient, applied below
      }
      // zf += -c_k df_k for every pair, in one pass over zf instead of one per pair (zf is not
      // read in the loop above): per element the same additions in the same order as pair by
      // pair, so bit for bit the same; blocks keep zf's block in cache across the pairs.
      par::for_ranges(n, pass_threads, [&](std::size_t b, std::size_t e) {
        constexpr std::size_t block = 2048;
        for (std::size_t i0 = b; i0 < e; i0 += block) {
          const std::size_t len = std::min(block, e - i0);
          const std::span<double> out(zf.data() + i0, len);
          for (std::size_t k = 0; k < memory.size(); ++k)  // a block: axpy stays on this thread
            axpy(out, alpha_coef[k], std::span<const double>(memory[k].df.data() + i0, len));
        }
      });
      std::swap(du, z);
      std::swap(df, zf);
    } else if (use_filter && !plain_next) {  // first step: filtered steepest descent
      q = x.r;
      apply_h0(q, z);
      each(n, [&](std::size_t i) {
        du[i] = -z[i];
        df[i] = -q[i];
      });
    } else {
      problem.compliance(x.r, z);
      const double rz = dot(x.r, z);
      double beta = 0.0;
      if (options.method == Method::cg && !restart && rz_prev > 0.0) {
        double num = 0.0;
        for (std::size_t i = 0; i < n; ++i)
          num += x.r[i] * (z[i] - z_prev[i]);
        beta = std::max(0.0, num / rz_prev);  // Polak-Ribiere+
      }
      each(n, [&](std::size_t i) {
        du[i] = -z[i] + beta * du_prev[i];
        df[i] = -x.r[i] + beta * df_prev[i];
      });
      if (options.method == Method::cg) z_prev = z;
      rz_prev = rz;
    }
    double d0 = dot(x.r, du);
    if (!(d0 < 0.0)) {  // not a descent direction: fall back to preconditioned steepest descent
      memory.clear();
      problem.compliance(x.r, z);  // G alone: G r . r > 0 whatever the filter does
      each(n, [&](std::size_t i) {
        du[i] = -z[i];
        df[i] = -x.r[i];
      });
      d0 = dot(x.r, du);
      z_prev = z;
      rz_prev = -d0;
      if (!(d0 < 0.0)) {
        res.termination = Termination::converged;  // r is numerically zero in the G metric
        break;
      }
    }
    const double t_max = options.max_displacement / std::max(1e-300, max_abs(du));
    const double c2 = options.method == Method::cg ? 0.1 : 0.9;
    const bool ls_ok =
        line_search(eval, x, du, df, d0, 1.0, t_max, c2, options.method == Method::cg, trial);
    if (!ls_ok) {
      // Retry once from G-preconditioned steepest descent.
      if (!memory.empty() || !restart || (use_filter && !plain_next)) {
        memory.clear();
        restart = true;
        plain_next = use_filter;
        continue;
      }
      res.termination = Termination::diverged;  // no descent left at this precision
      break;
    }
    restart = false;
    plain_next = false;
    if (options.method == Method::cg) {
      du_prev = du;  // CG continues from the direction, not the step
      df_prev = df;
    }
    if (quasi_newton) {
      // Store the step (s = du t, its K-image, y = dr).
      Pair& p = spare;
      p.s.resize(n);
      p.df.resize(n);
      p.y.resize(n);
      each(n, [&](std::size_t i) {
        p.s[i] = trial.u[i] - x.u[i];
        p.df[i] = trial.f[i] - x.f[i];
        p.y[i] = trial.r[i] - x.r[i];
      });
      const double sy = dot(p.s, p.y);
      if (sy > 1e-300) {  // keep only positive curvature
        p.rho = 1.0 / sy;
        memory.push_back(std::move(p));
        spare = Pair{};
        if (static_cast<int>(memory.size()) > options.memory) {
          spare = std::move(memory.front());
          memory.pop_front();
        }
      }
    }
    std::swap(x, trial);
    if (quasi_newton && options.curvature_reset) {
      // Experimental (issue 21): forget the pairs when a site enters or leaves the unstable half
      // of its well, so that no curvature measured before a site snapped steers the steps after.
      problem.curvature(x.u, z);
      bool changed = false;
      const bool first = unstable_half.size() != n;  // nothing to compare with yet
      if (first) unstable_half.assign(n, 0);
      for (std::size_t i = 0; i < n; ++i) {
        const std::uint8_t neg = z[i] < 0.0 ? 1 : 0;
        if (neg != unstable_half[i]) {
          unstable_half[i] = neg;
          changed = true;
        }
      }
      if (changed && !first) {
        memory.clear();
        ++res.memory_resets;
      }
    }
    if (observer && observer(it + 1, x.u, x.f)) {
      res.termination = Termination::interrupted;
      ++it;
      break;
    }
  }
  res.iterations = it;
  res.energy = x.e;
  res.max_force = max_abs(x.r);
  u = std::move(x.u);
  f = std::move(x.f);
  res.gf_applications = problem.gf_applications() - gf0;
  res.interface_evaluations = eval.evaluations;
  return res;
}

}  // namespace asperity::minimize
