// Progress reports of a slide (SlideControl::progress, slide/slider.hpp) and the lines the tools
// make of them (app::describe_progress, app::ProgressLines, common/slide_io.hpp).
//
// A report comes before every relaxation (what it is, where it goes), from inside the lateral
// force model's relaxations every 16 iterations, and after every accepted step; reporting must
// not change the slide.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "asperity/apps/common/slide_io.hpp"
#include "asperity/core/slide/slider.hpp"
#include "common/relaxations.hpp"
#include "common/results.hpp"
#include "common/scenes.hpp"

using namespace asperity;
using slide::SlidePhase;
using slide::SlideProgressInfo;

namespace {

struct Recorded {
  std::vector<SlideProgressInfo> reports;
  slide::SlideResult result;
};

Recorded slide_recording(const slide::SlideOptions& options) {
  Recorded r;
  const interface::ContactScene scene {};  // a = 43 d, R = 535 d: Regime II, two slips, replay
  r.result = slide::slide(scene, options,
                          [&r](const SlideProgressInfo& info) { r.reports.push_back(info); });
  return r;
}

}  // namespace

TEST(SlideProgress, ReportsEveryRelaxationInOrderAndChangesNothing) {
  const slide::SlideOptions options;
  const Recorded rec = slide_recording(options);
  const slide::SlideResult plain = slide::slide(interface::ContactScene{}, options);
  const slide::SlideResult& res = rec.result;
  ASSERT_FALSE(res.failed) << res.stop_reason;
  ASSERT_GE(res.slip_events, 2);
  ASSERT_GT(res.replayed_steps, 0);

  // Reporting (and the observer it installs in the minimiser) leaves the slide as it was.
  EXPECT_EQ(res.mu, plain.mu);
  EXPECT_EQ(res.gf_applications, plain.gf_applications);
  ASSERT_EQ(res.trace.size(), plain.trace.size());
  for (std::size_t k = 0; k < res.trace.size(); ++k)
    EXPECT_EQ(res.trace[k].Fx, plain.trace[k].Fx) << "row " << k;

  const auto& reps = rec.reports;
  ASSERT_FALSE(reps.empty());
  EXPECT_EQ(reps.front().phase, SlidePhase::start);
  EXPECT_EQ(reps.front().iteration, 0);

  int starts = 0, heartbeats = 0;
  std::size_t row = 1;  // trace row of the next accepted report
  const SlideProgressInfo* relaxing = nullptr;
  for (std::size_t k = 0; k < reps.size(); ++k) {
    const SlideProgressInfo& r = reps[k];
    if (k > 0) {
      EXPECT_GE(r.gf_applications, reps[k - 1].gf_applications) << "report " << k;
      EXPECT_GE(r.wall_s, reps[k - 1].wall_s) << "report " << k;
      EXPECT_GE(r.slip_events, reps[k - 1].slip_events) << "report " << k;
    }
    EXPECT_DOUBLE_EQ(r.limit, reps.front().limit);
    if (r.phase == SlidePhase::accepted) {
      ASSERT_LT(row, res.trace.size());
      EXPECT_EQ(r.Dx, res.trace[row].Dx) << "report " << k;
      EXPECT_EQ(r.target_Dx, r.Dx);
      // A computed slip comes out of the relaxation of its bracketed instability.
      if (res.trace[row].slip && !res.trace[row].replayed) {
        ASSERT_NE(relaxing, nullptr);
        EXPECT_EQ(relaxing->phase, SlidePhase::slip) << "row " << row;
        EXPECT_EQ(relaxing->target_Dx, res.trace[row].Dx) << "row " << row;
      }
      ++row;
    } else if (r.iteration == 0) {
      ++starts;
      relaxing = &r;
      if (r.phase == SlidePhase::peak) {
        EXPECT_EQ(row, res.trace.size()) << "the peak is refined after the stepping";
      }
    } else {
      ++heartbeats;
      ASSERT_NE(relaxing, nullptr);
      EXPECT_EQ(r.iteration % 16, 0);
      EXPECT_EQ(r.phase, relaxing->phase) << "report " << k;
      EXPECT_EQ(r.target_Dx, relaxing->target_Dx) << "report " << k;
    }
  }
  EXPECT_EQ(row, res.trace.size()) << "one accepted report per row after the first";
  EXPECT_EQ(starts, res.minimizations) << "one start report per relaxation";
  EXPECT_GT(heartbeats, 0) << "the slips take hundreds of iterations";
  EXPECT_LE(reps.back().gf_applications, res.gf_applications);
}

