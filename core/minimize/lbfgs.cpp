// The quasi-Newton methods of minimizer.hpp: lbfgs, L-BFGS with H0 = gamma G (or gamma G M with
// the interface filter M) in the pair representation of SOLVERS.md ("Free-boundary contact": the
// two-loop recursion on s = du, y = dr with one GF application per iteration, the K-image of the
// direction from the stored force changes), and newton, lbfgs with a Newton-Krylov finish.
#include <algorithm>
#include <cstdint>
#include <deque>
#include <memory>
#include <utility>
#include <vector>

#include "asperity/core/common/parallel.hpp"
#include "asperity/core/minimize/kernels.hpp"
#include "asperity/core/minimize/line_search.hpp"
#include "asperity/core/minimize/relaxation.hpp"
#include "asperity/core/solve/newton_krylov.hpp"

namespace asperity::minimize::detail {

namespace {

// A stored step: s = du, its K-image df (= the force change) and y = dr, rho = 1 / s.y.
struct Pair {
  std::vector<double> s, df, y;
  double rho;
};

class Lbfgs : public MinimizerMethod {
 public:
  explicit Lbfgs(Relaxation& run)
      : MinimizerMethod(run),
        use_filter_(
            run.options.preconditioner != Preconditioner::elastic &&
            run.problem.wants_filter(run.options.preconditioner == Preconditioner::automatic)),
        du_(run.n),
        df_(run.n),
        q_(run.n),
        z_(run.n),
        w_filter_(use_filter_ ? run.n : 0) {
    run.result.filtered = use_filter_;
  }

  [[nodiscard]] Method method() const override { return Method::lbfgs; }
  Step iterate(int iteration) override;
  void forget() override {
    memory_.clear();
    restart_ = true;
  }

 private:
  double direction();
  void two_loop();
  void apply_h0(std::vector<double>& v, std::vector<double>& zout);
  void remember_step();
  void reset_on_curvature_change();

