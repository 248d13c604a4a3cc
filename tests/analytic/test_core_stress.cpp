// Analytic tier: the stress on a core (tracking::core_stress, MODEL.md 6 and 7) in a Peierls
// cell loaded by a uniform stress tau_ext.
//
// Answer: the cell's balance is K u = f + tau_ext d^2 on every site (K the periodic half-space
// stiffness, K(0) = 0; f the interface force, tau_x = f / d^2). For an edge line along y, u
// depends on x alone, and u is the periodic sawtooth of the line: odd about the core up to a
// constant, which K(0) = 0 removes. Weighted by the core's slip density rho (the change of the
// registry offset over each bond), sum rho (K u) vanishes over a whole period, since for bonds
// sum_k (u_k+1 - u_k)(v_k + v_k+1)/2 = -sum_k u_k (v_k+1 - v_k-1)/2 is an antisymmetric form
// in u for v = K u with K symmetric and translation-invariant (and the frustration's ramp adds
// sum K u = 0). So the weighted mean of tau_x over a whole period is -tau_ext exactly: the
// lattice holds the core against the load.
//
// Tolerance: only the relaxation's residual is left: at most `tolerance` * tau_ext per site
// (PeierlsOptions, 1e-3), and rho keeps one sign, so 2e-3 tau_ext; at zero stress (relaxed to
// round-off) 1e-10 tau_max. The narrow (b_core = 2 d, tau_P = 0.06 tau_max) and the wide core
// (6 d, tau_P = 5e-5 tau_max: a tiny Peierls stress) are both held to it.
//
// A window of the row around the core (as track_loops takes in a contact) leaves out the rest of
// the core's tail. Since the whole period is exact, what the window's mean differs by is the
// left-out bonds' share: |error| <= sum_out |rho_k| (|tau_k| + tau_ext) / |slip in the window|,
// a bound computed from the state itself. An asymmetric window (4 d on one side, 12 d on the
// other) is held to it: the weight pairs the core's swing across the core, where a plain mean
// over that window would keep the swing's excess on the long side.
//
// The period must be whole. The row of the snapshot has L sites and L - 1 bonds; the bond across
// the cell's side (X = L - 1 to 0) is added by extending the row by one site. Left out, it
// weighs the stress there (the periodic self-stress of the line array, about 4e-4 G half a
// site from the antipode) by the core's tail there (1.5e-3 at b_core = 6 d): 5e-7 G, 7% of the
// wide core's tau_P. In a contact the window is a stretch of a profile around each core, and
// what it leaves out of the core's tail errs so (docs/tracking.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "asperity/peierls/peierls_stress.hpp"
#include "asperity/peierls/scan.hpp"
#include "asperity/tracking/lines.hpp"
#include "asperity/tracking/profile.hpp"

using namespace asperity;

namespace {

struct Cores {
  double tau_ext = 0.0, tau_max = 0.0, tau_P = 0.0;
  tracking::CoreStress zero, loaded;
  // The loaded core in windows from 4 d before to 12 d after it and the reverse, with the
  // bound of each from what it leaves out.
  tracking::CoreStress before, after;
  double before_bound = 0.0, after_bound = 0.0;
  tracking::CrossingStress crossing;
  double crossing_bound = 0.0;
};

Cores run(double b_core) {
  peierls::PeierlsOptions o;
  o.cell.L = 64;
  o.cell.b_core = b_core;
  o.cell.mx = 1;  // an edge line along y: it crosses the row y = 0 once
  o.cell.my = 0;
  o.both_signs = false;
  const peierls::PeierlsResult r = peierls::peierls_stress(o);
  EXPECT_TRUE(r.positive.resolved) << "b_core " << b_core;
  const peierls::PeierlsCell cell(o.cell);
  const auto profile = [&](const std::vector<double>& u, double tau) {
    const slide::Snapshot s = peierls::cell_snapshot(cell, u, "cell", tau);
    tracking::StressProfile p = tracking::stress_profile(s, tracking::ProfileAxis::x);
    // One site more, X = L: site X = 0 a period on, its offset s_x - X lower by m_x d.
    p.position.push_back(p.position.front() + o.cell.L);
    p.offset.push_back(p.offset.front() - o.cell.mx);
    p.tau_x.push_back(p.tau_x.front());
    p.in_contact.push_back(1);
    return p;
  };
  const auto whole = [](const tracking::StressProfile& p) {
    return tracking::core_stress(p, p.position.front(), p.position.back());
  };
  Cores c{.tau_ext = r.tau_loaded,
          .tau_max = r.tau_max,
          .tau_P = r.positive.tau_P,
          .zero = whole(profile(r.u_zero, 0.0))};
  const tracking::StressProfile p = profile(r.u_loaded, r.tau_loaded);
  c.loaded = whole(p);
  // The core: where the offset is halfway between its values at the row's ends.
  const double half = 0.5 * (p.offset.front() + p.offset.back());
  std::size_t k = 0;
  while (k + 1 < p.offset.size() && (p.offset[k + 1] - half) * (p.offset[0] - half) > 0.0)
    ++k;
  const double core = p.position[k] + (half - p.offset[k]) / (p.offset[k + 1] - p.offset[k]);
  // What a window [from, to] leaves out of each bond (a bond cut by an end counts by its
  // fraction inside), weighed by the most it can change the mean.
  const auto bound = [&](double from, double to, const tracking::CoreStress& in) {
    double out = 0.0;
    for (std::size_t j = 0; j + 1 < p.position.size(); ++j) {
      const double inside =
          std::clamp((std::min(p.position[j + 1], to) - std::max(p.position[j], from)) /
                         (p.position[j + 1] - p.position[j]),
                     0.0, 1.0);
      out += (1.0 - inside) * std::abs(p.offset[j + 1] - p.offset[j]) *
             (0.5 * std::abs(p.tau_x[j] + p.tau_x[j + 1]) + c.tau_ext);
    }
    return out / std::abs(in.slip);
  };
  c.before = tracking::core_stress(p, core - 4.0, core + 12.0);
  c.before_bound = bound(core - 4.0, core + 12.0, c.before);
  c.after = tracking::core_stress(p, core - 12.0, core + 4.0);
  c.after_bound = bound(core - 12.0, core + 4.0, c.after);
  // The window track_loops takes: crossing_stresses at the core, 4 b_core either side.
  const std::vector<tracking::CoreCrossing> crossing = {{.position = core}};
  c.crossing = tracking::crossing_stresses(p, crossing).at(0);
  c.crossing_bound =
      bound(core - c.crossing.half_width, core + c.crossing.half_width, c.crossing.stress);
  return c;
}

}  // namespace

