// Checkpoints of a slide (slide::SlideControl, slide::SlideState) and their files
// (common/slide_checkpoint.hpp); numerical failures during a slide.
//
// - A slide stopped at every possible point (each poll of stop_requested: between steps, in the
//   peak refinement, and every 16 iterations inside their relaxations, which are abandoned) and
//   resumed from the state it handed over, through an encoded checkpoint, gives the
//   uninterrupted result bit for bit: trace, mu, counts, snapshots.
// - A minimiser that stops converging mid-slide fails the slide with the step, Dx, step size and
//   solver settings in stop_reason, keeps the last good state as snapshot "last_good" and hands
//   it to the checkpoint callback.
// - Damaged checkpoints (truncated, corrupted, nested past the reader's depth limit), start
//   states of another scene and other settings are rejected.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "asperity/apps/common/slide_checkpoint.hpp"
#include "asperity/core/slide/slider.hpp"
#include "common/relaxations.hpp"
#include "common/results.hpp"
#include "common/scenes.hpp"
#include "scratch.hpp"

namespace asperity {
namespace {

using slide::SlideControl;
using slide::SlideResult;
using slide::SlideState;

app::SlideScene scene(double a, double distance) {
  app::SlideScene s;
  s.contact.a = a;
  s.contact.R = 535.0;
  s.contact.alpha = 0.7;
  s.options.distance = distance;
  s.options.path_frame_every = 5;  // snapshots of the relaxation paths are part of the state
  s.options.path_frame_slips = 1;  // of every slip
  return s;
}

// Whether a relaxation that starts is a slip's flow: the step of a slip is reported twice at
// the same target (iteration 0), the slide minimiser's relaxation (phase slip; step or
// bisection for a trial at most min_step wide, handed to the flow at once if it slips), then the
// flow's (phase slip).
struct FlowStarts {
  bool relaxing = false;  // the last start report was a step's relaxation
  double target = -1.0;
  bool starts_flow(const slide::SlideProgressInfo& p) {
    using slide::SlidePhase;
    const bool flow = p.phase == SlidePhase::slip && relaxing && p.target_Dx == target;
    relaxing = !flow && (p.phase == SlidePhase::step || p.phase == SlidePhase::bisection ||
                         p.phase == SlidePhase::slip);
    target = p.target_Dx;
    return flow;
  }
};

// The slide resumed from `saved` through an encoded and decoded checkpoint file.
SlideResult resume_through_file(const app::SlideScene& s, const SlideState& saved) {
  const auto bytes =
      app::encode_checkpoint({.settings = app::slide_fingerprint(s), .state = saved});
  const app::SlideCheckpoint back = app::decode_checkpoint(bytes, "test");
  return slide::slide(s.contact, s.options, SlideControl{.start = &back.state});
}

// Stops at the k-th poll of stop_requested; resumes from the encoded and decoded checkpoint.
// Returns false once k is past the last poll (the slide was not interrupted); counts the stops
// that abandoned a relaxation in `within`.
bool stop_and_resume(const app::SlideScene& s, int k, const SlideResult& reference, int& within) {
  std::optional<SlideState> saved;
  int polls = 0;
  const SlideControl stop{.checkpoint = [&](const SlideState& st) { saved = st; },
                          .checkpoint_every_s = 1e9,
                          .stop_requested = [&] { return ++polls == k; }};
  const SlideResult first = slide::slide(s.contact, s.options, stop);
  if (!first.interrupted) return false;
  const std::string where = "stopped at poll " + std::to_string(k) + " (" + first.stop_reason + ")";
  EXPECT_TRUE(saved.has_value()) << where;
  if (!saved) return false;
  EXPECT_TRUE(first.mu_is_lower_bound) << where;
  if (first.stop_reason.find("within the relaxation to Dx = ") != std::string::npos) ++within;
  const SlideResult resumed = resume_through_file(s, *saved);
  EXPECT_FALSE(resumed.interrupted) << where;
  test::expect_same_result(reference, resumed, where);
  return true;
}

TEST(SlideCheckpoint, StopsAnywhereResumeBitForBit) {
  // Regime I with a fixed distance (the peak is refined after the stepping), and Regime II
  // through two slip events (bisection brackets, relaxation-path frames, and after the first
  // slip the window of states and the pending probe of the cycle replay): every poll.
  // And the adhesive envelope (issue 27), whose slide maximises Fx/A: every third poll.
  // And the growing step after slips (slide.step_growth), which the protocol derives from the
  // trace: every poll.
  app::SlideScene adhesive = scene(16.0, 0.0);
  adhesive.contact.envelope = "adhesive";
  adhesive.contact.tau0 = 0.2;
  app::SlideScene growing = scene(20.0, 0.0);
  growing.options.step_growth = 2.0;
  for (const auto& [s, stride] : {std::pair{scene(6.0, 1.2), 1}, std::pair{scene(20.0, 0.0), 1},
                                  std::pair{adhesive, 3}, std::pair{growing, 1}}) {
    const SlideResult reference = slide::slide(s.contact, s.options);
    ASSERT_FALSE(reference.failed) << reference.stop_reason;
    // Regime II replays its second cycle (SlideOptions::replay_cycle): stops between the first
    // slip and the replay must carry the window of states and the pending comparison.
    if (reference.slip_events > 0) {
      EXPECT_GT(reference.replayed_steps, 0);
    }
    int stops = 0, within = 0;
    for (int k = 1; stop_and_resume(s, k, reference, within); k += stride)
      ++stops;
    EXPECT_GT(stops, 5) << "a = " << s.contact.a;
    // Polls inside relaxations come every 16 iterations; the slips of a = 20 d are short, so
    // few of them (StopInsideRelaxationsResumesBitForBit has many).
    if (reference.slip_events > 0) {
      EXPECT_GT(within, 0) << "a = " << s.contact.a;
    }
  }
}

TEST(SlideCheckpoint, StopInsideRelaxationsResumesBitForBit) {
  // A contact whose slips relax for about a hundred iterations (a = 43 d, a / b_core^0 = 6.2):
  // a stop at a poll inside a relaxation (a heartbeat, which the progress report just before
  // the poll tells by its iteration > 0) abandons it at once, hands over the state before it
  // and resumes to the uninterrupted result bit for bit. Stops: inside the first relaxation of
  // a slip, and at the first and the last poll inside any relaxation (bisection trials, steps).
  // The progress reports change nothing (test_slide_progress.cpp), so the reference may run
  // without them.
  const auto s = scene(43.0, 0.0);
  const SlideResult reference = slide::slide(s.contact, s.options);
  ASSERT_FALSE(reference.failed) << reference.stop_reason;
  ASSERT_GT(reference.slip_events, 0);
  // Runs the slide, stopping at the n-th poll inside a relaxation (of phase `only`, if given);
  // returns the number of such polls if it never stops.
  struct Stop {
    SlideResult result;
    std::optional<SlideState> saved;
    int polls = 0;
  };
  const auto run = [&](int n, std::optional<slide::SlidePhase> only) {
    Stop out;
    slide::SlidePhase phase{};
    int iteration = 0;
    out.result =
        slide::slide(s.contact, s.options,
                     SlideControl{.progress =
                                      [&](const slide::SlideProgressInfo& p) {
                                        phase = p.phase, iteration = p.iteration;
                                      },
                                  .checkpoint = [&](const SlideState& st) { out.saved = st; },
                                  .checkpoint_every_s = 1e9,
                                  .stop_requested =
                                      [&] {
                                        if (iteration == 0 || (only && phase != *only))
                                          return false;
                                        return ++out.polls == n;
                                      }});
    return out;
  };
  const int inside = run(0, std::nullopt).polls;
  const int inside_slips = run(0, slide::SlidePhase::slip).polls;
  ASSERT_GT(inside, 5);
  ASSERT_GT(inside_slips, 0);
  for (const auto& [n, only] : {std::pair{1, std::optional{slide::SlidePhase::slip}},
                                std::pair{1, std::optional<slide::SlidePhase>{}},
                                std::pair{inside, std::optional<slide::SlidePhase>{}}}) {
    const Stop stop = run(n, only);
    const std::string where = "stop at poll " + std::to_string(n) + " inside " +
                              (only ? "slip" : "any") + " relaxations (" + stop.result.stop_reason +
                              ")";
    ASSERT_TRUE(stop.result.interrupted) << where;
    EXPECT_NE(stop.result.stop_reason.find("within the relaxation to Dx = "), std::string::npos)
        << where;
    ASSERT_TRUE(stop.saved.has_value()) << where;
    // The handed-over state is the one before the abandoned relaxation; its cost leaves out
    // the abandoned work, which the resumed slide repeats.
    if (only) {
      EXPECT_LT(stop.saved->partial.slip_events, reference.slip_events) << where;
    }
    EXPECT_LT(stop.saved->partial.gf_applications, reference.gf_applications) << where;
    const SlideResult resumed = resume_through_file(s, *stop.saved);
    EXPECT_FALSE(resumed.interrupted) << where;
    test::expect_same_result(reference, resumed, where);
  }
}

TEST(SlideCheckpoint, StopInsideAPeakRefinementResumesBitForBit) {
  // Regime I (a = 12 d, no slip in 1.2 d) with a fixed distance: the smooth maximum is refined
  // after the stepping, by 4 probes. With FIRE (L-BFGS converges them in under 16 iterations)
  // they relax for up to about 100 iterations, so a stop lands inside one: the probe is
  // abandoned, the state at the end of the stepping is handed over, and the resumed slide redoes
  // the refinement to the uninterrupted result, bit for bit.
  auto s = scene(12.0, 1.2);
  s.options.minimizer.method = minimize::Method::fire;
  const SlideResult reference = slide::slide(s.contact, s.options);
  ASSERT_FALSE(reference.failed) << reference.stop_reason;
  std::optional<SlideState> saved;
  slide::SlidePhase phase{};
  int iteration = 0;
  const SlideResult first = slide::slide(
      s.contact, s.options,
      SlideControl{
          .progress =
              [&](const slide::SlideProgressInfo& p) { phase = p.phase, iteration = p.iteration; },
          .checkpoint = [&](const SlideState& st) { saved = st; },
          .checkpoint_every_s = 1e9,
          .stop_requested = [&] { return phase == slide::SlidePhase::peak && iteration > 0; }});
  ASSERT_TRUE(first.interrupted) << "no poll inside a peak probe: " << first.stop_reason;
  EXPECT_NE(first.stop_reason.find("(refining the peak), within the relaxation to Dx = "),
            std::string::npos)
      << first.stop_reason;
  ASSERT_TRUE(saved.has_value());
  EXPECT_TRUE(saved->stepping_done);
  const SlideResult resumed = resume_through_file(s, *saved);
  EXPECT_FALSE(resumed.interrupted);
  test::expect_same_result(reference, resumed, "stopped inside a peak probe");
}

TEST(SlideCheckpoint, SlipFlowPausesAndContinuesBitForBit) {
  // With the flow as slip minimiser (the tools' default) a slip relaxation is paused, not
  // abandoned: by a stop request (seen every 16 iterations, the pause comes at the next accepted
  // step of the flow) and by checkpoints that fall due inside it. The state handed over holds
  // the paused flow (SlideState::pending, with the path frames so far); resumed through a
  // checkpoint file it continues the flow where it was and ends as the uninterrupted slide did,
  // bit for bit, with the work before the pause counted once.
  auto s = scene(43.0, 0.0);
  s.options.slip_minimizer = slide::slip_minimizer_from(s.options.minimizer, minimize::Method::flow,
                                                        minimize::Preconditioner::interface);
  const SlideResult reference = slide::slide(s.contact, s.options);
  ASSERT_FALSE(reference.failed) << reference.stop_reason;
  ASSERT_GT(reference.slip_relaxations, 0);
  // Stop at the n-th poll inside a flow (from `start`, if given; n = -1: at the first poll,
  // wherever it is; FlowStarts tells the flow's relaxation).
  const auto stop_at = [&](int n, std::optional<SlideState>& saved,
                           const SlideState* start = nullptr) {
    int iteration = 0, polls = 0;
    bool in_flow = false;
    FlowStarts starts;
    const SlideResult r =
        slide::slide(s.contact, s.options,
                     SlideControl{.progress =
                                      [&](const slide::SlideProgressInfo& p) {
                                        iteration = p.iteration;
                                        if (p.iteration > 0) return;
                                        in_flow = starts.starts_flow(p);
                                      },
                                  .checkpoint = [&](const SlideState& st) { saved = st; },
                                  .checkpoint_every_s = 1e9,
                                  .stop_requested =
                                      [&] {
                                        if (n == -1) return true;
                                        if (iteration == 0 || !in_flow) return false;
                                        return ++polls == n;
                                      },
                                  .start = start});
    return std::pair{r, polls};
  };
  std::optional<SlideState> none;
  const int polls = stop_at(0, none).second;
  ASSERT_GT(polls, 3);
  for (int n : {1, polls / 2, polls}) {
    std::optional<SlideState> saved;
    const SlideResult stopped = stop_at(n, saved).first;
    const std::string where = "stop at poll " + std::to_string(n) + " of " + std::to_string(polls) +
                              " (" + stopped.stop_reason + ")";
    ASSERT_TRUE(stopped.interrupted) << where;
    EXPECT_NE(stopped.stop_reason.find("paused at iteration"), std::string::npos) << where;
    ASSERT_TRUE(saved && saved->pending) << where;
    EXPECT_GT(saved->pending->flow.iteration, 0) << where;
    EXPECT_FALSE(saved->pending->frames.empty()) << where;  // path frames of every slip
    const SlideResult resumed = resume_through_file(s, *saved);
    EXPECT_FALSE(resumed.interrupted) << where;
    test::expect_same_result(reference, resumed, where);
    if (n != polls / 2) continue;
    // The resumed slide, stopped again before it continues the flow (the first poll, between
    // steps), hands the paused flow on; stopped inside it, it pauses it further on.
    std::optional<SlideState> again, later;
    const SlideResult at_once = stop_at(-1, again, &*saved).first;
    ASSERT_TRUE(at_once.interrupted && again && again->pending) << where;
    EXPECT_EQ(again->pending->flow.iteration, saved->pending->flow.iteration) << where;
    EXPECT_EQ(again->partial.gf_applications, saved->partial.gf_applications) << where;
    test::expect_same_result(reference, resume_through_file(s, *again),
                             where + ", stopped again at once");
    const SlideResult further = stop_at(2, later, &*saved).first;
    ASSERT_TRUE(further.interrupted && later && later->pending) << where;
    if (later->pending->Dx == saved->pending->Dx) {
      EXPECT_GT(later->pending->flow.iteration, saved->pending->flow.iteration) << where;
    }
    test::expect_same_result(reference, resume_through_file(s, *later), where + ", paused twice");
  }
  // A resumed slide that checkpoints after every step hands the paused flow on too.
  {
    std::optional<SlideState> saved, first;
    stop_at(polls / 2, saved);
    ASSERT_TRUE(saved && saved->pending);
    const SlideControl control{.checkpoint =
                                   [&](const SlideState& st) {
                                     if (!first) first = st;
                                   },
                               .checkpoint_every_s = 0.0,
                               .start = &*saved};
    const SlideResult r = slide::slide(s.contact, s.options, control);
    test::expect_same_result(reference, r, "resumed with a checkpoint after every step");
    ASSERT_TRUE(first.has_value());
    ASSERT_TRUE(first->pending.has_value()) << "the first checkpoint of the resumed slide";
    test::expect_same_result(reference, resume_through_file(s, *first),
                             "resumed from its first checkpoint");
  }
  // Checkpoints due inside the flow (every one: a due time of 1e-9 s) change nothing, and the
  // slide resumed from one taken inside a slip relaxation ends the same.
  std::vector<SlideState> inside;
  const SlideResult r = slide::slide(s.contact, s.options,
                                     SlideControl{.checkpoint =
                                                      [&](const SlideState& st) {
                                                        if (st.pending && inside.size() < 40)
                                                          inside.push_back(st);
                                                      },
                                                  .checkpoint_every_s = 1e-9});
  test::expect_same_result(reference, r, "checkpoints inside the slip relaxations");
  ASSERT_GE(inside.size(), 2u);
  test::expect_same_result(reference, resume_through_file(s, inside[inside.size() / 2]),
                           "resumed from a checkpoint inside a slip relaxation");
  // A paused relaxation that does not fit the step the state leads to is refused.
  SlideState wrong = inside.front();
  wrong.pending->Dx += 0.5;
  EXPECT_THROW(slide::slide(s.contact, s.options, SlideControl{.start = &wrong}),
               std::invalid_argument);
  wrong = inside.front();
  wrong.pending->flow.u.pop_back();
  EXPECT_THROW(slide::slide(s.contact, s.options, SlideControl{.start = &wrong}),
               std::invalid_argument);
  wrong = inside.front();
  wrong.pending->flow.step = std::numeric_limits<double>::infinity();  // a damaged file
  EXPECT_THROW(slide::slide(s.contact, s.options, SlideControl{.start = &wrong}),
               std::invalid_argument);
  wrong = inside.back();
  ASSERT_FALSE(wrong.pending->frames.empty());
  wrong.pending->frames.back().fields.Dx += 1.0;
  EXPECT_THROW(slide::slide(s.contact, s.options, SlideControl{.start = &wrong}),
               std::invalid_argument);
}

TEST(SlideCheckpoint, PausedSlipIsWhereTheFlowStands) {
  // slide::paused_slip (friction_sweep --peek): the state of a checkpoint's paused slip flow.
  // Taken at every accepted step of every slip flow of the a = 43 d slide (checkpoints due at
  // once), it must hold (1) the pause's pair itself on the contact sites, bit for bit, at the
  // step's tip position; (2) along one flow, an energy that never rises (rkc rejects a step that
  // raises it: the flow descends, MODEL.md 5), from above the state the slip ends in down to it;
  // (3) at the flow's last accepted step, the state the slide accepts after the slip, bit for
  // bit (the slide makes it the same way: pair on the contact, u = G f off it), with the slip's
  // sites (registry_jumps) as its trace row counts them; (4) max |r| above the slip minimiser's
  // force tolerance at every pause the flow went on from, and within it at the last (the flow
  // ends there, converged).
  auto s = scene(43.0, 0.0);
  s.options.slip_minimizer = slide::slip_minimizer_from(s.options.minimizer, minimize::Method::flow,
                                                        minimize::Preconditioner::interface);
  std::vector<SlideState> inside, between;
  const SlideResult r = slide::slide(
      s.contact, s.options,
      SlideControl{.checkpoint =
                       [&](const SlideState& st) { (st.pending ? inside : between).push_back(st); },
                   .checkpoint_every_s = 1e-9});
  ASSERT_FALSE(r.failed) << r.stop_reason;
  ASSERT_GT(r.slip_events, 0);
  ASSERT_GE(inside.size(), 10u);
  std::size_t flows = 0, compared_ends = 0;
  double energy_before = 0.0;
  for (std::size_t k = 0; k < inside.size(); ++k) {
    const SlideState& st = inside[k];
    const slide::PausedSlip p = slide::paused_slip(s.contact, s.options, st);
    const std::string where = "pause " + std::to_string(k) +
                              " (Dx = " + std::to_string(st.pending->Dx) + " d, iteration " +
                              std::to_string(st.pending->flow.iteration) + ")";
    ASSERT_EQ(p.iteration, st.pending->flow.iteration) << where;
    ASSERT_EQ(p.state.Dx, st.pending->Dx) << where;
    // (1) The contact sites, in the order the pair holds them (block order), are the snapshot's
    // sites in contact.
    const slide::Snapshot snap = slide::snapshot_of(s.contact, p.state, "flow");
    const std::size_t m = st.pending->flow.u.size() / 2;
    std::size_t j = 0;
    bool same = true;
    for (std::size_t i = 0; i < snap.in_contact.size(); ++i) {
      if (!snap.in_contact[i]) continue;
      same = same && j < m && snap.ux[i] == st.pending->flow.u[j] &&
             snap.uy[i] == st.pending->flow.u[m + j];
      ++j;
    }
    EXPECT_TRUE(same && j == m) << where << ": " << j << " sites in contact, pair of " << m;
    // (2) Energy along the flow.
    const bool same_flow = k > 0 && inside[k - 1].pending->Dx == st.pending->Dx &&
                           inside[k - 1].pending->flow.iteration < st.pending->flow.iteration;
    if (same_flow) {
      EXPECT_LE(p.state.energy, energy_before) << where;
    } else {
      ++flows;
    }
    energy_before = p.state.energy;
    // (3) The flow's last pause against the state accepted after it.
    const bool last_of_flow = k + 1 == inside.size() || inside[k + 1].pending->Dx != st.pending->Dx;
    // (4) Distance from rest, as the flow measures it when it decides to stop.
    const double tolerance = s.options.slip_minimizer->force_tolerance;
    ASSERT_TRUE(std::isfinite(p.max_force)) << where;
    if (!last_of_flow) {
      EXPECT_GT(p.max_force, tolerance) << where << ": the flow went on from here";
      continue;
    }
    EXPECT_LE(p.max_force, tolerance) << where << ": the flow ended here";
    const auto after = std::find_if(between.begin(), between.end(), [&](const SlideState& b) {
      return b.current.Dx == st.pending->Dx;
    });
    if (after == between.end()) continue;
    ++compared_ends;
    double du = 0.0, df = 0.0;
    for (std::size_t i = 0; i < p.state.u.size(); ++i) {
      du = std::max(du, std::abs(p.state.u[i] - after->current.u[i]));
      df = std::max(df, std::abs(p.state.f[i] - after->current.f[i]));
    }
    EXPECT_EQ(du, 0.0) << where << ": the last pause against the state accepted after the flow";
    EXPECT_EQ(df, 0.0) << where;
    EXPECT_EQ(p.state.energy, after->current.energy) << where;
    EXPECT_EQ(p.state.Fx, after->current.Fx) << where;
    const auto row = std::find_if(r.trace.begin(), r.trace.end(), [&](const slide::TraceRow& t) {
      return t.Dx == st.pending->Dx && t.slip;
    });
    ASSERT_NE(row, r.trace.end()) << where << ": no slip in the trace at this Dx";
    EXPECT_EQ(p.slipped_sites, row->slipped_sites) << where;
    EXPECT_GT(p.slipped_sites, 0) << where;
  }
  // Measured: 148 pauses in the one flow this slide computes (its second slip is replayed),
  // the last at iteration 151, 5 628 sites slipped.
  EXPECT_GE(flows, 1u);
  EXPECT_EQ(compared_ends, flows);
  // No paused flow in a state taken between steps.
  ASSERT_FALSE(between.empty());
  EXPECT_THROW(slide::paused_slip(s.contact, s.options, between.back()), std::invalid_argument);
  // The state depends on the last accepted one only through the block's alignment: every force
  // is the pause's (those off the contact zero) and every displacement follows from them, so
  // with an accepted state of another alignment (the first, at Dx = 0: the roll to the step's
  // block is then made) whose fields are filled with junk nothing of it may show.
  const SlideState& mid = inside[inside.size() / 2];
  SlideState moved = mid;
  moved.current = between.front().current;
  std::fill(moved.current.f.begin(), moved.current.f.end(), 0.25);
  std::fill(moved.current.u.begin(), moved.current.u.end(), -3.0);
  ASSERT_NE(moved.current.shift, mid.current.shift) << "the roll is not exercised";
  const slide::PausedSlip a = slide::paused_slip(s.contact, s.options, mid);
  const slide::PausedSlip b = slide::paused_slip(s.contact, s.options, moved);
  EXPECT_EQ(a.state.shift, b.state.shift);
  EXPECT_TRUE(a.state.u == b.state.u && a.state.f == b.state.f)
      << "a field of the last accepted state shows in the paused one";
  EXPECT_EQ(a.state.energy, b.state.energy);
  EXPECT_EQ(a.max_force, b.max_force);
  // A damaged file: the step's tip position not beyond the accepted state's, or not finite.
  moved = mid;
  moved.pending->Dx = moved.current.Dx;
  EXPECT_THROW(slide::paused_slip(s.contact, s.options, moved), std::invalid_argument);
  moved.pending->Dx = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(slide::paused_slip(s.contact, s.options, moved), std::invalid_argument);
}

// The scene of the flow-first tests: a Regime III slide (R = 20 d, a = 15 d) with step growth
// and the flow for slips; flow_first_after = 2, so that the flow both slips and finds steps
// stable.
app::SlideScene creep_scene() {
  auto s = scene(15.0, 0.0);
  s.contact = test::regime_three_small();
  test::use_creep_settings(s.options);
  s.options.flow_first_after = 2;
  return s;
}

using test::Relaxation;
// The uninterrupted slide of s, recording its relaxations.
SlideResult slide_recording(const app::SlideScene& s, test::RelaxationLog& log) {
  return slide::slide(s.contact, s.options, [&](const slide::SlideProgressInfo& p) { log(p); });
}

// The slide of s stopped 16 iterations into the slip-phase relaxation (a flow) to `target`
// (the stop request is seen every 16 iterations; the flow pauses at its next accepted step);
// `saved` receives the state handed over.
SlideResult stop_inside_flow(const app::SlideScene& s, double target,
                             std::optional<SlideState>& saved) {
  bool in_flow = false;
  int iteration = 0;
  return slide::slide(s.contact, s.options,
                      SlideControl{.progress =
                                       [&](const slide::SlideProgressInfo& p) {
                                         iteration = p.iteration;
                                         if (p.iteration == 0)
                                           in_flow = p.phase == slide::SlidePhase::slip &&
                                                     p.target_Dx == target;
                                         if (p.phase == slide::SlidePhase::accepted)
                                           in_flow = false;
                                       },
                                   .checkpoint = [&](const SlideState& st) { saved = st; },
                                   .checkpoint_every_s = 1e9,
                                   .stop_requested = [&] { return in_flow && iteration >= 16; }});
}

// In creep (SlideOptions::flow_first_after) a step goes to the flow before the fast minimiser,
// so a checkpoint inside that flow holds no fast relaxation (PendingSlip::fast empty; null in
// the file). Resumed through a checkpoint file, such a pause continues as a step the flow took
// first: where the flow slips, the slip is accepted; where it finds the step stable, the fast
// minimiser relaxes it then, as the uninterrupted slide did. Both end as that slide, bit for
// bit. Adopted under other step settings, such a pause is still continued as its step (below).
// A Regime III slide (R = 20 d, a = 15 d) with step growth; flow_first_after = 2 so that both
// outcomes occur.
TEST(SlideCheckpoint, AFlowFirstPauseHoldsNoFastRelaxationAndResumesBitForBit) {
  const app::SlideScene s = creep_scene();
  test::RelaxationLog log;
  const SlideResult reference = slide_recording(s, log);
  ASSERT_FALSE(reference.failed) << reference.stop_reason;
  const std::vector<std::vector<Relaxation>> steps = log.per_step();
  ASSERT_GT(reference.flow_first_steps, reference.flow_first_stable);
  ASSERT_GT(reference.flow_first_stable, 0);
  // A flow-first step starts with the flow (a slip report). If the flow slips, it is the step's
  // only relaxation, and its row a slip (a step the fast minimiser starts with a slip report
  // and calls a slip has the flow's after it). If the flow finds it stable, the fast
  // minimiser's relaxation of the same target follows as a step or bisection trial.
  double slipping = -1.0, stable = -1.0;
  for (const auto& st : steps) {
    if (st.empty() || st.front().phase != slide::SlidePhase::slip) continue;
    const double t = st.front().target;
    const auto row = std::find_if(reference.trace.begin(), reference.trace.end(),
                                  [&](const auto& r) { return r.Dx == t; });
    if (st.size() == 1 && row != reference.trace.end() && row->slip && slipping < 0) slipping = t;
    if (st.size() == 2 && st[1].phase != slide::SlidePhase::slip && st[1].target == t && stable < 0)
      stable = t;
  }
  ASSERT_GT(slipping, 0.0) << "no flow-first step that slips";
  ASSERT_GT(stable, 0.0) << "no flow-first step found stable";
  // Stopped inside each one's flow.
  for (const double target : {slipping, stable}) {
    std::optional<SlideState> saved;
    const SlideResult stopped = stop_inside_flow(s, target, saved);
    const std::string where =
        "stopped inside the flow-first step to Dx = " + std::to_string(target) +
        (target == stable ? " (stable)" : "");
    ASSERT_TRUE(stopped.interrupted) << where;
    ASSERT_TRUE(saved && saved->pending) << where << ": " << stopped.stop_reason;
    EXPECT_FALSE(saved->pending->fast.has_value()) << where;
    EXPECT_GT(saved->pending->flow.iteration, 0) << where;
    const auto bytes =
        app::encode_checkpoint({.settings = app::slide_fingerprint(s), .state = *saved});
    const app::SlideCheckpoint back = app::decode_checkpoint(bytes, "test");
    ASSERT_TRUE(back.state.pending.has_value()) << where;
    EXPECT_FALSE(back.state.pending->fast.has_value()) << where << " (read back)";
    test::expect_same_result(
        reference, slide::slide(s.contact, s.options, SlideControl{.start = &back.state}), where);
    // Adopted with other step settings (friction_sweep --adopt, docs/reliability.md): the full
    // step instead of step growth, and a distance 0.05 d past the paused step. The paused step
    // is no longer where the plan would go (0.05 d on), and no bracket was closed to lead
    // there; it is continued all the same, as the flow of a step the fast minimiser saw slip
    // is: the rows up to it are the uninterrupted slide's.
    slide::SlideOptions other = s.options;
    other.step_growth = 0.0;
    other.distance = target + 0.05;
    const SlideResult adopted = slide::slide(s.contact, other, SlideControl{.start = &back.state});
    ASSERT_FALSE(adopted.failed) << where << ": " << adopted.stop_reason;
    const auto row = std::find_if(reference.trace.begin(), reference.trace.end(),
                                  [&](const auto& r) { return r.Dx == target; });
    ASSERT_NE(row, reference.trace.end());
    const auto rows = static_cast<std::size_t>(row - reference.trace.begin()) + 1;
    ASSERT_GT(adopted.trace.size(), rows) << where << " (adopted)";
    for (std::size_t i = 0; i < rows; ++i) {
      const auto &x = reference.trace[i], &y = adopted.trace[i];
      EXPECT_TRUE(test::same_bits(x.Dx, y.Dx) && test::same_bits(x.Fx, y.Fx) &&
                  test::same_bits(x.energy, y.energy) && x.slip == y.slip &&
                  x.slipped_sites == y.slipped_sites && x.gf_applications == y.gf_applications)
          << where << " (adopted): trace row " << i;
    }
  }
}

// A stop request during the fast relaxation that follows a flow-first flow that found its step
// stable is not taken there (the flow would be thrown away with the relaxation, and a flow
// resumed from a pause has its earlier part already in the slide's counts, which the handed-over
// state would then count twice): the step is finished and the stop taken at the next one. Both
// from the start and from a pause inside that flow, the slide stops past the step, and resumed
// it ends as the uninterrupted slide, bit for bit and with the same GF count. The step is the
// stable flow-first step whose fast relaxation is longest, so that the request is polled inside
// it (every 16 iterations).
TEST(SlideCheckpoint, AStopAfterAStableFlowFirstFlowFinishesTheStep) {
  const app::SlideScene s = creep_scene();
  test::RelaxationLog log;
  const SlideResult reference = slide_recording(s, log);
  ASSERT_FALSE(reference.failed) << reference.stop_reason;
  const std::vector<Relaxation>& relaxations = log.all();
  ASSERT_GT(reference.flow_first_stable, 0);
  // A flow (phase slip) followed by a step or bisection trial to the same target: the fast
  // relaxation after a flow-first flow that found the step stable.
  double target = -1.0;
  int longest = 0;
  for (std::size_t i = 1; i < relaxations.size(); ++i) {
    const auto &flow = relaxations[i - 1], &fast = relaxations[i];
    if (flow.phase == slide::SlidePhase::slip && fast.phase != slide::SlidePhase::slip &&
        fast.target == flow.target && fast.iterations > longest) {
      longest = fast.iterations;
      target = fast.target;
    }
  }
  // A report at iteration 16 or later is a heartbeat that polled the stop request.
  ASSERT_GE(longest, 16) << "no fast relaxation after a stable flow long enough to see a stop";
  std::printf("the fast relaxation after the stable flow to Dx = %.5f d: %d iterations\n", target,
              longest);
  // Stops requested from the fast relaxation's first report on; the state handed over.
  const auto stopped_after = [&](const SlideState* start, std::optional<SlideState>& saved) {
    bool requested = false;
    bool in_flow = false;
    return slide::slide(s.contact, s.options,
                        SlideControl{.progress =
                                         [&](const slide::SlideProgressInfo& p) {
                                           if (p.iteration != 0 || p.target_Dx != target) return;
                                           if (p.phase == slide::SlidePhase::slip)
                                             in_flow = true;
                                           else if (in_flow)
                                             requested = true;
                                         },
                                     .checkpoint = [&](const SlideState& st) { saved = st; },
                                     .checkpoint_every_s = 1e9,
                                     .stop_requested = [&] { return requested; },
                                     .start = start});
  };
  // From the start.
  std::optional<SlideState> saved;
  SlideResult stopped = stopped_after(nullptr, saved);
  ASSERT_TRUE(stopped.interrupted && saved) << stopped.stop_reason;
  EXPECT_FALSE(saved->pending.has_value());
  EXPECT_EQ(saved->current.Dx, target) << "the step was not finished before the stop";
  test::expect_same_result(reference, resume_through_file(s, *saved),
                           "stopped after the stable flow");
  // From a pause inside the flow (16 iterations in).
  std::optional<SlideState> paused;
  stopped = stop_inside_flow(s, target, paused);
  ASSERT_TRUE(stopped.interrupted && paused && paused->pending) << stopped.stop_reason;
  saved.reset();
  stopped = stopped_after(&*paused, saved);
  ASSERT_TRUE(stopped.interrupted && saved) << stopped.stop_reason;
  EXPECT_FALSE(saved->pending.has_value());
  EXPECT_EQ(saved->current.Dx, target) << "the resumed step was not finished before the stop";
  test::expect_same_result(reference, resume_through_file(s, *saved),
                           "paused inside the stable flow, then stopped after it");
}

// A checkpoint that falls due inside a slip's flow holds the paused flow, which belongs to its
// step: a slide with a longer limit cannot continue it (friction_sweep keeps a capped point's
// last checkpoint between steps). So the slide checkpoints again at the top of the next step,
// due or not (SlideControl). Here the checkpoint interval (0.5 s) falls due only inside the first
// flow, by a pause held there for 0.5 s: without that rule the next checkpoint would come 0.5 s
// later, wherever the slide is then. With it, every paused checkpoint is followed, before any
// other step's, by one between steps, from which the slide resumes bit for bit. (On a machine so
// slow that 0.5 s pass between the pause and the next step, the test passes without the rule;
// it cannot fail with it.)
TEST(SlideCheckpoint, APausedCheckpointIsFollowedByOneBetweenSteps) {
  auto s = scene(43.0, 0.0);
  s.options.slip_minimizer = slide::slip_minimizer_from(s.options.minimizer, minimize::Method::flow,
                                                        minimize::Preconditioner::interface);
  const SlideResult reference = slide::slide(s.contact, s.options);
  ASSERT_GT(reference.slip_relaxations, 0);
  std::vector<SlideState> saved;
  bool slept = false, in_flow = false;
  FlowStarts starts;
  const SlideResult r = slide::slide(
      s.contact, s.options,
      SlideControl{.progress =
                       [&](const slide::SlideProgressInfo& p) {
                         if (p.iteration > 0) {
                           // Inside the first flow: the checkpoint falls due here.
                           if (in_flow && !slept) {
                             std::this_thread::sleep_for(std::chrono::milliseconds(500));
                             slept = true;
                           }
                           return;
                         }
                         in_flow = starts.starts_flow(p);
                       },
                   .checkpoint = [&](const SlideState& st) { saved.push_back(st); },
                   .checkpoint_every_s = 0.5});
  test::expect_same_result(reference, r, "with a checkpoint inside a flow");
  ASSERT_TRUE(slept) << "no flow reported its iterations";
  std::size_t paused = 0;
  for (std::size_t i = 0; i < saved.size(); ++i) {
    if (!saved[i].pending) continue;
    ++paused;
    // The next checkpoint not inside the same flow.
    std::size_t j = i + 1;
    while (j < saved.size() && saved[j].pending && saved[j].pending->Dx == saved[i].pending->Dx)
      ++j;
    ASSERT_LT(j, saved.size()) << "no checkpoint after the paused one at Dx = "
                               << saved[i].current.Dx;
    EXPECT_FALSE(saved[j].pending.has_value())
        << "the checkpoint after a paused one is inside another flow";
    if (paused == 1) {
      test::expect_same_result(reference, resume_through_file(s, saved[j]),
                               "resumed from the checkpoint between steps after a paused one");
      // A slide resumed from the paused checkpoint itself writes one between steps after
      // continuing that flow, not the paused state again at its first step's top (with no
      // checkpoint ever due, that one is the only checkpoint it writes).
      std::vector<SlideState> again;
      const auto bytes =
          app::encode_checkpoint({.settings = app::slide_fingerprint(s), .state = saved[i]});
      const app::SlideCheckpoint back = app::decode_checkpoint(bytes, "test");
      const SlideResult resumed = slide::slide(
          s.contact, s.options,
          SlideControl{.checkpoint = [&](const SlideState& st) { again.push_back(st); },
                       .checkpoint_every_s = 1e9,
                       .start = &back.state});
      test::expect_same_result(reference, resumed, "resumed from the paused checkpoint");
      ASSERT_EQ(again.size(), 1u) << "checkpoints of the resumed slide";
      EXPECT_FALSE(again[0].pending.has_value());
      EXPECT_GE(again[0].current.Dx, saved[i].pending->Dx);  // after the flow's step
    }
    i = j - 1;
  }
  EXPECT_GE(paused, 1u);
}

TEST(SlideCheckpoint, IntervalCheckpointsChangeNothing) {
  const auto s = scene(20.0, 0.0);
  const SlideResult reference = slide::slide(s.contact, s.options);
  int calls = 0;
  std::optional<SlideState> last;
  const SlideResult r =
      slide::slide(s.contact, s.options,
                   SlideControl{.checkpoint = [&](const SlideState& st) { ++calls, last = st; },
                                .checkpoint_every_s = 0.0});
  test::expect_same_result(reference, r, "checkpoint after every step");
  EXPECT_GE(calls, reference.steps);
  // The last one resumes to the end too.
  ASSERT_TRUE(last.has_value());
  test::expect_same_result(reference,
                           slide::slide(s.contact, s.options, SlideControl{.start = &*last}),
                           "resumed from the last interval checkpoint");
}

// A slide stopped by its distance cap hands over no checkpoint at the cap: its last one is from
// before the step that was cut to land there (protocol.hpp, step()). So a longer cap continuing
// it (friction_sweep's capped lower bounds, --adopt) gives, bit for bit, the slide that had the
// longer cap from the start.
TEST(SlideCheckpoint, TheLastCheckpointOfACappedSlideContinuesUnderALongerCap) {
  auto capped = scene(20.0, 0.0);
  capped.options.max_distance = 0.45;
  std::optional<SlideState> last;
  const SlideResult first =
      slide::slide(capped.contact, capped.options,
                   SlideControl{.checkpoint = [&](const SlideState& st) { last = st; },
                                .checkpoint_every_s = 0.0});
  ASSERT_EQ(first.stop_reason, slide::kStopDistanceCap);
  ASSERT_TRUE(last.has_value());
  EXPECT_LT(last->current.Dx, 0.45);  // not the state at the cap
  auto longer = capped;
  longer.options.max_distance = 2.0;
  const SlideResult reference = slide::slide(longer.contact, longer.options);
  EXPECT_GT(reference.trace.back().Dx, 0.45);
  test::expect_same_result(
      reference, slide::slide(longer.contact, longer.options, SlideControl{.start = &*last}),
      "the capped slide's last checkpoint under a longer cap");
}

TEST(SlideCheckpoint, NonConvergenceStopsWithStepParametersAndLastGoodState) {
  auto s = scene(20.0, 0.0);
  s.options.minimizer.max_iterations = 12;  // enough on the ramp, not through the first slip
  std::optional<SlideState> saved;
  const SlideResult r =
      slide::slide(s.contact, s.options,
                   SlideControl{.checkpoint = [&](const SlideState& st) { saved = st; },
                                .checkpoint_every_s = 1e9});
  ASSERT_TRUE(r.failed);
  EXPECT_FALSE(r.interrupted);
  for (const char* part : {"minimizer max_iterations at Dx = ", "(step ", "from Dx = ",
                           "step size ", "lbfgs, tolerance 1e-05, max iterations 12"}) {
    EXPECT_NE(r.stop_reason.find(part), std::string::npos) << r.stop_reason;
  }
  ASSERT_GE(r.trace.size(), 2u) << "failed before any step: " << r.stop_reason;
  for (const auto& row : r.trace)
    EXPECT_TRUE(std::isfinite(row.Fx) && std::isfinite(row.energy));
  // The last good state: the last accepted step, as a snapshot and as a checkpoint.
  const double last_Dx = r.trace.back().Dx;
  const auto good = std::find_if(r.snapshots.begin(), r.snapshots.end(),
                                 [](const slide::Snapshot& x) { return x.label == "last_good"; });
  ASSERT_NE(good, r.snapshots.end());
  EXPECT_EQ(good->Dx, last_Dx);
  ASSERT_TRUE(saved.has_value());
  EXPECT_EQ(saved->current.Dx, last_Dx);
  EXPECT_EQ(saved->partial.trace.size(), r.trace.size());
  EXPECT_NE(r.stop_reason.find("step " + std::to_string(r.steps + 1)), std::string::npos)
      << r.stop_reason;
}

// Adoption (--adopt): a checkpoint of another build, or of other slide.*, solver.* or fft.*
// settings, continues under this run's settings; one of another problem (here alpha) does not.
// The resumed slide keeps the rows before the stop and after it steps by the new rule
// (slide.step_growth: min_step after a slip). Each adoption keeps the adopted file under a
// second name and appends a record.
class SlideCheckpointAdoption : public test_support::ScratchDirTest {};

TEST_F(SlideCheckpointAdoption, AnotherBuildAndNumericalSettingsOnly) {
  const app::SlideScene s0 = scene(20.0, 0.0);
  const SlideResult reference = slide::slide(s0.contact, s0.options);
  ASSERT_FALSE(reference.failed) << reference.stop_reason;
  ASSERT_GE(reference.slip_events, 1);
  // Stopped at the first poll after the first slip was accepted.
  std::optional<SlideState> saved;
  int slips = 0;
  const SlideResult stopped = slide::slide(
      s0.contact, s0.options,
      SlideControl{.progress = [&](const slide::SlideProgressInfo& i) { slips = i.slip_events; },
                   .checkpoint = [&](const SlideState& st) { saved = st; },
                   .checkpoint_every_s = 1e9,
                   .stop_requested = [&] { return slips >= 1; }});
  ASSERT_TRUE(stopped.interrupted);
  ASSERT_TRUE(saved.has_value());
  ASSERT_GE(saved->partial.slip_events, 1);

  // Written by another build, for the full step.
  std::string other_build = app::slide_fingerprint(s0);
  other_build = other_build.substr(0, other_build.find(" code=")) +
                " code=asperity 0.0.9 (commit 1234567) model=lfm";
  const app::SlideCheckpoint old{.settings = other_build, .state = *saved};
  const auto file = dir_ / "checkpoint.cbor";
  app::write_checkpoint(file, old);

  app::SlideScene s1 = s0;
  s1.options.step_growth = 2.0;
  const std::string now = app::slide_fingerprint(s1);
  const std::string refused = test_support::invalid_argument_message(
      [&] { app::check_or_adopt_checkpoint(old, now, file, false); });
  EXPECT_NE(refused.find("--adopt"), std::string::npos) << refused;
  const auto adoption = app::check_or_adopt_checkpoint(old, now, file, true);
  ASSERT_TRUE(adoption.has_value());
  EXPECT_NE(adoption->removed.find("slide.step_growth=0"), std::string::npos) << adoption->removed;
  EXPECT_NE(adoption->removed.find("1234567)"), std::string::npos) << adoption->removed;
  EXPECT_NE(adoption->added.find("slide.step_growth=2"), std::string::npos) << adoption->added;
  EXPECT_FALSE(
      app::check_or_adopt_checkpoint(app::SlideCheckpoint{.settings = now}, now, file, true)
          .has_value());

  // Another problem is refused even with --adopt, naming what differs.
  app::SlideScene s2 = s1;
  s2.contact.alpha = 0.6;
  const std::string problem = test_support::invalid_argument_message(
      [&] { app::check_or_adopt_checkpoint(old, app::slide_fingerprint(s2), file, true); });
  EXPECT_NE(problem.find("contact.alpha"), std::string::npos) << problem;
  EXPECT_EQ(problem.find("slide.step_growth"), std::string::npos)
      << "only the items that may not differ are named: " << problem;

  // The record: the adopted file under a second name (twice: .1 and .2), one entry each.
  app::record_adoption(file, old, *adoption);
  app::record_adoption(file, old, *adoption);
  for (const char* kept : {"checkpoint.adopted.1.cbor", "checkpoint.adopted.2.cbor"}) {
    EXPECT_EQ(app::read_checkpoint(dir_ / kept).settings, other_build) << kept;
  }
  std::ifstream in(dir_ / "adopted.json");
  const auto record = nlohmann::json::parse(in);
  ASSERT_EQ(record.size(), 2u);
  EXPECT_EQ(record[1].at("kept_as"), "checkpoint.adopted.2.cbor");
  EXPECT_EQ(record[0].at("Dx").get<double>(), saved->current.Dx);
  EXPECT_EQ(record[0].at("slip_events").get<int>(), saved->partial.slip_events);
  EXPECT_EQ(record[0].at("settings"), now);

  // The slide goes on under the new settings: the rows before the stop are the first run's;
  // after the next slip the step restarts at min_step.
  const SlideResult adopted =
      slide::slide(s1.contact, s1.options, SlideControl{.start = &old.state});
  ASSERT_FALSE(adopted.failed) << adopted.stop_reason;
  const std::size_t kept_rows = saved->partial.trace.size();
  ASSERT_GE(adopted.trace.size(), kept_rows);
  for (std::size_t i = 0; i < kept_rows; ++i) {
    EXPECT_EQ(adopted.trace[i].Dx, reference.trace[i].Dx) << "row " << i;
    EXPECT_EQ(adopted.trace[i].Fx, reference.trace[i].Fx) << "row " << i;
  }
  EXPECT_EQ(adopted.mu, reference.mu);  // Regime II: the peak before the first slip
  // The first step after the stop follows the new rule: min_step times 2 per row accepted
  // since the slip (the replayed second cycle, if any, comes later).
  std::size_t since = 0;
  for (std::size_t i = kept_rows; i-- > 0 && !saved->partial.trace[i].slip;)
    ++since;
  ASSERT_GT(adopted.trace.size(), kept_rows);
  ASSERT_GT(reference.trace.size(), kept_rows);
  const double expected = std::min(s1.options.max_step,
                                   s1.options.min_step * std::pow(2.0, static_cast<double>(since)));
  const double step = adopted.trace[kept_rows].Dx - adopted.trace[kept_rows - 1].Dx;
  EXPECT_NEAR(step, expected, 1e-12);
  std::printf(
      "stopped after %d slip(s) at Dx = %.4f d (%zu rows after it); the next step: %.4f d (full "
      "step: %.4f d); adopted slide: %d slips\n",
      saved->partial.slip_events, saved->current.Dx, since, step,
      reference.trace[kept_rows].Dx - reference.trace[kept_rows - 1].Dx, adopted.slip_events);
}

TEST(SlideCheckpoint, RejectsStatesAndFilesThatDoNotFit) {
  const auto s = scene(6.0, 1.2);
  std::optional<SlideState> saved;
  int polls = 0;
  slide::slide(s.contact, s.options,
               SlideControl{.checkpoint = [&](const SlideState& st) { saved = st; },
                            .stop_requested = [&] { return ++polls == 3; }});
  ASSERT_TRUE(saved.has_value());

  // Another contact radius: another block.
  auto other = s;
  other.contact.a = 8.0;
  EXPECT_THROW(slide::slide(other.contact, other.options, SlideControl{.start = &*saved}),
               std::invalid_argument);
  EXPECT_THROW(slide::slide(s.contact, s.options, SlideControl{.checkpoint_every_s = -1.0}),
               std::invalid_argument);

  const app::SlideCheckpoint c{.settings = app::slide_fingerprint(s), .state = *saved};
  EXPECT_NO_THROW(app::check_checkpoint_settings(c, s, "c.cbor"));
  try {
    app::check_checkpoint_settings(c, other, "c.cbor");
    ADD_FAILURE() << "other settings accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("a=6"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("a=8"), std::string::npos) << e.what();
  }

  // Every truncation throws std::invalid_argument; a corrupted byte either throws it (nothing
  // else) or decodes to a checkpoint, which must then encode back to the damaged bytes (a byte
  // of a value, not of the structure, was changed): never a crash, never a silent repair.
  const auto bytes = app::encode_checkpoint(c);
  for (std::size_t n = 0; n < bytes.size(); n += 1 + n / 8) {
    EXPECT_THROW(app::decode_checkpoint({bytes.data(), n}, "c.cbor"), std::invalid_argument)
        << n << " bytes";
  }
  int refused = 0, decoded = 0;
  for (std::size_t at = 0; at < 200 && at < bytes.size(); ++at) {
    auto damaged = bytes;
    damaged[at] ^= 0x5a;
    try {
      const auto back = app::decode_checkpoint(damaged, "c.cbor");
      ++decoded;
      EXPECT_EQ(app::encode_checkpoint(back), damaged) << "byte " << at;
    } catch (const std::invalid_argument&) {
      ++refused;
    }
  }
  std::printf("corrupted bytes: %d refused, %d decoded as other values\n", refused, decoded);
  EXPECT_GT(refused, 0);

  // Arrays nested a million deep (0x81: an array of one element) once overflowed the stack of
  // the recursive CBOR reader (fuzz_checkpoint); the reader now stops at a fixed depth.
  const std::vector<std::uint8_t> deep(1'000'000, 0x81);
  try {
    app::decode_checkpoint(deep, "deep.cbor");
    ADD_FAILURE() << "deep nesting accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("nested deeper than"), std::string::npos) << e.what();
  }
}

// A sink that records what it is handed, in order (label, Dx, ux), and repeats replayed paths
// as SlideResult::snapshots does.
class RecordFrames final : public slide::FrameSink {
 public:
  struct Frame {
    std::string label;
    double Dx;
    std::vector<double> ux;
  };
  void state(const slide::Snapshot& f) override { frames.push_back({f.label, f.Dx, f.ux}); }
  void path_frame(const slide::Snapshot& f) override { frames.push_back({f.label, f.Dx, f.ux}); }
  void replayed_path(const std::string& source, int periods, double period,
                     const std::string& label) override {
    const std::size_t n = frames.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (frames[i].label != source) continue;
      Frame moved = frames[i];
      moved.label = label;
      moved.Dx += periods * period;
      frames.push_back(std::move(moved));
    }
  }
  std::vector<Frame> frames;
};

// Frames streamed to a sink are the frames a slide without one collects, in the same order (the
// peak last instead of first), and a slide with a sink holds none: its result and every
// checkpoint carry no snapshot, and a checkpoint is the size of the states it must keep (issue
// 22: it held every frame of the slide, 434 MB at a = 50 d, R = 100 d).
TEST(FrameSink, StreamsTheFramesAndHoldsNone) {
  app::SlideScene s = scene(43.0, 0.0);  // automatic distance: two slips, the second replayed
  s.options.fft.threads = 1;
  const SlideResult collected = slide::slide(s.contact, s.options);
  RecordFrames sink;
  std::size_t checkpoints = 0;
  const SlideResult streamed = slide::slide(
      s.contact, s.options,
      SlideControl{.checkpoint =
                       [&](const SlideState& st) {
                         ++checkpoints;
                         EXPECT_TRUE(st.partial.snapshots.empty());
                         std::size_t states = 2 + st.window.size() + (st.previous ? 1 : 0) +
                                              (st.earlier ? 1 : 0) + (st.runner_up ? 1 : 0);
                         // Two fields of 2 components per state, 8 bytes per value and 1 of
                         // CBOR framing per byte string; 200 bytes per trace row.
                         const double bound = static_cast<double>(states) * 2.0 *
                                                  static_cast<double>(st.current.f.size()) * 9.0 +
                                              200.0 * static_cast<double>(st.partial.trace.size()) +
                                              65536.0;
                         const auto bytes = app::encode_checkpoint(
                             {.settings = app::slide_fingerprint(s), .state = st});
                         EXPECT_LT(static_cast<double>(bytes.size()), bound);
                       },
                   .checkpoint_every_s = 0.0,
                   .frames = &sink});
  ASSERT_GT(checkpoints, 5u);
  ASSERT_EQ(collected.slip_events, 2);
  ASSERT_GT(collected.replayed_steps, 0);
  EXPECT_TRUE(streamed.snapshots.empty());
  SlideResult without_frames = collected;
  without_frames.snapshots.clear();
  test::expect_same_result(without_frames, streamed, "streamed");
  ASSERT_EQ(sink.frames.size(), collected.snapshots.size());
  // The collected peak comes first, the streamed one last.
  std::vector<RecordFrames::Frame> expected;
  for (std::size_t k = 1; k < collected.snapshots.size(); ++k) {
    const auto& f = collected.snapshots[k];
    expected.push_back({f.label, f.Dx, f.ux});
  }
  expected.push_back({"peak", collected.snapshots.front().Dx, collected.snapshots.front().ux});
  int paths = 0;
  for (std::size_t k = 0; k < expected.size(); ++k) {
    EXPECT_EQ(sink.frames[k].label, expected[k].label) << "frame " << k;
    EXPECT_EQ(sink.frames[k].Dx, expected[k].Dx) << "frame " << k;
    EXPECT_EQ(sink.frames[k].ux, expected[k].ux) << "frame " << k;
    paths += expected[k].label == "slip_002_path" ? 1 : 0;
  }
  EXPECT_GT(paths, 0);  // the replayed slip has its path
  EXPECT_EQ(streamed.peak_snapshot.ux, collected.snapshots.front().ux);
}

// Relaxation paths of every k-th slip only (SlideOptions::path_frame_slips), and none at k = 0.
TEST(FrameSink, PathsOfEveryKthSlip) {
  app::SlideScene s = scene(24.0, 0.0);
  s.contact.R = 40.0;  // Regime III: many small slips
  s.options.fft.threads = 1;
  s.options.path_frame_slips = 3;
  const SlideResult r = slide::slide(s.contact, s.options);
  ASSERT_GE(r.slip_events, 5);
  int with_path = 0;
  for (int event = 1; event <= r.slip_events; ++event) {
    char label[32];
    std::snprintf(label, sizeof label, "slip_%03d_path", event);
    const bool has = std::any_of(r.snapshots.begin(), r.snapshots.end(),
                                 [&](const auto& f) { return f.label == label; });
    // A selected slip relaxed in fewer than path_frame_every iterations has no frame to show.
    if ((event - 1) % 3 != 0) {
      EXPECT_FALSE(has) << label;
    }
    with_path += has ? 1 : 0;
  }
  EXPECT_GE(with_path, 2);
  s.options.path_frame_slips = 0;
  const SlideResult none = slide::slide(s.contact, s.options);
  EXPECT_FALSE(std::any_of(none.snapshots.begin(), none.snapshots.end(),
                           [](const auto& f) { return f.label.ends_with("_path"); }));
  EXPECT_EQ(none.mu, r.mu);  // frames do not change the slide
}

}  // namespace
}  // namespace asperity