// With a slip minimiser, a trial at most min_step from the stable state (a bisection's last, or
// the first step after a slip under step growth) that slips is the slip itself: it goes to the
// flow at once, not undone and relaxed again by the fast minimiser from the same state to the
// same Dx (which repeated the same relaxation to the same verdict: plan(), protocol.hpp). So no
// tip position gets more than two relaxations from one state, and the second is the flow's.
TEST(SlideProgress, ASlipIsNotRelaxedTwiceFromTheSameState) {
  slide::SlideOptions options;
  options.slip_minimizer = slide::slip_minimizer_from(options.minimizer, minimize::Method::flow,
                                                      minimize::Preconditioner::interface);
  // A bracket 0.05 d wide: the bisection of the first slip ends with a trial that slips (at
  // 0.01 d it ends with a stable one here, and the slip is relaxed from there).
  options.min_step = 0.05;
  options.step_growth = 2.0;  // the first step after a slip is min_step wide
  const Recorded rec = slide_recording(options);
  const slide::SlideResult& res = rec.result;
  ASSERT_FALSE(res.failed) << res.stop_reason;
  ASSERT_GE(res.slip_events, 2);
  int taken_at_once = 0;  // slips whose flow follows a step or bisection trial directly
  std::vector<const SlideProgressInfo*> since;  // relaxations started since the last accepted
  for (const SlideProgressInfo& r : rec.reports) {
    if (r.phase == SlidePhase::accepted) {
      if (since.size() >= 2 && since.back()->phase == SlidePhase::slip &&
          since[since.size() - 2]->target_Dx == r.Dx &&
          since[since.size() - 2]->phase != SlidePhase::slip) {
        ++taken_at_once;
      }
      since.clear();
      continue;
    }
    if (r.iteration != 0 || r.phase == SlidePhase::peak || r.phase == SlidePhase::start) continue;
    const auto at_same = std::count_if(since.begin(), since.end(),
                                       [&](const auto* q) { return q->target_Dx == r.target_Dx; });
    EXPECT_LE(at_same, 1) << "a third relaxation to Dx = " << r.target_Dx << " from Dx = " << r.Dx;
    if (at_same == 1) {
      EXPECT_EQ(r.phase, SlidePhase::slip) << "Dx = " << r.target_Dx;
    }
    since.push_back(&r);
  }
  EXPECT_GE(taken_at_once, 1) << "no slip was taken from its trial at once in this slide";
}

TEST(SlideProgress, LinesAtTheIntervalAndAtSlipEvents) {
  SlideProgressInfo info;
  app::ProgressLines every_10s(10.0, true);
  EXPECT_TRUE(every_10s.due(info)) << "the first report";
  info.wall_s = 9.0;
  EXPECT_FALSE(every_10s.due(info));
  info.slip_events = 1;
  EXPECT_TRUE(every_10s.due(info)) << "a new slip event";
  info.wall_s = 18.0;
  EXPECT_FALSE(every_10s.due(info)) << "10 s after the last line, not the first";
  info.wall_s = 19.5;
  EXPECT_TRUE(every_10s.due(info));

  app::ProgressLines quiet(60.0);
  info = {};
  EXPECT_TRUE(quiet.due(info));
  info.slip_events = 3;
  info.wall_s = 30.0;
  EXPECT_FALSE(quiet.due(info)) << "slip events do not count without each_slip";
}