TEST(CoreStress, ARelaxedCoreHoldsTheLoadOfItsCell) {
  for (const double b_core : {2.0, 6.0}) {
    const Cores c = run(b_core);
    ASSERT_GT(c.tau_ext, 0.0);
    // The load is the last stable one, within the bracket's precision of tau_P.
    EXPECT_NEAR(c.tau_ext / c.tau_P, 1.0, 2e-3);
    // A whole period holds the core's whole slip: the offset falls by d across the line.
    EXPECT_NEAR(c.loaded.slip, -1.0, 1e-12) << "b_core " << b_core;
    EXPECT_EQ(c.loaded.bonds, 64);
    EXPECT_NEAR(c.loaded.tau, -c.tau_ext, 2e-3 * c.tau_ext)
        << "b_core " << b_core << ": tau_ext " << c.tau_ext << ", tau_max " << c.tau_max;
    EXPECT_NEAR(c.zero.tau, 0.0, 1e-10 * c.tau_max) << "b_core " << b_core;
    // Windows of 16 d around the core, off-centre both ways: within the bound of what they
    // leave out (plus the residual). A plain mean over them misses it by 2.6-7 times the bound.
    for (const auto& [w, bound] : {std::pair{c.before, c.before_bound}, {c.after, c.after_bound}}) {
      EXPECT_GE(w.bonds, 15);
      EXPECT_NEAR(w.tau, -c.tau_ext, bound + 2e-3 * c.tau_ext) << "b_core " << b_core;
    }
    // The window of track_loops and slips.csv: 4 b_core either side of the crossing, uncut here
    // (one core in the row, all in contact), so resolved; within its bound like any window.
    EXPECT_NEAR(c.crossing.half_width, 4.0 * b_core, 1e-12);
    EXPECT_TRUE(c.crossing.resolved()) << "b_core " << b_core;
    EXPECT_NEAR(c.crossing.stress.tau, -c.tau_ext, c.crossing_bound + 2e-3 * c.tau_ext)
        << "b_core " << b_core;
    std::printf(
        "b_core %g: crossing window +-%g d: %.6e against the load %.6e (tau_P); error "
        "%.2e G = %.2e tau_max, bound %.2e\n",
        b_core, c.crossing.half_width, c.crossing.stress.tau, c.tau_ext,
        std::abs(c.crossing.stress.tau + c.tau_ext),
        std::abs(c.crossing.stress.tau + c.tau_ext) / c.tau_max, c.crossing_bound);
  }
}

