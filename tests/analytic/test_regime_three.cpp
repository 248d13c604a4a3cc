// Analytic tier: Regime III hardening in a quasi-static slide (MODEL.md 5 and 8) and the stop
// rule of the automatic distance that has to follow it (slide/slider.hpp).
//
// Scene: R = 20 d, a = 15 d, alpha = 0.7, nu = 0.5: a/b_core^0 = 20, b_core^0 = 0.75 d. The edge
// Peierls stress at the centre is then 0.36 tau_max (peierls_scan, L = 128..256, b_core = 0.8 d),
// far above the shear stress a Regime II slip leaves there (about mu p0 / 3, 0.07 tau_max), so
// loops are arrested and pile up, and Fx keeps rising through many small slips after the first
// nucleation. Expected, each with its tolerance:
// 1. The slide is not cut short: the static peak comes after the second slip event and lies
//    above the highest Fx/Fz before it (the nucleation peak) by more than 10% (measured: 0.288
//    against 0.238, +21%; a slide that stopped at two slips, the rule before, reported the
//    latter).
// 2. The peak held over a period d before the automatic distance stopped (the rule itself; it
//    counts from the first sample within the trace's resolution of the peak, which may precede
//    the refined peak by a bracket, so 0.9 d), and mu is not a lower bound.
// 3. The Regime III prediction of MODEL.md 8 (a fraction f_P = 0.5 of the local edge Peierls
//    stress integrated over the contact, k1 = 2.326, k2 = 1.802 from this project's
//    peierls_scan edge fit) is within a factor 2 of mu/alpha (issue 9's acceptance bound;
//    predicted 0.194, measured 0.288), and mu/alpha lies above the Regime II law for
//    c0 = 0.22 (0.235), which a sweep stopped at two slips undershot.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "asperity/core/slide/slider.hpp"
#include "asperity/nucleation/regime_three.hpp"
#include "asperity/nucleation/regime_two.hpp"
#include "common/scenes.hpp"

using namespace asperity;

TEST(RegimeThree, FrictionHardensThroughArrestedLoopsAndTheSlideFollowsIt) {
  const interface::ContactScene scene = test::regime_three_small();
  slide::SlideOptions options;
  options.fft.threads = 1;
  const slide::SlideResult r = slide::slide(scene, options);
  ASSERT_FALSE(r.failed) << r.stop_reason;

  // The highest Fx/Fz before the second slip: what a stop at two slips reported.
  double before_second = 0.0, second_slip_Dx = -1.0;
  int slips = 0;
  for (const auto& row : r.trace) {
    if (row.slip && ++slips == 2) {
      second_slip_Dx = row.Dx;
      break;
    }
    before_second = std::max(before_second, row.Fx / row.Fz);
  }
  std::printf(
      "mu/alpha = %.4f at Dx = %.4f d (%d slips, slid %.3f d, %zu GF, %.1f s); highest "
      "before the second slip (Dx = %.4f d): %.4f\n",
      r.mu_over_alpha, r.peak_Dx, r.slip_events, r.distance, r.gf_applications, r.wall_s,
      second_slip_Dx, before_second / scene.alpha);
  ASSERT_GE(second_slip_Dx, 0.0) << "fewer than two slip events";
  EXPECT_GT(r.peak_Dx, second_slip_Dx);
  EXPECT_GT(r.mu, 1.1 * before_second);

  EXPECT_EQ(r.stop_reason, "slip events reached");
  EXPECT_FALSE(r.mu_is_lower_bound);
  EXPECT_GE(r.distance - r.peak_Dx, 0.9 * scene.d);

  const double beta = nucleation::bcore0(scene.a, scene.R, scene.alpha, scene.material.nu);
  const nucleation::PeierlsLaw law{.k1 = 2.326, .k2 = 1.802};
  const double predicted = nucleation::regime_three_integrated(beta, law, 0.5);
  const double regime_two = nucleation::regime_two_law(scene.a / (beta * scene.d), 0.22);
  std::printf("b_core^0 = %.3f d; Regime III prediction %.4f, Regime II law %.4f\n", beta,
              predicted, regime_two);
  EXPECT_LT(std::abs(std::log(r.mu_over_alpha / predicted)), std::log(2.0));
  EXPECT_GT(r.mu_over_alpha, regime_two);
}
