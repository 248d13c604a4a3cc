// The fire method of minimizer.hpp: FIRE (Bitzek et al., PRL 97, 170201, 2006) on the
// preconditioned force -G r in the pair representation of SOLVERS.md ("Free-boundary contact"),
// with powers and norms in the K metric (r.du, r.G r), which the pair makes free.
#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "asperity/core/minimize/kernels.hpp"
#include "asperity/core/minimize/relaxation.hpp"

namespace asperity::minimize::detail {

namespace {

class Fire final : public MinimizerMethod {
 public:
  explicit Fire(Relaxation& run)
      : MinimizerMethod(run), q_(run.n), z_(run.n), vu_(run.n, 0.0), vf_(run.n, 0.0) {}

  [[nodiscard]] Method method() const override { return Method::fire; }
  Step iterate(int iteration) override;
  void forget() override {
    std::fill(vu_.begin(), vu_.end(), 0.0);
    std::fill(vf_.begin(), vf_.end(), 0.0);
  }

 private:
  // Stop, and go on slower: after an uphill power or an energy rise.
  void slow_down() {
    forget();
    dt_ *= 0.5;
    alpha_ = alpha0;
    positive_ = 0;
  }

  static constexpr double dt_max = 1.0, alpha0 = 0.1;
  std::vector<double> q_, z_;
  std::vector<double> vu_, vf_;  // the velocity (u, f) of the pair
  double dt_ = 0.1, alpha_ = alpha0;
  int positive_ = 0;  // steps since the power was last negative
};

Step Fire::iterate(int iteration) {
  const std::size_t n = run_.n;
  Point& x = run_.x;
  Point& trial = run_.trial;
  run_.refresh(iteration);
  // Preconditioned force: -G r in u, -r in f.
  run_.problem.compliance(x.r, z_);
  for (std::size_t i = 0; i < n; ++i)
    q_[i] = -x.r[i];  // K-image of -z
  const double power = -dot(x.r, vu_);
  if (power > 0.0) {
    const double vnorm = std::sqrt(std::max(0.0, dot(vu_, vf_)));
    const double fnorm = std::sqrt(std::max(1e-300, dot(z_, x.r)));
    for (std::size_t i = 0; i < n; ++i) {
      vu_[i] = (1.0 - alpha_) * vu_[i] - alpha_ * vnorm / fnorm * z_[i];
      vf_[i] = (1.0 - alpha_) * vf_[i] + alpha_ * vnorm / fnorm * q_[i];
    }
    if (++positive_ > 5) {
      dt_ = std::min(1.1 * dt_, dt_max);
      alpha_ *= 0.99;
    }
  } else {
    slow_down();
  }
  for (std::size_t i = 0; i < n; ++i) {
    vu_[i] -= dt_ * z_[i];
    vf_[i] += dt_ * q_[i];
  }
  const double cap =
      std::min(1.0, run_.options.max_displacement / std::max(1e-300, dt_ * max_abs(vu_)));
  axpy_into(trial.u, x.u, cap * dt_, vu_);
  axpy_into(trial.f, x.f, cap * dt_, vf_);
  trial.e = run_.eval(trial.u, trial.f, trial.r);
  if (trial.e > x.e + energy_slack(x.e)) {  // no ascent: stop and restart slower
    slow_down();
    return dt_ < 1e-8 ? Step::diverged : Step::again;
  }
  std::swap(x, trial);
  return Step::accepted;
}

}  // namespace

std::unique_ptr<MinimizerMethod> make_fire(Relaxation& run) {
  return std::make_unique<Fire>(run);
}

}  // namespace asperity::minimize::detail
