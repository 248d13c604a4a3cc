// The pure functions over a trace (slide/trace.hpp; MODEL.md 5). The stop rule of the
// automatic distance (detail::peak_held):
// the static peak must have held over a period d with slips_to_stop slip events after it, and
// the slide stops at a slip that leaves Fx/Fz below the peak by more than the trace's
// resolution. Synthetic traces, d = 1, two slips wanted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "asperity/core/slide/trace.hpp"

using namespace asperity;
using slide::TraceRow;

namespace {

TraceRow row(double Dx, double ratio, bool slip) {
  return TraceRow{.Dx = Dx, .Fx = ratio * 100.0, .Fz = 100.0, .slip = slip};
}

// The first prefix of `t` (ending at a row) at which the rule says the peak held, or -1; the
// peak is the largest Fx/Fz of the prefix, as the slide keeps it.
int first_stop(const std::vector<TraceRow>& t) {
  double best = 0.0;
  for (std::size_t k = 1; k <= t.size(); ++k) {
    const TraceRow& last = t[k - 1];
    best = std::max(best, last.Fx / last.Fz);
    if (slide::detail::peak_held(std::span(t.data(), k), best, last.Fx / last.Fz, last.Dx, 1.0,
                                 2)) {
      return static_cast<int>(k) - 1;
    }
  }
  return -1;
}

}  // namespace

// Regime II: stick (stable rows rising to 0.5) and one large slip per period, repeated.
TEST(PeakRule, ARepeatedStickSlipCycleHoldsAtItsSecondSlip) {
  std::vector<TraceRow> t{row(0.0, 0.0, false)};
  for (int cycle = 0; cycle < 4; ++cycle) {
    for (int k = 1; k <= 8; ++k)
      t.push_back(row(cycle + 0.1 * k, 0.3 + 0.025 * k, false));  // up to 0.5 at +0.8
    t.push_back(row(cycle + 0.9, 0.3, true));                     // the slip
  }
  // Peak first reached at Dx = 0.8; held from there over d with two slips after it: the slip at
  // 1.9 (the second after 0.8 is at 1.9, one period on).
  const int stop = first_stop(t);
  ASSERT_GE(stop, 0);
  EXPECT_DOUBLE_EQ(t[static_cast<std::size_t>(stop)].Dx, 1.9);
}

// Regime III steady state: Fx rises through a run of tiny slips with no stable row between them
// (every row a slip), peaks on one and drops at a larger slip, the same every period (as at
// R = 40 d, a = 36 d from 11.6 d on). Before the rule counted slip rows as samples, no row ever
// held and the slide ran to its cap.
TEST(PeakRule, APeakOnARunOfTinySlipsHolds) {
  std::vector<TraceRow> t{row(0.0, 0.0, false)};
  for (int k = 1; k <= 20; ++k)
    t.push_back(row(0.02 * k, 0.01 * k, false));  // loading ramp to 0.2 (resolution 0.01)
  for (int cycle = 0; cycle < 4; ++cycle) {
    for (int k = 1; k <= 6; ++k)
      t.push_back(row(0.4 + cycle + 0.1 * k, 0.20 + 0.01 * k, true));  // tiny slips, up to 0.26
    for (int k = 7; k <= 10; ++k)
      t.push_back(row(0.4 + cycle + 0.1 * k, 0.26 - 0.02 * (k - 6), true));  // larger ones
  }
  // Peak 0.26 first at Dx = 1.0; held one period later, at the first slip row below
  // 0.26 - 0.01 (the ramp's resolution) with Dx >= 2.0: Dx = 2.1 (0.24).
  const int stop = first_stop(t);
  ASSERT_GE(stop, 0);
  EXPECT_NEAR(t[static_cast<std::size_t>(stop)].Dx, 2.1, 1e-12);
  EXPECT_NEAR(t[static_cast<std::size_t>(stop)].Fx / t[static_cast<std::size_t>(stop)].Fz, 0.24,
              1e-12);
}

// Still hardening: every period's peak above the last by more than the tie (Regime III before
// its steady state): the rule never stops.
TEST(PeakRule, AFrictionStillRisingNeverHolds) {
  std::vector<TraceRow> t{row(0.0, 0.0, false)};
  for (int cycle = 0; cycle < 6; ++cycle) {
    for (int k = 1; k <= 5; ++k)
      t.push_back(row(cycle + 0.1 * k, 0.2 + 0.01 * cycle + 0.002 * k, k == 5));
    for (int k = 6; k <= 10; ++k)
      t.push_back(row(cycle + 0.1 * k, 0.19 + 0.01 * cycle, true));
  }
  EXPECT_EQ(first_stop(t), -1);
}

