// Unit tier: the single-atom path of alpha_path (core/explicit/alpha_path.hpp) and the repulsive
// Lennard-Jones terms (core/explicit/lennard_jones.hpp).
// Checks: V, V'/r and V'' against finite differences and continuity at the cutoff; the path is
// mirror symmetric about the bridge (z'(x) = -z'(d - x), Fx too); the lateral force is the
// derivative of the enthalpy H = V + Fz z along the path (its integral from hollow to bridge is
// the barrier); bad options are rejected naming the field.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "asperity/core/explicit/alpha_path.hpp"
#include "asperity/core/explicit/lennard_jones.hpp"

using namespace asperity::explicit_model;

TEST(ExplicitLennardJones, DerivativesAndCutoff) {
  const LennardJones lj(1.3, 0.9);
  EXPECT_NEAR(lj.cutoff(), std::pow(2.0, 1.0 / 6.0) * 0.9, 1e-15);
  for (double r : {0.85, 0.9, 0.95, 1.0}) {
    const double e = 1e-6;
    const auto t = lj.at(r * r);
    const double vp = (lj.at((r + e) * (r + e)).v - lj.at((r - e) * (r - e)).v) / (2 * e);
    const double vpp =
        (lj.at((r + e) * (r + e)).dv_r * (r + e) - lj.at((r - e) * (r - e)).dv_r * (r - e)) /
        (2 * e);
    EXPECT_NEAR(t.dv_r * r, vp, 1e-6 * std::max(1.0, std::abs(vp))) << r;
    EXPECT_NEAR(t.d2v, vpp, 1e-5 * std::max(1.0, std::abs(vpp))) << r;
  }
  const double rc = lj.cutoff();
  EXPECT_NEAR(lj.at(rc * rc * (1 - 1e-12)).v, 0.0, 1e-9);
  EXPECT_NEAR(lj.at(rc * rc * (1 - 1e-12)).dv_r, 0.0, 1e-9);
  EXPECT_EQ(lj.at(rc * rc).v, 0.0);
  // Scene units: eps = sigma^3 / G with G in eps/sigma^3 (G the stress unit).
  const auto s = LennardJones::in_substrate_units(10.0, 0.8);
  EXPECT_NEAR(s.eps(), 0.512 / 10.0, 1e-15);
  EXPECT_NEAR(s.sigma(), 0.8, 1e-15);
}

TEST(ExplicitAlphaPath, SymmetryAndEnthalpy) {
  for (double fz : {0.1, 1.0, 10.0}) {
    const auto p = alpha_path({.normal_force = fz, .samples = 401});
    const std::size_t n = p.x.size();
    for (std::size_t k = 0; k < n; ++k) {
      EXPECT_NEAR(p.height[k], p.height[n - 1 - k], 1e-10);
      EXPECT_NEAR(p.slope[k], -p.slope[n - 1 - k], 1e-7);
      EXPECT_NEAR(p.lateral[k], -p.lateral[n - 1 - k], 1e-7 * fz);
    }
    EXPECT_NEAR(p.slope[0], 0.0, 1e-9);
    EXPECT_NEAR(p.slope[n / 2], 0.0, 1e-9);
    EXPECT_GT(p.height_bridge, p.height_hollow);
    // dH/dx = Fx: trapezoids of Fx (eps/sigma, x in d: times d/sigma) against the barrier.
    // Fx is continuous (V' is), but at low load it rises from 0 to ~alpha Fz within the first
    // ~0.001 d past the hollow (the neighbours behind leave the cutoff), below the 0.0025 d
    // spacing: that step costs up to 3e-3 of the barrier at Fz = 0.1 (measured); 5e-3 allowed.
    double work = 0.0;
    for (std::size_t k = 0; k < n / 2; ++k)
      work += 0.5 * (p.lateral[k] + p.lateral[k + 1]) * (p.x[k + 1] - p.x[k]);
    work /= AlphaPathOptions{}.sigma_over_d;
    EXPECT_NEAR(work, p.barrier, 5e-3 * p.barrier) << "Fz " << fz;
    EXPECT_LT(p.slope_check, 1e-2);
  }
}

TEST(ExplicitAlphaPath, RejectsBadOptions) {
  EXPECT_THROW(alpha_path({.sigma_over_d = 0.5}), std::invalid_argument);
  EXPECT_THROW(alpha_path({.normal_force = 0.0}), std::invalid_argument);
  EXPECT_THROW(alpha_path({.normal_force = std::nan("")}), std::invalid_argument);
  EXPECT_THROW(alpha_path({.samples = 200}), std::invalid_argument);
  // Each refusal names the key and what is allowed (AlphaPathOptions::settings()).
  const auto message = [](const AlphaPathOptions& o) -> std::string {
    try {
      alpha_path(o);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "(no throw)";
  };
  EXPECT_EQ(message({.samples = 2}), "samples = 2: allowed: an integer [3, 1000001]");
  EXPECT_EQ(message({.samples = 200}),
            "samples = 200: allowed: odd (the bridge site must be a sample)");
  EXPECT_EQ(message({.sigma_over_d = 0.5}), "sigma_over_d = 0.5: allowed: [0.6, 1.5] d");
  EXPECT_EQ(message({.normal_force = -1.0}), "normal_force = -1: allowed: > 0 eps/sigma");
}
