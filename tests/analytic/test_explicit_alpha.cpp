// Analytic tier: the local friction coefficient alpha of the repulsive LJ interface (MODEL.md 4,
// core/explicit/alpha_path.hpp).
//
// Analytic answer, the low-load limit: as Fz -> 0 the atom rides at the cutoff distance r_c of
// its neighbours. Just past the hollow site the two neighbours behind it leave range, and it
// rests on the two ahead, at lateral offsets (d/2 - x, +-d/2); the height profile is then the
// circle z^2 = r_c^2 - d^2/4 - (d/2 - x)^2, whose slope at x -> 0+ is the largest:
//   alpha_0 = (d/2) / sqrt(r_c^2 - d^2/2),   r_c = 2^(1/6) sigma,
// 1/sqrt(2) = 0.7071 at sigma/d = 2^(-1/6). At fixed Fz the pairs compress by about
// Fz / V''(r_c) ~ 1e-5 sigma at Fz = 1e-3 eps/sigma, so alpha must match alpha_0 to 1e-3, and
// the force ratio max Fx/Fz must too (on a surface of constant r the force is normal to it).
// alpha_force is a maximum over samples only (alpha is refined between them), and the ratio
// falls by 0.7% over the first 0.0025 d past the hollow site: 20001 samples bring that to 1e-4.
//
// Load independence (issue acceptance 2, first half): alpha varies by less than 10% over
// Fz = 0.1 .. 10 eps/sigma for sigma/d = 2^(-1/6), 0.95 and 1.0 (measured: 1.8%, 1.6%, 3.7%).
// At sigma/d = 0.8 it is 10.3% and at 0.7 a factor 1.9: the cutoff then barely exceeds the
// hollow-site gap d/sqrt(2) and the atom sinks into the hollow as the load grows, so small
// sigma/d are reported by alpha_path but not claimed load independent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "asperity/core/explicit/alpha_path.hpp"

using namespace asperity::explicit_model;

TEST(ExplicitAlpha, LowLoadLimit) {
  for (double s : {0.8908987181403393, 0.95, 1.0}) {
    const double rc = std::pow(2.0, 1.0 / 6.0) * s;
    const double alpha0 = 0.5 / std::sqrt(rc * rc - 0.5);
    const auto p = alpha_path({.sigma_over_d = s, .normal_force = 1e-3, .samples = 20001});
    std::printf("sigma/d = %.4f: alpha = %.6f, max Fx/Fz = %.6f, alpha_0 = %.6f\n", s, p.alpha,
                p.alpha_force, alpha0);
    EXPECT_NEAR(p.alpha / alpha0, 1.0, 1e-3);
    EXPECT_NEAR(p.alpha_force / alpha0, 1.0, 1e-3);
  }
}

TEST(ExplicitAlpha, NearlyLoadIndependent) {
  for (double s : {0.8908987181403393, 0.95, 1.0}) {
    double lo = 1e300, hi = 0.0;
    for (double fz : {0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0}) {
      const auto p = alpha_path({.sigma_over_d = s, .normal_force = fz});
      lo = std::min(lo, p.alpha), hi = std::max(hi, p.alpha);
    }
    std::printf("sigma/d = %.4f: alpha in [%.4f, %.4f], variation %.2f%%\n", s, lo, hi,
                100.0 * (hi - lo) / lo);
    EXPECT_LT((hi - lo) / lo, 0.10);
  }
}