  // H0 = G M with the interface filter M, as the preconditioner option and the problem decide.
  bool use_filter_;
  // After a failed line search the retry is plain G steepest descent, as without the filter:
  // G r . r > 0 always, whereas G M, not symmetric on the contact sites, only nearly so.
  bool plain_next_ = false;
  bool restart_ = true;  // no step since the start, a retry or an escape
  std::deque<Pair> memory_;
  // The storage of the next pair: the oldest pair's, once the memory is full, so that an
  // iteration allocates no vector (three of 13 MB each per iteration at a = 510 d).
  Pair spare_;
  std::vector<double> du_, df_, q_, z_, alpha_coef_, w_filter_;
  std::vector<std::uint8_t> unstable_half_;  // curvature_reset: sites in the unstable half
};

Step Lbfgs::iterate(int iteration) {
  run_.refresh(iteration);
  double d0 = direction();
  if (!(d0 < 0.0)) {  // not a descent direction: fall back to preconditioned steepest descent
    memory_.clear();
    d0 = steepest_descent(run_, z_, du_, df_);
    if (!(d0 < 0.0)) return Step::converged;
  }
  // Weak Wolfe conditions: the updates only need y.s > 0.
  if (!search_line(run_, du_, df_, d0, 0.9, false)) {
    // Retry once from G-preconditioned steepest descent.
    if (!memory_.empty() || !restart_ || (use_filter_ && !plain_next_)) {
      memory_.clear();
      restart_ = true;
      plain_next_ = use_filter_;
      return Step::again;
    }
    return Step::diverged;  // no descent left at this precision
  }
  restart_ = false;
  plain_next_ = false;
  remember_step();
  std::swap(run_.x, run_.trial);
  if (run_.options.curvature_reset) reset_on_curvature_change();
  return Step::accepted;
}

// The search direction (du, df) with df = K du; returns its slope r.du.
double Lbfgs::direction() {
  const Point& x = run_.x;
  if (!memory_.empty()) {
    two_loop();
  } else if (use_filter_ && !plain_next_) {  // first step: filtered steepest descent
    q_ = x.r;
    apply_h0(q_, z_);
    each(run_.n, [&](std::size_t i) {
      du_[i] = -z_[i];
      df_[i] = -q_[i];
    });
  } else {
    run_.problem.compliance(x.r, z_);
    // -(G r, r) + 0.0: as this direction was computed when it shared cg's code (cg's direction
    // with beta = 0 and no previous one), so that a -0 becomes +0 and the bits stay the same.
    each(run_.n, [&](std::size_t i) {
      du_[i] = -z_[i] + 0.0;
      df_[i] = -x.r[i] + 0.0;
    });
  }
  return dot(x.r, du_);
}

// z = H0 v (one GF application); v becomes the K-image of z (v itself without the filter).
void Lbfgs::apply_h0(std::vector<double>& v, std::vector<double>& zout) {
  if (use_filter_ && !plain_next_) {
    run_.filter(v, w_filter_);
    run_.problem.compliance(w_filter_, zout);
    std::swap(v, w_filter_);
  } else {
    run_.problem.compliance(v, zout);
  }
}

// The two-loop recursion into (du, df).
void Lbfgs::two_loop() {
  const std::size_t n = run_.n;
  const Point& x = run_.x;
  alpha_coef_.assign(memory_.size(), 0.0);
  for (std::size_t k = memory_.size(); k-- > 0;) {
    // The newest pair reads r itself and writes q = r - alpha y in one pass: the same
    // values as copying r into q first (a + t b either way), without the copy.
    const bool newest_pair = k + 1 == memory_.size();
    alpha_coef_[k] = memory_[k].rho * dot(memory_[k].s, newest_pair ? x.r : q_);
    if (newest_pair)
      axpy_into(q_, x.r, -alpha_coef_[k], memory_[k].y);
    else
      axpy(q_, -alpha_coef_[k], memory_[k].y);
  }
  apply_h0(q_, z_);
  std::vector<double>& zf = q_;  // K-image of z, built in place
  // H0 = gamma G with gamma = s.K s / s.y of the newest pair: the elastic curvature along
  // the last step over the total one (free: K s is the stored force change). The interface
  // softens the problem as a state nears an instability, and unscaled G steps fell short.
  // With the filter, H0 = gamma G M: the same scale, measured rather than derived (M already
  // holds a uniform interface stiffness, so gamma then corrects for its difference from the
  // actual one; slides at a / b_core^0 = 20 to 64 ran at gamma 0.2 to 5).
  const Pair& newest = memory_.back();
  const double gamma = std::clamp(dot(newest.s, newest.df) * newest.rho, 0.1, 10.0);
  // Built negated, so that z and zf become the direction (du, df) without a pass to negate
  // them: negation is exact and commutes with every product and sum here, so the result is
  // bit for bit -(the recursion's z), and c is the recursion's c.
  scale(z_, -gamma);
  scale(zf, -gamma);
  for (std::size_t k = 0; k < memory_.size(); ++k) {
    const double c = alpha_coef_[k] + memory_[k].rho * dot(memory_[k].y, z_);
    axpy(z_, -c, memory_[k].s);
    alpha_coef_[k] = -c;  // zf's coefficient, applied below
  }
  // zf += -c_k df_k for every pair, in one pass over zf instead of one per pair (zf is not
  // read in the loop above): per element the same additions in the same order as pair by
  // pair, so bit for bit the same; blocks keep zf's block in cache across the pairs.
  par::for_ranges(n, pass_threads, [&](std::size_t b, std::size_t e) {
    constexpr std::size_t block = 2048;
    for (std::size_t i0 = b; i0 < e; i0 += block) {
      const std::size_t len = std::min(block, e - i0);
      const std::span<double> out(zf.data() + i0, len);
      for (std::size_t k = 0; k < memory_.size(); ++k)  // a block: axpy stays on this thread
        axpy(out, alpha_coef_[k], std::span<const double>(memory_[k].df.data() + i0, len));
    }
  });
  std::swap(du_, z_);
  std::swap(df_, zf);
}

// Stores the step from x to the trial (s = du t, its K-image, y = dr), if its curvature is
// positive.
void Lbfgs::remember_step() {
  const Point& x = run_.x;
  const Point& trial = run_.trial;
  Pair& p = spare_;
  p.s.resize(run_.n);
  p.df.resize(run_.n);
  p.y.resize(run_.n);
  each(run_.n, [&](std::size_t i) {
    p.s[i] = trial.u[i] - x.u[i];
    p.df[i] = trial.f[i] - x.f[i];
    p.y[i] = trial.r[i] - x.r[i];
  });
  const double sy = dot(p.s, p.y);
  if (sy > 1e-300) {  // keep only positive curvature
    p.rho = 1.0 / sy;
    memory_.push_back(std::move(p));
    spare_ = Pair{};
    if (static_cast<int>(memory_.size()) > run_.options.memory) {
      spare_ = std::move(memory_.front());
      memory_.pop_front();
    }
  }
}

// Experimental (issue 21): forget the pairs when a site enters or leaves the unstable half of
// its well, so that no curvature measured before a site snapped steers the steps after.
void Lbfgs::reset_on_curvature_change() {
  const std::size_t n = run_.n;
  run_.problem.curvature(run_.x.u, z_);
  bool changed = false;
  const bool first = unstable_half_.size() != n;  // nothing to compare with yet
  if (first) unstable_half_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t neg = z_[i] < 0.0 ? 1 : 0;
    if (neg != unstable_half_[i]) {
      unstable_half_[i] = neg;
      changed = true;
    }
  }
  if (changed && !first) {
    memory_.clear();
    ++run_.result.memory_resets;
  }
}

// Newton-Krylov on F(f) = f - f_int(G f): the unknowns are the forces, so the pair stays
// consistent (u = G f). J v = v + H_int (G v). Returns true if it converged (x is then updated).
bool newton_finish(Problem& problem, Point& x, const MinimizerOptions& options) {
  const std::size_t n = x.f.size();
  std::vector<double> f = x.f, u(n), fint(n), gv(n), hgv(n), at(n);
  InterfaceHessian hessian;
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
      hessian.at(problem, u);
      std::copy(fin.begin(), fin.end(), at.begin());
      have_h = true;
    }
    problem.compliance(v, gv);
    if (hessian.coupled()) {
      hessian.apply(gv, hgv);
      for (std::size_t i = 0; i < n; ++i)
        jv[i] = v[i] + hgv[i];
    } else {
      const std::vector<double>& h = hessian.diagonal();
      for (std::size_t i = 0; i < n; ++i)
        jv[i] = v[i] + h[i] * gv[i];
    }
  };
  const auto r = solve::newton_krylov(f, residual, jtimes,
                                      {.tolerance = options.force_tolerance, .max_iterations = 30});
  if (r.termination != Termination::converged) return false;
  x.f = std::move(f);
  problem.compliance(x.f, x.u);
  return true;
}

// lbfgs down to newton_start, then one Newton-Krylov finish (a minimisation tries it once).
// Newton finds any stationary point: the stability check of minimize() keeps it on minima.
class Newton final : public Lbfgs {
 public:
  using Lbfgs::Lbfgs;

  [[nodiscard]] Method method() const override { return Method::newton; }
  Step iterate(int iteration) override {
    const MinimizerOptions& o = run_.options;
    if (!tried_ && run_.result.max_force <= std::max(o.newton_start, o.force_tolerance)) {
      tried_ = true;
      if (newton_finish(run_.problem, run_.x, o)) {
        run_.x.e = run_.eval(run_.x.u, run_.x.f, run_.x.r);
        forget();
        return Step::again;  // converged: minimize()'s test (stability included) decides
      }
    }
    return Lbfgs::iterate(iteration);
  }

 private:
  bool tried_ = false;
};

}  // namespace

std::unique_ptr<MinimizerMethod> make_lbfgs(Relaxation& run) {
  return std::make_unique<Lbfgs>(run);
}

std::unique_ptr<MinimizerMethod> make_newton(Relaxation& run) {
  return std::make_unique<Newton>(run);
}

}  // namespace asperity::minimize::detail
