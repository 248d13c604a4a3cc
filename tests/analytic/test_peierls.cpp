// Analytic tier: the Peierls cell against the Peierls-Nabarro model (MODEL.md 6).
//
// Answers and tolerances:
// 1. Relaxed core width (registry offset d/4 -> 3d/4 across the line) = continuum PN width of a
//    half-space against a rigid body, w = (b_core / pi) (cos^2 theta + sin^2 theta / (1 - nu)):
//    b_core / pi (screw), b_core / (pi (1 - nu)) (edge), so edge/screw = 1/(1 - nu). Tolerance 5%
//    for b_core >= 4 d (issue 5): the discrete kernel departs from G |q| only at q ~ pi/d.
// 2. At nu = 0.5 the edge stiffness is twice the screw stiffness, so a screw line at b_core
//    behaves like an edge line at b_core/2 (SOLVERS.md). This holds exactly in the discrete
//    kernel too: the patch factor sinc(Q_y d/2) vanishes on every image off the normal, so both
//    lattice sums run over the same images with G_xx in the ratio (1 - nu). Both thresholds are
//    bracketed on the same sequence of scaled stresses: tolerance 1e-9 (round-off).
// 3. Edge tau_P decays exponentially; the rigid-profile PN estimate
//    tau_P/tau_max = (4 pi zeta/d) exp(-2 pi zeta/d), zeta = b_core/(2 pi (1 - nu)), decays as
//    exp(-b_core/((1 - nu) d)): k2 = 2 at nu = 0.5. Relaxation of the core lowers the barrier,
//    most where the core is narrow, so the relaxed tau_P lies below the rigid one and its local
//    decay rate approaches 2 from below as the core widens: between 1.6 and 2.0 over
//    b_core in [6, 12] d.
// 4. Screw lines are harder to move than edge lines at equal b_core (narrower core).
// 5. Cell size and tolerance: doubling L or tightening the tolerance 10x changes tau_P by < 2%.
//    At L = 256 this holds for narrow cores only: the line's periodic images (L/|m| apart) shift
//    tau_P by an amount growing with b_core |m| and falling as 1/L^2 (edge at 12 d and the
//    63.4 degree line at 6 d change by more than 2% from L = 256 to 512). The scan therefore
//    doubles L until tau_P changes by less than 1% (peierls_stress_converged): for those hard
//    cases the converged cell, doubled once more, changes tau_P by < 0.5% (about 1/4 of the
//    last change, <= 1%, from the 1/L^2 law; the issue asks for 2%).
// 6. The reduced chain and the full L x L cell (with a random push that lets kinks show) give
//    the same tau_P: relative difference below 1e-6 (both are bracketed on the same stresses).
// 7. Hard cases to b_core = 12 d: each point is resolved or flagged; resolved points reproduce
//    within 1% when the tolerance changes by 10x either way (or are flagged at the new floor).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <tuple>
#include <vector>

#include "asperity/peierls/peierls_stress.hpp"

using namespace asperity::peierls;

namespace {

PeierlsResult run(double b_core, int mx, int my, int L = 256, double tolerance = 1e-3,
                  CellModel model = CellModel::reduced, double nu = 0.5) {
  PeierlsOptions o;
  o.cell.b_core = b_core;
  o.cell.mx = mx;
  o.cell.my = my;
  o.cell.L = L;
  o.cell.model = model;
  o.cell.material.nu = nu;
  o.tolerance = tolerance;
  return peierls_stress(o);
}

double ratio(const PeierlsResult& r) {
  return r.positive.tau_P / r.tau_max;
}

}  // namespace

