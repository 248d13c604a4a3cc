// The flow method of minimizer.hpp: the reference path of MODEL.md section 5, the overdamped
// gradient flow in the pair representation of SOLVERS.md ("Free-boundary contact"), integrated
// under error control; a flow can pause after an accepted step and continue from the pause.
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "asperity/core/minimize/kernels.hpp"
#include "asperity/core/minimize/relaxation.hpp"

namespace asperity::minimize::detail {

namespace {

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
class Flow final : public MinimizerMethod {
 public:
  explicit Flow(Relaxation& run)
      : MinimizerMethod(run),
        // The mobility is G (the reference) unless the filter is asked for explicitly.
        filter_(run.options.preconditioner == Preconditioner::interface &&
                run.problem.wants_filter(false)),
        Fu_(run.n),
        Ff_(run.n),
        Fu_new_(run.n),
        Ff_new_(run.n),
        y1u_(run.n),
        y1f_(run.n),
        y2u_(run.n),
        y2f_(run.n),
        gu_(run.n),
        gf_(run.n),
        v_(run.n),
        w_(run.n),
        z_(run.n) {
    run.result.filtered = filter_;
    if (run.resume) restore(*run.resume);
  }

  [[nodiscard]] Method method() const override { return Method::flow; }
  Step iterate(int iteration) override;
  // x was moved off an unstable state: its velocity is computed again.
  void forget() override { fresh_ = false; }
  bool pause(int iterations, const FlowPauses& pauses) override;

 private:
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

  // The velocity at residual r is -(u_dot, f_dot) = (G P r, P r), P = I or M.
  void mobility(std::span<const double> r, std::vector<double>& u_dot, std::vector<double>& f_dot) {
    if (filter_) {
      run_.filter(r, f_dot);
    } else {
      std::copy(r.begin(), r.end(), f_dot.begin());
    }
    run_.problem.compliance(f_dot, u_dot);
  }

  Step euler(Point& x, Point& trial, double pmax) {
    const std::size_t n = Fu_.size();
    const double h = std::min(step_, run_.options.max_displacement / pmax);
    axpy_into(trial.u, x.u, -h, Fu_);
    axpy_into(trial.f, x.f, -h, Ff_);
    trial.e = run_.eval(trial.u, trial.f, trial.r);
    mobility(trial.r, Fu_new_, Ff_new_);  // the slope at the new point: the next step's, if kept
    double err = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      err = std::max(err, std::abs(Fu_new_[i] - Fu_[i]));
    err = reduce_max(err) * 0.5 * h;
    // A finite state with a non-finite energy or slope is a fault of the problem.
    if (!std::isfinite(trial.e) || !std::isfinite(err)) return Step::diverged;
    const bool overshoot = dot(trial.r, Fu_) < 0.0;
    const bool accepted = err <= run_.options.flow_tolerance && !overshoot;
    const double factor = err > 0.0 ? 0.9 * std::sqrt(run_.options.flow_tolerance / err) : 4.0;
    if (!accepted) {
      ++run_.result.rejected_steps;
      step_ = h * std::clamp(overshoot ? std::min(factor, 0.5) : factor, 0.1, 0.5);
      rejected_last_ = true;
      if (step_ * pmax < 1e-14 * run_.options.flow_tolerance) return Step::diverged;
      return Step::again;
    }
    // No growth right after a rejection: at the stability limit a rejected step followed by a
    // fourfold one wasted four steps in ten (a = 46 d, R = 100 d).
    step_ = h * std::clamp(factor, 0.2, rejected_last_ ? 1.0 : 2.0);
    rejected_last_ = false;
    std::swap(x, trial);
    std::swap(Fu_, Fu_new_);
    std::swap(Ff_, Ff_new_);
    return Step::accepted;
  }

