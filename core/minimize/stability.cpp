// Stability of a converged state (minimizer.hpp): the lowest eigenvalue of the Hessian K + H_int
// in the congruent form A = G + G H_int G of the pair representation (SOLVERS.md, "Free-boundary
// contact"), and the check of every method's converged states, by a push and a second
// minimisation (perturb) or by that eigenvalue (lanczos), with the escape from an unstable state.
#include <Spectra/SymEigsSolver.h>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "asperity/core/minimize/kernels.hpp"
#include "asperity/core/minimize/relaxation.hpp"

namespace asperity::minimize {

namespace {

// A = G + G H G, the Hessian K + H in force coordinates (congruent, same inertia).
class HessianOp {
 public:
  using Scalar = double;
  HessianOp(Problem& p, const InterfaceHessian& hessian)
      : p_(&p), hessian_(&hessian), h_(hessian.diagonal()), z_(p.size()), t_(p.size()) {}
  [[nodiscard]] Eigen::Index rows() const { return static_cast<Eigen::Index>(h_.size()); }
  [[nodiscard]] Eigen::Index cols() const { return rows(); }
  void perform_op(const double* x, double* y) const {
    const std::size_t n = h_.size();
    p_->compliance({x, n}, z_);
    if (hessian_->coupled()) {
      hessian_->apply(z_, t_);
    } else {
      for (std::size_t i = 0; i < n; ++i)
        t_[i] = h_[i] * z_[i];
    }
    p_->compliance(t_, {y, n});
    for (std::size_t i = 0; i < n; ++i)
      y[i] += z_[i];
  }

 private:
  Problem* p_;
  const InterfaceHessian* hessian_;
  std::span<const double> h_;
  mutable std::vector<double> z_, t_;
};

}  // namespace

Stability lowest_mode(Problem& problem, std::span<const double> u) {
  const std::size_t n = problem.size();
  const std::size_t gf0 = problem.gf_applications();
  InterfaceHessian hessian;
  hessian.at(problem, u);
  HessianOp op(problem, hessian);
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

namespace detail {

namespace {

// The lanczos check: whether x is unstable, by the sign of the lowest eigenvalue of A (an
// unstable x is left along its eigenvector, on the side of lower energy); nullopt if Lanczos
// did not decide.
std::optional<bool> lanczos_check(Relaxation& run) {
  Point& x = run.x;
  Point& trial = run.trial;  // scratch
  Stability st = lowest_mode(run.problem, x.u);
  run.result.lowest_eigenvalue = st.lowest;
  if (!st.converged || !std::isfinite(st.lowest) || st.direction_u.empty()) return std::nullopt;
  // Scale of A: its Rayleigh quotient along the mode's own G-image is ~ |G|.
  const double scale = std::max(1e-300, dot(st.direction_u, st.direction_f) /
                                            std::max(1e-300, dot(st.direction_f, st.direction_f)));
  if (!(st.lowest < -1e-8 * scale)) return false;
  // Leave the saddle along its unstable mode, on the side of lower energy.
  const double eta = run.options.escape_displacement / std::max(1e-300, max_abs(st.direction_u));
  double best_e = std::numeric_limits<double>::infinity();
  double best_sign = 1.0;
  for (double sign : {1.0, -1.0}) {
    axpy_into(trial.u, x.u, sign * eta, st.direction_u);
    axpy_into(trial.f, x.f, sign * eta, st.direction_f);
    const double e = run.eval(trial.u, trial.f, trial.r);
    if (e < best_e) best_e = e, best_sign = sign;
  }
  axpy_into(x.u, x.u, best_sign * eta, st.direction_u);
  axpy_into(x.f, x.f, best_sign * eta, st.direction_f);
  x.e = run.eval(x.u, x.f, x.r);
  return true;
}

// The perturb check: push, relax without a check (on a budget of its own), and compare. A
// relaxation that ends lower in energy than the state, converged or not, shows the state was
// not a minimum: the lower state is kept (x) and minimised on. Returns whether x was unstable;
// the relaxation's iterations count into `iteration`.
bool push_check(Relaxation& run, int& iteration) {
  const std::size_t n = run.n;
  const MinimizerOptions& options = run.options;
  Point& x = run.x;
  std::vector<double> q(n), z(n);
  // The push of every unknown of every process, drawn in the global order (each process keeps
  // its own): the same push on any number of processes.
  const Share share = run.problem.share();
  std::mt19937 gen(
      static_cast<unsigned>(share.global_size() + static_cast<std::size_t>(iteration)));
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  const auto skip = [&](std::size_t k) {  // draws, not engine steps: a draw may take several
    for (; k > 0; --k)
      (void)dist(gen);
  };
  for (std::size_t b = 0, i = 0; b < share.blocks; ++b) {
    skip(share.offset);
    for (std::size_t j = 0; j < share.per_block; ++j)
      q[i++] = dist(gen);
    skip(share.global_per_block - share.offset - share.per_block);
  }
  run.problem.compliance(q, z);
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
  const MinimizeResult again = minimize::minimize(run.problem, pu, pf, inner);
  iteration += again.iterations;
  run.eval.evaluations += again.interface_evaluations;
  run.result.filter_applications += again.filter_applications;
  double moved = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    moved = std::max(moved, std::abs(pu[i] - x.u[i]));
  moved = reduce_max(moved);
  const bool lower = std::isfinite(again.energy) && again.energy < x.e - energy_slack(x.e);
  const bool unstable =
      lower && (moved > 10.0 * pushed || again.termination != Termination::converged);
  if (unstable) {
    x.u = std::move(pu);
    x.f = std::move(pf);
    x.e = run.eval(x.u, x.f, x.r);
  }
  return unstable;
}

}  // namespace

Verdict check_minimum(Relaxation& run, int& iteration) {
  if (run.options.stability == StabilityCheck::none) return Verdict::minimum;
  InterfaceHessian hessian;
  hessian.at(run.problem, run.x.u);
  if (!reduce_any(!hessian.positive_semidefinite())) return Verdict::minimum;  // K + H_int > 0
  run.result.stability_checked = true;
  std::optional<bool> unstable;
  if (run.options.stability == StabilityCheck::lanczos) unstable = lanczos_check(run);
  // perturb, or Lanczos undecided: the push decides.
  if (!unstable.has_value()) unstable = push_check(run, iteration);
  if (!*unstable) return Verdict::minimum;
  run.result.lowest_eigenvalue = std::numeric_limits<double>::quiet_NaN();  // of a state left
  return ++run.result.escapes > run.options.max_escapes ? Verdict::unstable : Verdict::escaped;
}

}  // namespace detail

}  // namespace asperity::minimize