// The slide does not stop while Fx lies within the trace's resolution of the peak, nor on a
// stable row.
TEST(PeakRule, NoStopWithinTheTieOrOnAStableRow) {
  // Peak 0.3 at Dx = 0.4, resolved to 0.01 by its neighbours.
  std::vector<TraceRow> t{row(0.0, 0.0, false),  row(0.1, 0.1, false), row(0.2, 0.2, false),
                          row(0.3, 0.29, false), row(0.4, 0.3, false), row(0.5, 0.295, false),
                          row(0.6, 0.2, true),   row(1.0, 0.25, true), row(1.7, 0.295, true)};
  EXPECT_FALSE(slide::detail::peak_held(t, 0.3, 0.295, 1.7, 1.0, 2));  // within 0.01 of it
  t.push_back(row(1.8, 0.1, false));
  EXPECT_FALSE(slide::detail::peak_held(t, 0.3, 0.1, 1.8, 1.0, 2));  // a stable row
  t.back().slip = true;
  EXPECT_TRUE(slide::detail::peak_held(t, 0.3, 0.1, 1.8, 1.0, 2));
}

// Kinetic friction (detail::kinetic_friction): the Dx-weighted mean of Fx/Fz after the first
// slip, by trapezoids on uneven steps: rows (1, 0.2 slip), (1.5, 0.4), (3, 0.1) give
// (0.5 * 0.3 + 1.5 * 0.25) / 2 = 0.2625. Without slips, over the last period d; NaN on a slide
// shorter than d without slips.
TEST(KineticFriction, TrapezoidMeanAfterTheFirstSlipOrOverTheLastPeriod) {
  const std::vector<TraceRow> slipping = {row(0.0, 0.0, false), row(0.5, 0.9, false),
                                          row(1.0, 0.2, true), row(1.5, 0.4, false),
                                          row(3.0, 0.1, false)};
  EXPECT_DOUBLE_EQ(slide::detail::kinetic_friction(slipping, 3.0, 1.0), 0.2625);
  const std::vector<TraceRow> smooth = {row(0.0, 0.0, false), row(1.0, 0.8, false),
                                        row(1.5, 0.4, false), row(2.5, 0.6, false)};
  // The last period starts at Dx = 1.5: (1.0 * 0.5) / 1.0.
  EXPECT_DOUBLE_EQ(slide::detail::kinetic_friction(smooth, 2.5, 1.0), 0.5);
  EXPECT_TRUE(std::isnan(slide::detail::kinetic_friction(smooth, 0.8, 1.0)));
}

// The peak parabola (detail::PeakBracket): through three samples of y = 0.5 - 2 (x - 0.3)^2 the
// vertex is x = 0.3, y = 0.5 exactly (a parabola is its own interpolant; tolerance: a few ulps
// of the divided differences). Not concave (y = x^2): the middle sample itself.
TEST(PeakBracket, VertexOfTheParabolaThroughThreeSamples) {
  const auto y = [](double x) { return 0.5 - 2.0 * (x - 0.3) * (x - 0.3); };
  const slide::detail::PeakBracket b{0.1, 0.25, 0.6, y(0.1), y(0.25), y(0.6)};
  double yv = 0.0;
  EXPECT_NEAR(b.vertex(yv), 0.3, 1e-14);
  EXPECT_NEAR(yv, 0.5, 1e-14);
  const slide::detail::PeakBracket convex{-1.0, 0.5, 1.0, 1.0, 0.25, 1.0};
  EXPECT_EQ(convex.vertex(yv), 0.5);
}

// mu's resolution before a slip (detail::peak_precision_before_slip): the step to the slip
// times the slope before the peak: rows (1.0, 0.30), (1.2, 0.34), slip at 1.25 give
// 0.05 * 0.04 / 0.2 = 0.01.
TEST(PeakBracket, PrecisionBeforeASlipIsTheSlopeTimesTheStep) {
  EXPECT_NEAR(slide::detail::peak_precision_before_slip(
                  row(1.0, 0.30, false), row(1.2, 0.34, false), row(1.25, 0.2, true)),
              0.01, 1e-15);
}