TEST(SlideProgress, DescribesPositionCostAndRelaxation) {
  SlideProgressInfo info{.phase = SlidePhase::slip,
                         .Dx = 4.625,
                         .target_Dx = 4.626,
                         .limit = 9.25,
                         .slip_events = 1,
                         .steps = 25,
                         .replayed_steps = 7,
                         .gf_applications = 801,
                         .wall_s = 324.0,
                         .iteration = 3200};
  EXPECT_EQ(app::describe_progress(info),
            "Dx = 4.6250 d of at most 9.25 d, 1 slip event, 25 steps + 7 replayed, 801 GF, "
            "5.4 min; relaxing the slip at Dx = 4.6260 d, iteration 3200");
  info.phase = SlidePhase::accepted;
  info.replayed_steps = 0;
  info.wall_s = 7300.0;
  EXPECT_EQ(app::describe_progress(info),
            "Dx = 4.6250 d of at most 9.25 d, 1 slip event, 25 steps, 801 GF, 2.03 h");
  // The friction now and the largest so far, once there is a state (a = 300 d, R = 800 d after
  // its fifth slip: Fx/Fz = 5342.89 / 179999.4 against the first peak's 6587.0 / 179999.4).
  info.friction = 5342.89 / 179999.4;
  info.peak_friction = 6587.0 / 179999.4;
  EXPECT_EQ(app::describe_progress(info),
            "Dx = 4.6250 d of at most 9.25 d, 1 slip event, 25 steps, Fx/Fz 0.029683 (largest "
            "0.036595), 801 GF, 2.03 h");
  info.measure = slide::FrictionMeasure::area;
  info.friction = 0.0125;
  info.peak_friction = 0.0131;
  EXPECT_EQ(app::describe_progress(info),
            "Dx = 4.6250 d of at most 9.25 d, 1 slip event, 25 steps, Fx/area 0.0125 G (largest "
            "0.0131), 801 GF, 2.03 h");
}

// The slide reports the friction of its last accepted state and the largest so far: NaN before
// the first state, then Fx/Fz of the trace row last accepted, in every report (steps, trials,
// the peak refinement), and the running maximum of the rows (up to the 1e-6 noise guard by
// which a later maximum replaces the peak), never below the friction beside it.
TEST(SlideProgress, ReportsTheFrictionNowAndTheLargestSoFar) {
  const interface::ContactScene scene { .a = 12.0, .R = 125.0 };  // Regime I, under 0.1 s
  std::vector<SlideProgressInfo> seen;
  slide::SlideControl control;
  control.progress = [&](const SlideProgressInfo& info) { seen.push_back(info); };
  const auto r = slide::slide(scene, slide::SlideOptions{}, control);
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.front().phase, SlidePhase::start);
  EXPECT_TRUE(std::isnan(seen.front().friction));
  EXPECT_TRUE(std::isnan(seen.front().peak_friction));
  double last = r.trace.front().Fx / r.trace.front().Fz;  // the first state's
  double largest = last;
  int checked = 0, others = 0;
  bool refined = false;
  for (std::size_t k = 1; k < seen.size(); ++k) {
    const SlideProgressInfo& info = seen[k];
    ASSERT_NE(info.phase, SlidePhase::start);
    EXPECT_EQ(info.measure, slide::FrictionMeasure::load);
    EXPECT_GE(info.peak_friction, info.friction) << "report " << k;
    if (info.phase != SlidePhase::accepted) {
      EXPECT_DOUBLE_EQ(info.friction, last) << "report " << k << ": not the last accepted state's";
      refined = refined || info.phase == SlidePhase::peak;
      ++others;
      continue;
    }
    const auto row = std::find_if(r.trace.begin(), r.trace.end(),
                                  [&](const slide::TraceRow& t) { return t.Dx == info.Dx; });
    ASSERT_NE(row, r.trace.end()) << "no trace row at Dx = " << info.Dx;
    last = row->Fx / row->Fz;
    EXPECT_DOUBLE_EQ(info.friction, last);
    largest = std::max(largest, last);
    EXPECT_LE(info.peak_friction, largest);
    EXPECT_GE(info.peak_friction, largest * (1.0 - 1e-6));
    ++checked;
  }
  EXPECT_GE(checked, 5);
  EXPECT_GE(others, checked) << "every accepted step is preceded by its relaxation's report";
  EXPECT_TRUE(refined) << "a Regime I slide refines its smooth maximum";
}

