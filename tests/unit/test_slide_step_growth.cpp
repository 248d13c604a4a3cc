// slide.step_growth (SlideOptions::step_growth, MODEL.md 5): in the adaptive protocol the step
// after a slip event restarts at min_step and doubles (here) with every accepted step up to
// max_step, instead of trying max_step at once. Before the first slip nothing changes.
//
// 1. Regime II (a = 20 d, R = 535 d): the path up to the first slip is the same bit for bit, so
//    mu (the peak before it) is the same; after each computed slip the next state lies exactly
//    min_step further; the cycle probe still finds the repeating cycle (it waits until a step
//    reaches a state one period back) and the second cycle is replayed.
// 2. Regime III (R = 20 d, a = 15 d, the scene of test_regime_three.cpp: loops arrested, many
//    small slips): the growing step costs fewer GF applications, and mu/alpha agrees with the
//    full-step protocol within the bracket's resolution. Both protocols take each slip from a
//    stable state less than min_step before its instability, but not from the same one, so the
//    paths after the first slip differ within that resolution. The bound below is min_step times
//    the loading slope dFx/dDx of the trace, divided by Fz: how far mu can move when the state a
//    slip starts from moves by min_step (measured: see the printed line).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "asperity/core/slide/slider.hpp"
#include "common/scenes.hpp"

using namespace asperity;

namespace {

// The steepest loading slope dFx/dDx between consecutive stable rows (G d).
double loading_slope(const slide::SlideResult& r) {
  double k = 0.0;
  for (std::size_t i = 1; i < r.trace.size(); ++i) {
    const auto &a = r.trace[i - 1], &b = r.trace[i];
    if (b.slip || b.replayed || !(b.Dx > a.Dx)) continue;
    k = std::max(k, (b.Fx - a.Fx) / (b.Dx - a.Dx));
  }
  return k;
}

// The slide of `scene` with the full step and with step growth 2 (one FFT thread each), both
// required to finish.
struct BothSlides {
  slide::SlideOptions full, grow;
  slide::SlideResult r0, rg;
};
BothSlides slide_both(const interface::ContactScene& scene) {
  BothSlides b;
  b.full.fft.threads = 1;
  b.grow = b.full;
  b.grow.step_growth = 2.0;
  b.r0 = slide::slide(scene, b.full);
  b.rg = slide::slide(scene, b.grow);
  EXPECT_FALSE(b.r0.failed) << b.r0.stop_reason;
  EXPECT_FALSE(b.rg.failed) << b.rg.stop_reason;
  return b;
}

}  // namespace