// The whole front (tracking::front_stresses): a straight line of any direction in a loaded cell
// holds the load all along it. Answer: -tau_ext, as above. The sites of a stretch of a straight
// line normal to m = (m_x, m_y) are copies of the cell's chain, v = m_x X + m_y Y, d / |m|
// apart along the normal (tracking/profile.hpp); the default stretch of 32 d holds every chain
// site for these directions (|m| <= 8.1), and in order of s_x - X they are the chain in order,
// so the weight is the chain's, whose whole period is exact (above). Tolerance: the
// relaxation's residual (2e-3 tau_ext, above) plus what the window leaves out of the chain,
// bounded as above from the state, over the chain's bonds farther than h - 1 d from the point
// (the traced line lies within a site of the core's centre). Directions up to (8, 1) and (1, 8),
// 7.1 degrees from edge and screw; a stretch of 8 d (a part of their period) misses (8, 1) by
// 2.2 tau_P and (1, 8) by 3.6, and single rows or columns miss (2, 1) by 2 tau_P, (1, 3) by 6.
TEST(CoreStress, AStraightFrontOfAnyDirectionHoldsTheLoadAllAlong) {
  struct Case {
    int mx, my;
  };
  for (const Case& k :
       {Case{1, 0}, Case{0, 1}, Case{1, 1}, Case{2, 1}, Case{1, 2}, Case{3, 1}, Case{3, 2},
        Case{1, 3}, Case{4, 1}, Case{5, 1}, Case{1, 5}, Case{8, 1}, Case{1, 8}}) {
    // Line images L / |m| apart: at least 25 d, so that a window of 8 d either side holds one,
    // and a block wide enough that stretches of 32 d lie inside it, across lines crossing it
    // obliquely.
    const int L = std::hypot(k.mx, k.my) > 3.0 ? 256 : 128;
    peierls::PeierlsOptions o;
    o.cell.L = L;
    o.cell.b_core = 2.0;
    o.cell.mx = k.mx;
    o.cell.my = k.my;
    o.both_signs = false;
    const peierls::PeierlsResult r = peierls::peierls_stress(o);
    ASSERT_TRUE(r.positive.resolved) << k.mx << "," << k.my;
    const peierls::PeierlsCell cell(o.cell);
    const slide::Snapshot s = peierls::cell_snapshot(cell, r.u_loaded, "cell", r.tau_loaded);
    const tracking::FrameLines lines = tracking::find_lines(tracking::view_of(s, true));
    ASSERT_FALSE(lines.lines.empty());
    const std::vector<tracking::FrontStress> front = tracking::front_stresses(s, lines);
    const double norm = std::hypot(k.mx, k.my);
    // The chain around a value v0 of v: one site per v in [v0 - L/2, v0 + L/2), its offset
    // s_x - X continuous there (the frustration winds by whole periods only across the cell).
    struct Site {
      double xi, offset, tau;
    };
    const auto chain = [&](double v0) {
      std::vector<Site> c;
      const int first = static_cast<int>(std::lround(v0)) - L / 2;
      for (int v = first; v < first + L; ++v) {
        for (int X = 0; X < L; ++X) {
          const int rest = v - k.mx * X;
          const int Y = k.my == 0 ? 0 : rest / k.my;
          if ((k.my == 0 && rest != 0) || (k.my != 0 && (rest % k.my != 0 || Y < 0 || Y >= L)))
            continue;
          const std::size_t i = static_cast<std::size_t>(X) * static_cast<std::size_t>(L) +
                                static_cast<std::size_t>(Y);
          c.push_back({v / norm, s.sx[i] - X, s.tau_x[i]});
          break;
        }
      }
      return c;
    };
    int resolved = 0, checked = 0;
    double worst = 0.0, angle = 0.0;
    for (const tracking::FrontStress& f : front) {
      angle += f.angle_deg;
      if (!f.resolved()) continue;
      ++resolved;
      const double v0 = k.mx * f.at.x + k.my * f.at.y;
      const std::vector<Site> c = chain(v0);
      // Values of v that no site of the block takes (near its corner) merge two bonds of the
      // chain into one, which the bound still counts; a chain short of more than a few leaves
      // the block on the window's side.
      if (c.size() + 8 < static_cast<std::size_t>(L)) continue;
      ++checked;
      double out = 0.0;
      for (std::size_t j = 0; j + 1 < c.size(); ++j) {
        const double mid = 0.5 * (c[j].xi + c[j + 1].xi) - v0 / norm;
        if (std::abs(mid) <= f.half_width - 1.0) continue;
        out += std::abs(c[j + 1].offset - c[j].offset) *
               (0.5 * std::abs(c[j].tau + c[j + 1].tau) + r.tau_loaded);
      }
      const double bound = out / std::abs(f.held.slip) + 2e-3 * r.tau_loaded;
      const double e = std::abs(f.held.tau + r.tau_loaded);
      worst = std::max(worst, e / r.positive.tau_P);
      EXPECT_LE(e, bound) << "m = (" << k.mx << ", " << k.my << ") at (" << f.at.x << ", " << f.at.y
                          << ")";
      EXPECT_NEAR(f.half_width, 4.0 * o.cell.b_core, 1e-9);
    }
    // The block does not wrap: windows near its sides are cut; the others resolve.
    EXPECT_GE(checked, 2) << "m = (" << k.mx << ", " << k.my << ")";
    EXPECT_NEAR(angle / static_cast<double>(front.size()), r.theta_deg, 2.0);
    std::printf(
        "m = (%d, %d), theta %.1f deg (mean %.2f): %zu points, %d resolved, %d checked; "
        "worst %.2e of tau_P (tau_P %.3e tau_max)\n",
        k.mx, k.my, r.theta_deg, angle / static_cast<double>(front.size()), front.size(), resolved,
        checked, worst, r.positive.tau_P / r.tau_max);
  }
}