// A resumed slide (SlideControl::start) has a state from its first report on: the friction of
// the start state's last accepted state and the largest of its earlier sessions, not NaN (the
// start phase, which would have none, is not repeated), and its reports then go on as the
// uninterrupted slide's did from the same state.
TEST(SlideProgress, AResumedSlideReportsItsStartStatesFrictionAndLargest) {
  const interface::ContactScene scene {};  // a = 43 d, R = 535 d: Regime II, two slips
  const slide::SlideOptions options;
  std::vector<slide::SlideState> states;
  std::vector<SlideProgressInfo> whole;
  slide::SlideControl control{
      .progress = [&](const SlideProgressInfo& i) { whole.push_back(i); },
      .checkpoint = [&](const slide::SlideState& s) { states.push_back(s); },
      .checkpoint_every_s = 0.0};
  const auto full = slide::slide(scene, options, control);
  ASSERT_GE(full.slip_events, 1);
  // The first checkpoint after the first slip, where the friction has fallen below the peak.
  const auto after_slip = std::find_if(
      states.begin(), states.end(),
      [](const slide::SlideState& s) { return s.partial.slip_events >= 1 && !s.stepping_done; });
  ASSERT_NE(after_slip, states.end());
  const slide::SlideState& st = *after_slip;
  const double now = st.current.Fx / st.current.Fz;
  ASSERT_LT(now, st.best) << "the checkpoint after a slip is below the peak";

  std::vector<SlideProgressInfo> resumed;
  const auto rest = slide::slide(
      scene, options,
      slide::SlideControl{.progress = [&](const SlideProgressInfo& i) { resumed.push_back(i); },
                          .start = &st});
  ASSERT_FALSE(resumed.empty());
  const SlideProgressInfo& first = resumed.front();
  EXPECT_NE(first.phase, SlidePhase::start);
  EXPECT_EQ(first.Dx, st.current.Dx);
  EXPECT_EQ(first.slip_events, st.partial.slip_events);
  EXPECT_DOUBLE_EQ(first.friction, now);
  EXPECT_DOUBLE_EQ(first.peak_friction, st.best);

  // The uninterrupted slide's report of the same relaxation (the first from that state, of the
  // same phase and target) says the same.
  const auto same = std::find_if(whole.begin(), whole.end(), [&](const SlideProgressInfo& i) {
    return i.Dx == first.Dx && i.target_Dx == first.target_Dx && i.phase == first.phase &&
           i.iteration == first.iteration && i.steps == first.steps;
  });
  ASSERT_NE(same, whole.end()) << "no report of the relaxation to Dx = " << first.target_Dx;
  // From there on the reports are the uninterrupted slide's, one for one (the cost and the
  // wall time aside, which a resumed slide counts from its sessions).
  const auto offset = static_cast<std::size_t>(same - whole.begin());
  ASSERT_EQ(whole.size() - offset, resumed.size());
  for (std::size_t k = 0; k < resumed.size(); ++k) {
    const SlideProgressInfo &a = whole[offset + k], &b = resumed[k];
    EXPECT_TRUE(a.phase == b.phase && a.Dx == b.Dx && a.target_Dx == b.target_Dx &&
                a.iteration == b.iteration && a.steps == b.steps &&
                a.slip_events == b.slip_events && a.replayed_steps == b.replayed_steps &&
                a.friction == b.friction && a.peak_friction == b.peak_friction)
        << "report " << k << " after the resume";
  }
  EXPECT_EQ(rest.mu, full.mu);
}

