// The cg method of minimizer.hpp: Polak-Ribiere+ conjugate gradients preconditioned with G in the
// pair representation of SOLVERS.md ("Free-boundary contact": the direction -(G r, r) at one GF
// application, line searches free), the classic reference of the minimisers.
#include <algorithm>
#include <memory>
#include <utility>
#include <vector>

#include "asperity/core/minimize/kernels.hpp"
#include "asperity/core/minimize/line_search.hpp"
#include "asperity/core/minimize/relaxation.hpp"

namespace asperity::minimize::detail {

namespace {

class Cg final : public MinimizerMethod {
 public:
  explicit Cg(Relaxation& run)
      : MinimizerMethod(run),
        du_(run.n),
        df_(run.n),
        z_(run.n),
        du_prev_(run.n, 0.0),
        df_prev_(run.n, 0.0),
        z_prev_(run.n, 0.0) {}

  [[nodiscard]] Method method() const override { return Method::cg; }
  Step iterate(int iteration) override;
  void forget() override { restart_ = true; }

 private:
  void conjugate_direction();

  std::vector<double> du_, df_, z_;
  // The previous direction, G r and r.G r: the memory of the conjugation.
  std::vector<double> du_prev_, df_prev_, z_prev_;
  double rz_prev_ = 0.0;
  bool restart_ = true;  // steepest descent next: the start, a retry or an escape
};

Step Cg::iterate(int iteration) {
  run_.refresh(iteration);
  conjugate_direction();
  double d0 = dot(run_.x.r, du_);
  if (!(d0 < 0.0)) {  // not a descent direction: fall back to preconditioned steepest descent
    d0 = steepest_descent(run_, z_, du_, df_);
    z_prev_ = z_;
    rz_prev_ = -d0;
    if (!(d0 < 0.0)) return Step::converged;
  }
  // Strong Wolfe conditions: conjugacy needs them.
  if (!search_line(run_, du_, df_, d0, 0.1, true)) {
    // Retry once from G-preconditioned steepest descent.
    if (!restart_) {
      restart_ = true;
      return Step::again;
    }
    return Step::diverged;  // no descent left at this precision
  }
  restart_ = false;
  du_prev_ = du_;  // CG continues from the direction, not the step
  df_prev_ = df_;
  std::swap(run_.x, run_.trial);
  return Step::accepted;
}

// (du, df) = -(G r, r) + beta (du_prev, df_prev), beta by Polak-Ribiere+ (0 on a restart).
void Cg::conjugate_direction() {
  const std::size_t n = run_.n;
  const Point& x = run_.x;
  run_.problem.compliance(x.r, z_);
  const double rz = dot(x.r, z_);
  double beta = 0.0;
  if (!restart_ && rz_prev_ > 0.0) {
    // r.(z - z_prev) as a dot product (kernels.hpp: the same sums on any number of processes).
    each(n, [&](std::size_t i) { z_prev_[i] = z_[i] - z_prev_[i]; });
    const double num = dot(x.r, z_prev_);
    beta = std::max(0.0, num / rz_prev_);  // Polak-Ribiere+
  }
  each(n, [&](std::size_t i) {
    du_[i] = -z_[i] + beta * du_prev_[i];
    df_[i] = -x.r[i] + beta * df_prev_[i];
  });
  z_prev_ = z_;
  rz_prev_ = rz;
}

}  // namespace

std::unique_ptr<MinimizerMethod> make_cg(Relaxation& run) {
  return std::make_unique<Cg>(run);
}

}  // namespace asperity::minimize::detail