TEST(SlideStepGrowth, RegimeTwoKeepsThePeakStepsFromMinStepAndStillReplays) {
  interface::ContactScene scene;
  scene.a = 20.0;
  scene.R = 535.0;
  const BothSlides both = slide_both(scene);
  const auto& grow = both.grow;
  const slide::SlideResult &r0 = both.r0, &rg = both.rg;
  ASSERT_FALSE(r0.failed || rg.failed);
  ASSERT_GE(rg.slip_events, 1);

  // Up to and including the first slip the rows are the same.
  std::size_t first_slip = 0;
  while (first_slip < r0.trace.size() && !r0.trace[first_slip].slip)
    ++first_slip;
  ASSERT_LT(first_slip, r0.trace.size());
  ASSERT_GT(rg.trace.size(), first_slip);
  for (std::size_t i = 0; i <= first_slip; ++i) {
    EXPECT_EQ(rg.trace[i].Dx, r0.trace[i].Dx) << "row " << i;
    EXPECT_EQ(rg.trace[i].Fx, r0.trace[i].Fx) << "row " << i;
  }
  EXPECT_EQ(rg.mu, r0.mu);
  EXPECT_EQ(rg.peak_Dx, r0.peak_Dx);
  EXPECT_EQ(rg.slip_events, r0.slip_events);

  // After each computed slip the next row is min_step on; the steps then grow.
  int checked = 0;
  for (std::size_t i = 0; i + 1 < rg.trace.size(); ++i) {
    const auto &s = rg.trace[i], &n = rg.trace[i + 1];
    if (!s.slip || s.replayed || n.replayed) continue;
    EXPECT_NEAR(n.Dx - s.Dx, grow.min_step, 1e-12) << "row " << i + 1;
    ++checked;
  }
  EXPECT_GT(checked, 0);
  std::size_t largest_after = 0;
  for (std::size_t i = first_slip + 1; i + 1 < rg.trace.size(); ++i) {
    if (rg.trace[i + 1].replayed) break;
    largest_after = std::max<std::size_t>(
        largest_after, static_cast<std::size_t>(
                           std::lround((rg.trace[i + 1].Dx - rg.trace[i].Dx) / grow.min_step)));
  }
  EXPECT_GE(largest_after, 4u) << "the step did not grow after the slip";

  // The probe still finds the repeating cycle.
  EXPECT_GT(r0.replayed_steps, 0);
  EXPECT_GT(rg.replayed_steps, 0);
  std::printf(
      "Regime II a = 20 d: mu/alpha %.6f (both); full step: %d steps + %d replayed, %zu GF; "
      "growing step: %d + %d, %zu GF\n",
      rg.mu_over_alpha, r0.steps, r0.replayed_steps, r0.gf_applications, rg.steps,
      rg.replayed_steps, rg.gf_applications);

  slide::SlideOptions bad;
  bad.step_growth = 1.0;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
  bad.step_growth = -2.0;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

TEST(SlideStepGrowth, RegimeThreeCostsLessForTheSameMuWithinTheBracket) {
  const interface::ContactScene scene = test::regime_three_small();
  const BothSlides both = slide_both(scene);
  const auto& full = both.full;
  const slide::SlideResult &r0 = both.r0, &rg = both.rg;
  ASSERT_FALSE(r0.failed || rg.failed);
  ASSERT_FALSE(r0.mu_is_lower_bound);
  ASSERT_FALSE(rg.mu_is_lower_bound);
  ASSERT_GT(r0.slip_events, 10) << "not the Regime III slide this test is about";

  const double resolution = full.min_step * loading_slope(r0) / r0.trace.back().Fz;
  std::printf(
      "Regime III R = 20 d, a = 15 d: mu/alpha %.5f (full step: %d slips, %zu GF, %.2f s) vs "
      "%.5f (growing step: %d slips, %zu GF, %.2f s); |d mu| = %.2e, bound min_step k / Fz = "
      "%.2e\n",
      r0.mu_over_alpha, r0.slip_events, r0.gf_applications, r0.wall_s, rg.mu_over_alpha,
      rg.slip_events, rg.gf_applications, rg.wall_s, std::abs(rg.mu - r0.mu), resolution);
  EXPECT_LE(std::abs(rg.mu - r0.mu), resolution);
  EXPECT_LT(rg.gf_applications, r0.gf_applications);
}

// The closed-bracket test the bisection, its closing trials and bracket_slip share: positions
// are sums of steps and halvings, so a gap of min_step can come out an ulp or two over it (four
// steps of 0.01 d from 0, then one more: 0.010000000000000002). Such a gap is closed; the
// bisection's next halving of a gap over min_step (0.0125 from 0.4 halved five times) is not.
TEST(SlideStepGrowth, AClosedBracketIsMinStepWideUpToRoundOff) {
  slide::SlideOptions o;
  o.min_step = 0.01;
  double x = 0.0;
  for (int k = 0; k < 4; ++k)
    x += 0.01;
  const double gap = (x + 0.01) - x;
  EXPECT_GT(gap, 0.01);  // the round-off the slack is for
  EXPECT_TRUE(o.within_min_step(gap));
  EXPECT_TRUE(o.within_min_step(0.01));
  EXPECT_TRUE(o.within_min_step(0.00625));
  EXPECT_FALSE(o.within_min_step(0.0125));
  EXPECT_FALSE(o.within_min_step(0.0101));
}