TEST(PeierlsCore, RelaxedWidthFollowsTheContinuumPeierlsNabarroWidth) {
  for (double nu : {0.5, 0.25}) {
    for (double b : {4.0, 6.0, 8.0}) {
      const PeierlsResult edge = run(b, 1, 0, 256, 1e-3, CellModel::reduced, nu);
      const PeierlsResult screw = run(b, 0, 1, 256, 1e-3, CellModel::reduced, nu);
      const double edge_expected = b / (std::acos(-1.0) * (1.0 - nu));
      const double screw_expected = b / std::acos(-1.0);
      EXPECT_NEAR(edge.core_width / edge_expected, 1.0, 0.05) << "edge b=" << b << " nu=" << nu;
      EXPECT_NEAR(screw.core_width / screw_expected, 1.0, 0.05) << "screw b=" << b << " nu=" << nu;
      EXPECT_NEAR(edge.core_width / screw.core_width * (1.0 - nu), 1.0, 0.05)
          << "edge/screw b=" << b << " nu=" << nu;
      EXPECT_DOUBLE_EQ(edge.core_width_continuum, edge_expected);
    }
  }
}

TEST(PeierlsStress, ScrewAtTwiceTheCoreWidthBehavesLikeEdgeAtNuOneHalf) {
  for (double b : {2.0, 4.0, 6.0}) {
    const PeierlsResult edge = run(b, 1, 0);
    const PeierlsResult screw = run(2.0 * b, 0, 1);
    ASSERT_TRUE(edge.positive.resolved && screw.positive.resolved);
    EXPECT_NEAR(ratio(screw) / ratio(edge), 1.0, 1e-9) << "b = " << b;
    EXPECT_NEAR(screw.core_width / edge.core_width, 1.0, 1e-9) << "b = " << b;
  }
}

TEST(PeierlsStress, EdgeDecaysExponentiallyBelowTheRigidProfileEstimate) {
  std::vector<double> b = {6, 8, 10, 12}, tau;
  for (double x : b) {
    const PeierlsResult r = run(x, 1, 0);
    ASSERT_TRUE(r.positive.resolved) << "b = " << x;
    tau.push_back(ratio(r));
    EXPECT_LT(ratio(r), r.rigid_estimate) << "b = " << x;
    EXPECT_GT(ratio(r), 0.1 * r.rigid_estimate) << "b = " << x;
  }
  for (std::size_t i = 0; i + 1 < b.size(); ++i) {
    const double k2 = std::log(tau[i] / tau[i + 1]) / (b[i + 1] - b[i]);
    EXPECT_GT(k2, 1.6) << "between b = " << b[i] << " and " << b[i + 1];
    EXPECT_LT(k2, 2.0) << "between b = " << b[i] << " and " << b[i + 1];
  }
}

TEST(PeierlsStress, ScrewIsHarderThanEdgeAndBothSignsAgree) {
  for (double b : {2.0, 4.0, 6.0}) {
    const PeierlsResult edge = run(b, 1, 0);
    const PeierlsResult screw = run(b, 0, 1);
    const PeierlsResult mixed = run(b, 1, 1);
    EXPECT_GT(ratio(screw), ratio(edge)) << "b = " << b;
    for (const PeierlsResult* r : {&edge, &screw, &mixed}) {
      ASSERT_TRUE(r->positive.resolved && r->negative.resolved);
      // Both signs are bracketed to the precision; the square lattice makes them equal.
      EXPECT_NEAR(r->negative.tau_P / r->positive.tau_P, 1.0, 2e-3);
      EXPECT_LE((r->positive.upper - r->positive.lower) / (2.0 * r->positive.tau_P), 1e-3);
    }
  }
}

TEST(PeierlsStress, IndependentOfCellSizeAndTolerance) {
  for (auto [mx, my] : {std::pair{1, 0}, std::pair{0, 1}, std::pair{1, 1}, std::pair{2, 1}}) {
    const PeierlsResult base = run(4.0, mx, my, 256);
    const PeierlsResult big = run(4.0, mx, my, 512);
    const PeierlsResult tight = run(4.0, mx, my, 256, 1e-4);
    ASSERT_TRUE(base.positive.resolved && big.positive.resolved && tight.positive.resolved);
    EXPECT_NEAR(ratio(big) / ratio(base), 1.0, 0.02) << "m = (" << mx << ", " << my << ")";
    EXPECT_NEAR(ratio(tight) / ratio(base), 1.0, 0.02) << "m = (" << mx << ", " << my << ")";
  }
}