  // Spectral radius of the Jacobian of df/dt, w -> P (w + H G w), by power iteration
  // warm-started from the last vector.
  void estimate_radius(const Point& x) {
    const std::size_t n = v_.size();
    hessian_.at(run_.problem, x.u);
    const std::vector<double>& h = hessian_.diagonal();
    if (!have_vector_) {
      // Of the global index, so that every number of processes starts from the same vector.
      const Share share = run_.problem.share();
      for (std::size_t i = 0; i < n; ++i)  // not an eigenvector
        v_[i] = 1.0 + 0.5 * std::sin(1.7 * static_cast<double>(share.global_index(i)));
      have_vector_ = true;
    }
    double est = 0.0;
    for (int k = 0; k < 10; ++k) {
      const double norm = std::sqrt(dot(v_, v_));
      if (!(norm > 0.0)) break;
      view(std::span<double>(v_)) /= norm;
      run_.problem.compliance(v_, gu_);
      if (hessian_.coupled()) {
        hessian_.apply(gu_, z_);
        for (std::size_t i = 0; i < n; ++i)
          z_[i] += v_[i];
      } else {
        for (std::size_t i = 0; i < n; ++i)
          z_[i] = v_[i] + h[i] * gu_[i];
      }
      if (filter_) {
        run_.filter(z_, w_);
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

  Step rkc(Point& x, Point& trial) {
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
      run_.eval(y1u_, y1f_, trial.r);
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
    trial.e = run_.eval(trial.u, trial.f, trial.r);
    mobility(trial.r, Fu_new_, Ff_new_);
    double err = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      // y_n - y_n+1 + h/2 (F_n + F_n+1), with F = -(G P r).
      err = std::max(err, std::abs(12.0 * (x.u[i] - trial.u[i]) - 6.0 * h * (Fu_[i] + Fu_new_[i])));
    }
    err = reduce_max(err) / 15.0;
    // A non-finite stage is most likely an underestimated spectral radius (the stages then grow
    // without bound): a rejected step, with rho estimated again.
    if (!std::isfinite(trial.e) || !std::isfinite(err)) err = 1e300;
    const bool rises = trial.e > x.e + energy_slack(x.e);
    const bool accepted = err <= run_.options.flow_tolerance && !rises;
    const double factor = err > 0.0 ? 0.8 * std::cbrt(run_.options.flow_tolerance / err) : 10.0;
    if (!accepted) {
      ++run_.result.rejected_steps;
      step_ = h * std::clamp(rises ? std::min(factor, 0.5) : factor, 0.1, 0.5);
      rejected_last_ = true;
      radius_ = 0.0;  // re-estimate: an underestimate shows as a rejected step
      if (step_ * max_abs(Fu_) < 1e-14 * run_.options.flow_tolerance) return Step::diverged;
      return Step::again;
    }
    step_ = h * std::clamp(factor, 0.1, rejected_last_ ? 1.0 : 4.0);
    rejected_last_ = false;
    ++since_estimate_;
    std::swap(x, trial);
    std::swap(Fu_, Fu_new_);
    std::swap(Ff_, Ff_new_);
    return Step::accepted;
  }

  bool filter_;
  // -F at x and at the trial: (G P r, P r).
  std::vector<double> Fu_, Ff_, Fu_new_, Ff_new_;
  std::vector<double> y1u_, y1f_, y2u_, y2f_, gu_, gf_;  // RKC stages
  InterfaceHessian hessian_;                             // power iteration
  std::vector<double> v_, w_, z_;
  std::vector<double> T_, dT_, ddT_, b_;  // Chebyshev coefficients
  bool fresh_ = false, have_vector_ = false, rejected_last_ = false;
  double step_ = 0.0, radius_ = 0.0;
  int since_estimate_ = 0;
};

Step Flow::iterate(int iteration) {
  if (run_.refresh(iteration)) fresh_ = false;
  if (!fresh_) {
    mobility(run_.x.r, Fu_, Ff_);
    fresh_ = true;
  }
  const double pmax = max_abs(Fu_);
  if (!(pmax > 0.0)) return Step::converged;  // r is numerically zero in the G metric
  // First step: the Euler error h^2/2 |d(G r)/dt| with d(G r)/dt ~ G r; at most 1, the
  // relaxation time of the half-space alone (flow time is dimensionless: G K = I), so that a
  // start near equilibrium does not begin with hundreds of stages.
  if (step_ <= 0.0) step_ = std::min(1.0, std::sqrt(2.0 * run_.options.flow_tolerance / pmax));
  return run_.options.flow_scheme == FlowScheme::euler ? euler(run_.x, run_.trial, pmax)
                                                       : rkc(run_.x, run_.trial);
}

bool Flow::pause(int iterations, const FlowPauses& pauses) {
  if (!pauses.due || !pauses.due(iterations)) return false;
  FlowPause here{.iteration = iterations, .u = run_.x.u, .f = run_.x.f, .done = run_.result};
  save(here);
  here.done.iterations = iterations;
  here.done.gf_applications = run_.problem.gf_applications() - run_.gf0;
  here.done.interface_evaluations = run_.eval.evaluations;
  return pauses.pause && pauses.pause(here);
}

}  // namespace

std::unique_ptr<MinimizerMethod> make_flow(Relaxation& run) {
  return std::make_unique<Flow>(run);
}

}  // namespace asperity::minimize::detail