// Creep (SlideOptions::flow_first_after): after that many slip steps in a row, a step at most
// min_step wide goes to the slip minimiser first, and to the fast one only if the flow finds it
// stable. A Regime III slide (R = 20 d, a = 15 d: loops arrested, many small slips) with the
// flow as slip minimiser, taken with flow_first_after = 2 (so that both outcomes occur: the
// flow slips, and the flow finds the step stable) against 0 (never), with step growth (every
// closing step starts from an open bracket) and without (the full step after a slip is
// bisected, and the closing trial has the bracket's far end):
// - the path is the same bit for bit: every trace row (tip position, forces, energy, slip,
//   slipped sites), mu and the slip events. Where the fast minimiser would call the step a
//   slip, the flow starts from the same state either way; where the flow finds it stable, the
//   fast minimiser's relaxation follows and the step is the one it would have been;
// - the relaxations, step by step (those started between accepted reports: the same steps in
//   both slides, as the rows are). Without flow_first_after a step ended with the fast
//   minimiser's relaxation to its Dx, followed by the flow's where it called the step a slip.
//   With it, a step the flow took first and slipped through has the flow's alone (the fast
//   trial saved); one it found stable has the flow's and then the fast minimiser's (one more
//   where the fast minimiser finds it stable too; as many, swapped, where it calls it a slip
//   and the flow's stable verdict stands either way). Anything else is a failure; every other
//   step has the same relaxations. So the counts differ by exactly (stable by both) -
//   (slipped), and every relaxation has its start report.
void check_flow_first_on_the_same_path(double step_growth) {
  const interface::ContactScene scene = test::regime_three_small();
  slide::SlideOptions never;
  test::use_creep_settings(never);
  never.step_growth = step_growth;
  never.flow_first_after = 0;
  slide::SlideOptions first = never;
  first.flow_first_after = 2;
  test::RelaxationLog log0, log1;
  const slide::SlideResult r0 =
      slide::slide(scene, never, [&](const SlideProgressInfo& p) { log0(p); });
  const slide::SlideResult r1 =
      slide::slide(scene, first, [&](const SlideProgressInfo& p) { log1(p); });
  ASSERT_FALSE(r0.failed) << r0.stop_reason;
  ASSERT_FALSE(r1.failed) << r1.stop_reason;
  ASSERT_GT(r0.slip_events, 10) << "not the Regime III slide this test is about";
  EXPECT_EQ(r0.flow_first_steps, 0);

  test::expect_same_path(r0, r1, "flow_first_after 2 against 0");
  const int slipped = r1.flow_first_steps - r1.flow_first_stable;
  EXPECT_GT(slipped, 0) << "no step taken by the flow first slipped";
  EXPECT_GT(r1.flow_first_stable, 0) << "the flow found no step it took first stable";

  const auto steps0 = log0.per_step(), steps1 = log1.per_step();
  ASSERT_EQ(steps0.size(), steps1.size());
  int relaxations0 = 0, relaxations1 = 0, took_slipped = 0, stable_by_both = 0, fast_slipped = 0;
  for (std::size_t k = 0; k < steps1.size(); ++k) {
    const auto &a = steps0[k], &b = steps1[k];
    relaxations0 += static_cast<int>(a.size());
    relaxations1 += static_cast<int>(b.size());
    if (std::equal(a.begin(), a.end(), b.begin(), b.end(), test::same_start)) continue;
    // The step's own relaxations: the fast one and the flow's after it (without), the flow's and
    // the fast one after it (with); the undone trials before them are the same.
    const auto same_before = [&](std::size_t na, std::size_t nb) {
      return a.size() >= na && b.size() >= nb && a.size() - na == b.size() - nb &&
             std::equal(a.begin(), a.end() - static_cast<std::ptrdiff_t>(na), b.begin(),
                        test::same_start);
    };
    if (b.empty()) {
      ADD_FAILURE() << "step " << k << ": no relaxation where the slide without it had some";
      continue;
    }
    const test::Relaxation flow_b = b.back();
    if (flow_b.phase == SlidePhase::slip && same_before(2, 1) &&
        test::same_start(a.end()[-1], flow_b) && a.end()[-2].phase != SlidePhase::slip &&
        a.end()[-2].target == flow_b.target) {
      ++took_slipped;
    } else if (same_before(1, 2) && b.end()[-2].phase == SlidePhase::slip &&
               b.end()[-2].target == b.back().target && test::same_start(a.back(), b.back())) {
      ++stable_by_both;
    } else if (same_before(2, 2) && test::same_start(a.end()[-1], b.end()[-2]) &&
               test::same_start(a.end()[-2], b.end()[-1]) &&
               b.end()[-2].phase == SlidePhase::slip && b.back().phase != SlidePhase::slip) {
      ++fast_slipped;
    } else {
      ADD_FAILURE() << "step " << k << ": relaxations neither as before nor a flow-first step's";
    }
  }
  EXPECT_EQ(relaxations0, r0.minimizations);
  EXPECT_EQ(relaxations1, r1.minimizations);
  EXPECT_EQ(took_slipped, slipped);
  EXPECT_EQ(stable_by_both + fast_slipped, r1.flow_first_stable);
  EXPECT_EQ(r1.minimizations - r0.minimizations, stable_by_both - slipped);
  std::printf(
      "R = 20 d, a = 15 d, step growth %g: %d slip events; flow first at %d steps (%d stable: %d "
      "also by the fast minimiser, %d it called a slip); relaxations %d -> %d, GF applications "
      "%zu -> %zu\n",
      step_growth, r1.slip_events, r1.flow_first_steps, r1.flow_first_stable, stable_by_both,
      fast_slipped, r0.minimizations, r1.minimizations, r0.gf_applications, r1.gf_applications);
}

TEST(SlideProgress, InCreepTheFlowGoesFirstOnTheSamePath) {
  check_flow_first_on_the_same_path(2.0);
}

TEST(SlideProgress, InCreepTheFlowGoesFirstOnTheSamePathAlsoInABisectedBracket) {
  check_flow_first_on_the_same_path(0.0);
}