TEST(PeierlsStress, CellDoubledUntilWideCoresAreIndependentOfItsSize) {
  for (auto [b, mx, my] : {std::tuple{12.0, 1, 0}, std::tuple{6.0, 2, 1}}) {
    SCOPED_TRACE("b_core " + std::to_string(b) + ", m = (" + std::to_string(mx) + ", " +
                 std::to_string(my) + ")");
    // For the record: what the fixed default cell would change by (over 2% here).
    const double fixed_change = ratio(run(b, mx, my, 512)) / ratio(run(b, mx, my, 256)) - 1.0;
    PeierlsOptions o;
    o.cell.b_core = b;
    o.cell.mx = mx;
    o.cell.my = my;
    const CellSizeResult c = peierls_stress_converged(o, CellSizeOptions{.tolerance = 0.01});
    ASSERT_TRUE(c.converged && c.result.positive.resolved);
    EXPECT_LE(c.change, 0.01);
    EXPECT_GT(c.result.L, 256);
    const PeierlsResult doubled = run(b, mx, my, 2 * c.result.L);
    // Issue 5 asks for 2%; the 1/L^2 law predicts about a quarter of the last change (<= 1%).
    EXPECT_NEAR(ratio(doubled) / ratio(c.result), 1.0, 0.005);
    std::printf(
        "b_core %g, m = (%d, %d): L 256 -> 512 changes tau_P by %.2f%%; converged at L = "
        "%d (last change %.2f%%), doubled again: %.2f%%\n",
        b, mx, my, 100 * fixed_change, c.result.L, 100 * c.change,
        100 * (ratio(doubled) / ratio(c.result) - 1.0));
  }
}

TEST(PeierlsStress, ReducedChainEqualsTheFullCellWithAPush) {
  for (auto [mx, my] : {std::pair{1, 0}, std::pair{0, 1}, std::pair{2, 1}}) {
    const PeierlsResult reduced = run(4.0, mx, my, 64);
    const PeierlsResult full = run(4.0, mx, my, 64, 1e-3, CellModel::full);
    ASSERT_TRUE(reduced.positive.resolved && full.positive.resolved);
    EXPECT_NEAR(ratio(full) / ratio(reduced), 1.0, 1e-6) << "m = (" << mx << ", " << my << ")";
    EXPECT_NEAR(full.core_width, reduced.core_width, 1e-6);
  }
}

TEST(PeierlsStress, HardCasesAreResolvedStablyOrFlagged) {
  int resolved = 0, flagged = 0;
  for (auto [mx, my] : {std::pair{1, 0}, std::pair{2, 1}}) {
    for (double b : {8.0, 10.0, 12.0}) {
      const PeierlsResult r = run(b, mx, my);
      if (!r.positive.resolved) {
        ++flagged;
        EXPECT_GT(r.positive.floor, 0.0);
        EXPECT_LE(r.positive.upper, 8.0 * r.positive.floor + 1e-300);
        continue;
      }
      ++resolved;
      EXPECT_GE(r.positive.lower, r.positive.floor);
      for (double tol : {1e-4, 1e-2}) {
        const PeierlsResult p = run(b, mx, my, 256, tol);
        if (p.positive.resolved) {
          EXPECT_NEAR(ratio(p) / ratio(r), 1.0, 0.01)
              << "b = " << b << " m = (" << mx << ", " << my << ") tol " << tol;
        } else {
          // Only a tighter tolerance raises the floor past a threshold resolved before.
          EXPECT_LT(tol, 1e-3);
          EXPECT_GT(p.positive.floor, r.positive.lower);
        }
      }
    }
  }
  EXPECT_GT(resolved, 0);
  EXPECT_GT(flagged, 0);  // 63.4 degrees at b_core = 12 d is far below round-off
}
