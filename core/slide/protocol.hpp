// The sliding protocols of MODEL.md section 5 (slider.hpp: reference and adaptive, bisection of
// instabilities, slip detection, peak refinement, checkpoints), written once against a model of
// the contact so that the lateral force model (slider.cpp) and the explicit atomistic model
// (explicit/explicit_slide.cpp) slide through the same code.
//
// A Model (the concept SlideModel below) provides (State = SlideFields; its fields live on a block
// of sites that the model chooses, identified by State::shift and the field size):
//   State initial();                           the state the slide starts from (unrelaxed)
//   MinimizeResult relax(State& s, double Dx, std::vector<PathFrame>* frames, bool stop_on_slip,
//                        const MinimizerOptions* solver = nullptr);
//                                              move s to tip position Dx and minimise (with
//                                              `solver`, or the slide's minimiser; path
//                                              frames, if it records them, to `frames`); with
//                                              stop_on_slip, return Termination::interrupted as
//                                              soon as a slip is certain (LFM: a site moved by
//                                              3/4 d; explicit model: d/2)
//   void align(State& s, const State& like);   bring s's fields onto like's block (warm starts)
//   int slipped_sites(const State& before, const State& after);  registry index changes
//   Snapshot snapshot(const State& s, std::string label);
//   std::string check_fields(const State& s);  why s cannot be a state of this scene (a start
//                                              state's fields on a foreign block), or empty
//   std::size_t field_size(), contact_sites(), gf_applications();  Shape2 block_shape(),
//   fft_grid();
// and optionally std::function<bool(int)> heartbeat, called during relax() with the iteration
// (progress reports from inside long relaxations); returning true abandons the relaxation (a stop
// request acts within it, not after it).
// Frames (snapshots) go to SlideControl::frames as they are made, or, without a sink, to
// SlideResult::snapshots.
// Include only from the .cpp files that instantiate it.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <concepts>
#include <cstdio>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "common/validate.hpp"
#include "slide/types.hpp"

namespace asperity::slide::detail {

// The sink of a slide without SlideControl::frames: collects the frames in a vector (the
// slide's result), as the library did before frames were streamed.
class CollectFrames final : public FrameSink {
 public:
  explicit CollectFrames(std::vector<Snapshot>& out) : out_(out) {}
  void state(const Snapshot& frame) override { out_.push_back(frame); }
  void path_frame(const Snapshot& frame) override { out_.push_back(frame); }
  void replayed_path(const std::string& source, int periods, double period,
                     const std::string& label) override {
    const std::size_t n = out_.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (out_[i].label != source) continue;
      Snapshot moved = out_[i];
      moved.label = label;
      moved.Dx += periods * period;
      moved.block.origin0 += periods;
      out_.push_back(std::move(moved));
    }
  }

 private:
  std::vector<Snapshot>& out_;
};

// A slip relaxation by the flow that may pause and continue (Model::relax takes it if the model
// supports pauses: the lateral force model): where to pause, the pause to continue from, and
// the path frames' interval, which the relaxation keeps here while it runs.
struct RelaxPausing {
  const minimize::FlowPause* from = nullptr;
  minimize::FlowPauses pauses;
  int frame_interval = 0;  // 0: SlideOptions::path_frame_every
};

// What the protocol needs to know of the scene.
// The contact model a slide runs on (the list at the top of this file), as a type: the lateral
// force model (slider.cpp) and the explicit model (explicit/explicit_slide.cpp) satisfy it, and a
// third model is one class that does. Optional: `heartbeat` (progress from inside relaxations)
// and period_mismatch(later, earlier) (the cycle replay).
template <class M>
concept SlideModel = requires(M& m, const M& cm, SlideFields& s, const SlideFields& cs, double Dx,
                              std::vector<PathFrame>* frames,
                              const minimize::MinimizerOptions* solver) {
  { m.initial() } -> std::same_as<SlideFields>;
  { m.relax(s, Dx, frames) } -> std::same_as<minimize::MinimizeResult>;
  { m.relax(s, Dx, frames, true, solver) } -> std::same_as<minimize::MinimizeResult>;
  m.align(s, cs);
  { m.slipped_sites(cs, cs) } -> std::convertible_to<int>;
  { m.snapshot(cs, std::string()) } -> std::same_as<Snapshot>;
  { m.snapshot(cs, std::string(), 0) } -> std::same_as<Snapshot>;
  { cm.check_fields(cs) } -> std::convertible_to<std::string>;
  { cm.field_size() } -> std::convertible_to<std::size_t>;
  { cm.contact_sites() } -> std::convertible_to<std::size_t>;
  { cm.gf_applications() } -> std::convertible_to<std::size_t>;
  { cm.block_shape() } -> std::same_as<Shape2>;
  { cm.fft_grid() } -> std::same_as<Shape2>;
};

struct ProtocolParams {
  double d = 1.0;             // lattice spacing (d)
  double alpha = 1.0;         // local friction coefficient, for mu / alpha
  double Fz_continuum = 0.0;  // continuum load reported with the result (G d^2)
  double default_cap = 0.0;   // automatic distance cap when SlideOptions.max_distance = 0 (d)
};

// A start state must come from a slide of the same scene: every field on a block of that
// scene (the model says which blocks it accepts).
template <SlideModel Model>
void check_start(const SlideState& st, const Model& model) {
  const auto fields = [&](const SlideFields& f, const char* name) {
    if (const std::string why = model.check_fields(f); !why.empty()) {
      reject(std::string("SlideState.") + name + " fields",
             std::to_string(f.f.size()) + " and " + std::to_string(f.u.size()) + " values", why);
    }
    if (!std::isfinite(f.Dx) || !(f.Dx >= 0.0)) {
      reject(std::string("SlideState.") + name + ".Dx", std::to_string(f.Dx), "finite and >= 0");
    }
    if (!std::isfinite(f.h) || !std::isfinite(f.dFz_dh) || !(f.dFz_dh <= 0.0)) {
      reject(std::string("SlideState.") + name + ".h and dFz_dh",
             std::to_string(f.h) + " and " + std::to_string(f.dFz_dh), "finite, dFz_dh <= 0");
    }
  };
  fields(st.current, "current");
  fields(st.peak, "peak");
  if (st.previous) fields(*st.previous, "previous");
  if (st.earlier) fields(*st.earlier, "earlier");
  if (st.runner_up) fields(*st.runner_up, "runner_up");
  for (const SlideFields& w : st.window)
    fields(w, "window");
  if (st.window_rows.size() != st.window.size())
    reject("SlideState.window_rows", std::to_string(st.window_rows.size()) + " rows",
           "one per window state (" + std::to_string(st.window.size()) + ")");
  if (st.window.size() > kCycleWindow)
    reject("SlideState.window", std::to_string(st.window.size()) + " states",
           "at most kCycleWindow = " + std::to_string(kCycleWindow));
  for (std::size_t i = 0; i < st.window_rows.size(); ++i) {
    const std::size_t row = st.window_rows[i];
    if (row >= st.partial.trace.size() || (i > 0 && row <= st.window_rows[i - 1]) ||
        st.partial.trace[row].Dx != st.window[i].Dx || st.window[i].Dx > st.current.Dx) {
      reject("SlideState.window_rows", std::to_string(row),
             "increasing rows of partial.trace at the window states' Dx, up to current.Dx");
    }
  }
  if (st.partial.trace.empty())
    reject("SlideState.partial.trace", "empty", "the first row at least");
  if (st.pending) {
    // The pair's size is checked where the flow continues (minimize), against the contact.
    if (!(st.pending->Dx > st.current.Dx) || !std::isfinite(st.pending->Dx)) {
      reject("SlideState.pending.Dx", std::to_string(st.pending->Dx),
             "finite and beyond current.Dx = " + std::to_string(st.current.Dx));
    }
    // Frames are displacements at the pause's tip position, all on one block near current's.
    for (const PathFrame& frame : st.pending->frames) {
      if (frame.fields.u.size() != model.field_size() || !frame.fields.f.empty()) {
        reject("SlideState.pending.frames", std::to_string(frame.fields.u.size()) + " values",
               "a displacement of " + std::to_string(model.field_size()) + " values, no force");
      }
      if (frame.fields.Dx != st.pending->Dx ||
          frame.fields.shift != st.pending->frames.front().fields.shift ||
          std::abs(static_cast<long long>(frame.fields.shift) - st.current.shift) > 2 ||
          frame.iteration < 0 || frame.iteration > st.pending->flow.iteration) {
        reject("SlideState.pending.frames", "Dx " + std::to_string(frame.fields.Dx),
               "frames at the pause's Dx, on one block within 2 rows of current's, taken at "
               "iterations up to the pause's");
      }
    }
    // Counts that later sums must not overflow.
    constexpr int kMaxCount = std::numeric_limits<int>::max() / 4;
    if (st.pending->fast.iterations < 0 || st.pending->fast.iterations > kMaxCount ||
        st.pending->flow.iteration > kMaxCount) {
      reject("SlideState.pending iterations",
             std::to_string(st.pending->fast.iterations) + " and " +
                 std::to_string(st.pending->flow.iteration),
             "0 ... " + std::to_string(kMaxCount));
    }
    if (st.pending->frame_interval < 0)
      reject("SlideState.pending.frame_interval", std::to_string(st.pending->frame_interval),
             ">= 0");
  }
}

// The static peak is established once it has held over a whole period d of sliding with
// slips_to_stop slip events after it. In Regime II the stick-slip cycle repeats with period
// d, so this is the slips_to_stop-th slip itself; in Regime III arrested loops pile up and
// Fx keeps rising through many small slips (R = 100 d, a = 70 d: mu/alpha 0.091 at the
// second slip, 0.129 and still rising 2.5 d later), and a count of slips alone would report
// the first one as mu.
// A repeated cycle reaches its maximum again only to within the sampling of the trace (a
// bracket of min_step before a slip; a smooth maximum between coarse steps, which can be
// missed altogether: the explicit model's first cycle, sampled every 0.4 d, shows 0.392
// where the second shows 0.423), and that must not count as a new peak. So each stick
// segment (the stable samples between slips) carries the uncertainty of its highest sample,
// the steps to its stable neighbours, at least kPeakTie (a fifth of the 0.5% to which mu is
// converged, docs/benchmarks.md); the peak held from the first segment whose highest sample
// reaches the maximum within its own uncertainty, or the first slip row that does within
// kPeakTie.
//
// t: the trace so far; best: the largest Fx/Fz of it; ratio_now, Dx_now: the current state (the
// last row); d: the period; slips_to_stop: the slip events wanted after the peak.
inline constexpr double kPeakTie = 1e-3;
inline bool peak_held(std::span<const TraceRow> t, double best, double ratio_now, double Dx_now,
                      double d, int slips_to_stop) {
  // The slide stops at a slip, and not while Fx is still within reach of the peak (after a
  // small slip in Regime III it can lie just below it and rise past it next).
  if (t.empty() || !t.back().slip) return false;
  const auto y = [&](std::size_t i) { return t[i].Fx / t[i].Fz; };
  const double floor_tie = kPeakTie * std::abs(best);
  double largest_tie = floor_tie;
  std::optional<double> held_Dx;
  std::size_t top = 0;  // highest sample of the current stick segment
  for (std::size_t i = 1; i <= t.size(); ++i) {
    if (i < t.size() && !t[i].slip) {
      if (t[top].slip || y(i) > y(top)) top = i;
      continue;
    }
    if (!t[top].slip) {  // the segment ends
      double tie = floor_tie;
      if (top > 0 && !t[top - 1].slip) tie = std::max(tie, std::abs(y(top) - y(top - 1)));
      if (top + 1 < t.size() && !t[top + 1].slip)
        tie = std::max(tie, std::abs(y(top) - y(top + 1)));
      largest_tie = std::max(largest_tie, tie);
      if (!held_Dx && y(top) + tie >= best) held_Dx = t[top].Dx;
    }
    if (i < t.size()) {
      top = i;
      // A slip row is a sample of its own, exact in Dx (a bracket end). In a Regime III
      // steady state Fx can rise through a run of tiny slips with no stable sample between
      // them and peak on one of them (R = 40 d, a = 36 d: a 2-site slip, the same to 1e-12
      // every period from 11.6 d on); without this such a peak never held and the slide ran
      // to the cap, reporting a lower bound.
      if (!held_Dx && y(i) + floor_tie >= best) held_Dx = t[i].Dx;
    }
  }
  if (!held_Dx || ratio_now >= best - largest_tie) return false;
  if (Dx_now < *held_Dx + d - 1e-9 * d) return false;
  return std::count_if(t.begin(), t.end(), [&](const TraceRow& row) {
           return row.slip && row.Dx > *held_Dx;
         }) >= slips_to_stop;
}

// Kinetic friction of a trace (MODEL.md 5): the mean of Fx/Fz over Dx (trapezoid: adaptive
// steps are uneven) after the first slip; without slips (smooth sliding) over the last whole
// period d before Dx_end. NaN if neither exists (no slip, slide shorter than d).
inline double kinetic_friction(std::span<const TraceRow> t, double Dx_end, double d) {
  auto from = std::find_if(t.begin(), t.end(), [](const TraceRow& row) { return row.slip; });
  if (from == t.end() && Dx_end >= d) {
    from = std::find_if(t.begin(), t.end(),
                        [&](const TraceRow& row) { return row.Dx >= Dx_end - d - 1e-12; });
  }
  if (from == t.end()) return std::numeric_limits<double>::quiet_NaN();
  double area = 0.0, span = 0.0;
  for (auto a = from; a + 1 != t.end(); ++a) {
    const double w = (a + 1)->Dx - a->Dx;
    area += 0.5 * w * (a->Fx / a->Fz + (a + 1)->Fx / (a + 1)->Fz);
    span += w;
  }
  return span > 0.0 ? area / span : from->Fx / from->Fz;
}

template <SlideModel Model>
SlideResult run_protocol(Model& model, const ProtocolParams& params, const SlideOptions& options,
                         const SlideControl& control, std::chrono::steady_clock::time_point t0) {
  using State = SlideFields;
  const auto elapsed = [&t0] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  SlideResult res;
  // Of the earlier sessions of a resumed slide (counted in the start state).
  std::size_t gf_before = 0;
  double wall_before = 0.0;
  if (control.start) {
    check_start(*control.start, model);
    res = control.start->partial;
    gf_before = res.gf_applications;
    wall_before = res.wall_s;
  }
  res.block = model.block_shape();
  res.fft_grid = model.fft_grid();
  CollectFrames collect(res.snapshots);
  FrameSink& sink = control.frames ? *control.frames : collect;
  res.Fz_continuum = params.Fz_continuum;
  const double d = params.d;
  const bool automatic = options.distance == 0.0;
  const double limit =
      automatic ? (options.max_distance > 0.0 ? options.max_distance : params.default_cap)
                : options.distance;

  State state = model.initial();
  // The start state replaces the initial one: GF work the model spent building it (the
  // explicit model's Hertz start) was counted by the session that did use it.
  const std::size_t gf_unused = control.start ? model.gf_applications() : 0;
  // Progress report: what starts now (or was just accepted), with the cost so far; a model that
  // can (one with a `heartbeat` slot) also reports while it relaxes, so that a relaxation of
  // many minutes (a slip through a large contact) shows what it is and that it runs.
  SlidePhase relaxing = SlidePhase::start;
  double relaxing_to = 0.0;
  const auto report = [&](SlidePhase phase, double target, int iteration = 0) {
    if (!control.progress) return;
    if (iteration == 0) {
      relaxing = phase;
      relaxing_to = target;
    }
    control.progress(
        SlideProgressInfo{.phase = phase,
                          .Dx = state.Dx,
                          .target_Dx = target,
                          .limit = limit,
                          .slip_events = res.slip_events,
                          .steps = res.steps,
                          .replayed_steps = res.replayed_steps,
                          .gf_applications = gf_before + model.gf_applications() - gf_unused,
                          .wall_s = wall_before + elapsed(),
                          .iteration = iteration});
  };
  // A stop request is also polled from inside a relaxation of the stepping or of the peak
  // refinement (not the first one, before which there is no state to hand over): the relaxation,
  // of a copy of the state, is abandoned and the state it started from is handed over, so that
  // the resumed slide repeats it. A slip through a large contact relaxes for most of an hour
  // (R = 1700 d, a = 510 d: 12 854 iterations), which a stop must not wait for.
  bool may_abandon = false;
  bool abandoned = false;
  // The slip minimiser's flow is paused instead (SlideState::pending), at its next accepted step.
  bool may_pause = false;
  bool pause_requested = false;
  const auto stop_requested = [&] { return control.stop_requested && control.stop_requested(); };
  struct ClearOnExit {
    std::function<bool(int)>* slot = nullptr;
    ~ClearOnExit() {
      if (slot) *slot = nullptr;  // it refers to this call's locals
    }
  } clear_heartbeat;
  if constexpr (requires { model.heartbeat = std::function<bool(int)>{}; }) {
    if (control.progress || control.stop_requested) {
      model.heartbeat = [&](int iteration) {
        report(relaxing, relaxing_to, iteration);
        const bool stop = (may_abandon || may_pause) && stop_requested();
        abandoned = may_abandon && stop;
        pause_requested = pause_requested || (may_pause && stop);
        return abandoned;
      };
      clear_heartbeat.slot = &model.heartbeat;
    }
  }
  // A trace row of state s; replayed rows cost no iterations.
  const auto record = [&](const State& s, int iterations, std::size_t gf, double max_force,
                          bool slip, int sites, bool replayed) {
    res.trace.push_back(
        TraceRow{s.Dx, s.Fx, s.Fz, s.energy, iterations, gf, max_force, slip, sites, replayed});
    res.iterations += iterations;
  };
  const auto count = [&](const minimize::MinimizeResult& r) {
    ++res.minimizations;
    res.gradient_evaluations += r.interface_evaluations;
    res.filter_applications += r.filter_applications;
    res.filtered = res.filtered || r.filtered;
  };
  // Why a relaxation to Dx (from the state at `from`) cannot be accepted: the minimiser did not
  // converge, or the relaxed state has non-finite forces or energy. Empty if it can. The message
  // names the step and the parameters needed to reproduce it.
  const auto failure = [&](const minimize::MinimizeResult& r, const State& s, double Dx,
                           double from,
                           const minimize::MinimizerOptions* solver = nullptr) -> std::string {
    const minimize::MinimizerOptions& m = solver ? *solver : options.minimizer;
    const char* what = nullptr;
    if (r.termination != Termination::converged) {
      what = "";
    } else if (!std::isfinite(s.Fx) || !std::isfinite(s.Fz) || !std::isfinite(s.energy) ||
               !(s.Fz > 0.0)) {
      // Fz = 0 (a load that underflowed) would make mu = Fx / Fz NaN.
      what = "non-finite force or energy, or no load, after ";
    } else {
      return {};
    }
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "%sminimizer %s at Dx = %.9g d (step %d, from Dx = %.9g d, step size %.3g d; "
                  "%d iterations, max force %.3g, energy %.9g; %s, tolerance %g, max "
                  "iterations %d)",
                  what, to_string(r.termination).c_str(), Dx, res.steps + 1, from, Dx - from,
                  r.iterations, r.max_force, r.energy, minimize::to_string(m.method).c_str(),
                  m.force_tolerance, m.max_iterations);
    return buf;
  };

  std::optional<State> peak, previous, earlier, runner_up;
  double runner_up_ratio = -std::numeric_limits<double>::infinity();
  double best = 0.0;
  double first_max_Dx = -1.0;  // Regime I: first maximum of Fx without a slip
  double slip_at = std::numeric_limits<double>::infinity();
  bool stopped = false;
  // Cycle replay (SlideOptions::replay_cycle): the accepted states of the last period d and a
  // step, with their trace rows, so that a state one period after one of them can be compared.
  std::vector<State> window;
  std::vector<std::size_t> window_rows;
  bool cycle_check_due = false;
  // Only models that can compare states a period apart replay (the explicit model does not).
  constexpr bool comparable = requires(const Model& m, const State& a) {
    m.period_mismatch(a, a);
  };
  const auto mismatch = [&](const State& later, const State& before) {
    if constexpr (comparable) {
      return model.period_mismatch(later, before);
    } else {
      return std::numeric_limits<double>::infinity();
    }
  };
  const bool replay = comparable && options.replay_cycle && options.protocol == Protocol::adaptive;
  constexpr std::size_t kMaxWindow = kCycleWindow;  // slider.hpp
  // Fraction of the contact sites whose registry index changed in a slip worth a probe (seen:
  // 0.86 to 1.006 in Regime II, where edge sites catch up while sticking; mostly 0.001 to 0.03
  // in Regime III, with a few larger partial slips of 0.58 to 0.84).
  constexpr double kSweptSlip = 0.5;
  // A slip relaxation paused in the slide this one continues (only models whose relax() takes a
  // RelaxPausing can pause).
  std::optional<PendingSlip> pending;
  constexpr bool pausable = requires(Model & m, State & s, std::vector<PathFrame> * frames,
                                     const minimize::MinimizerOptions* o, RelaxPausing* p) {
    m.relax(s, 0.0, frames, false, o, p);
  };
  if (control.start) {
    const SlideState& st = *control.start;
    state = st.current;
    previous = st.previous;
    earlier = st.earlier;
    peak = st.peak;
    runner_up = st.runner_up;
    best = st.best;
    runner_up_ratio = st.runner_up_ratio;
    first_max_Dx = st.first_max_Dx;
    slip_at = st.slip_at;
    stopped = st.stepping_done;
    window = st.window;
    window_rows = st.window_rows;
    cycle_check_due = st.cycle_check_due;
    pending = st.pending;
    if (pending) {
      const char* why =
          !pausable ? "this model cannot continue"
          : stopped ? "a state past the stepping cannot have"
          : !options.slip_minimizer || options.slip_minimizer->method != minimize::Method::flow
              ? "only a flow as slip minimiser makes"
          : pending->Dx > limit + 1e-12 ? "lies beyond the distance of this slide"
                                        : nullptr;
      if (why) {
        throw std::invalid_argument(
            std::string("slide: the start state holds a paused slip relaxation, which ") + why);
      }
    }
  } else {
    report(SlidePhase::start, 0.0);
    auto first = model.relax(state, 0.0, nullptr);
    count(first);
    res.contact_sites = model.contact_sites();
    record(state, first.iterations, first.gf_applications, first.max_force, false, 0, false);
    if (replay) {
      window.push_back(state);
      window_rows.push_back(0);
    }
    best = state.Fx / state.Fz;
    peak = state;
    if (const std::string why = failure(first, state, 0.0, 0.0); !why.empty()) {
      res.failed = true;  // no good state yet to keep
      res.stop_reason = why;
      stopped = true;
    }
  }

  // The state at the top of the stepping loop (or after it), for checkpoints. Its cost is the
  // model's so far, or `model_gf` (the count before an abandoned relaxation, whose work the
  // resumed slide repeats: counted once, a resumed slide reports an uninterrupted one's counts).
  const auto capture = [&](bool stepping_done, std::optional<std::size_t> model_gf = {}) {
    SlideState st{.current = state,
                  .previous = previous,
                  .earlier = earlier,
                  .peak = *peak,
                  .runner_up = runner_up,
                  .best = best,
                  .runner_up_ratio = runner_up_ratio,
                  .first_max_Dx = first_max_Dx,
                  .slip_at = slip_at,
                  .stepping_done = stepping_done,
                  .window = window,
                  .window_rows = window_rows,
                  .cycle_check_due = cycle_check_due,
                  .partial = res,
                  // A paused slip not yet continued (a resumed slide stopped or checkpointed
                  // before its first step) is handed on: its work is in `res` already.
                  .pending = pending};
    st.partial.gf_applications = gf_before + model_gf.value_or(model.gf_applications()) - gf_unused;
    st.partial.wall_s = wall_before + elapsed();
    return st;
  };
  // Stop on request: hand the state over and return what is known so far.
  // `abandoned_to`: the target of a relaxation abandoned for the stop, if one was.
  // A state with a pending slip relaxation (st.pending) was paused within it instead.
  const auto interrupt = [&](const SlideState& st,
                             double abandoned_to = std::numeric_limits<double>::quiet_NaN()) {
    if (control.checkpoint) control.checkpoint(st);
    SlideResult out = st.partial;
    out.interrupted = true;
    char buf[240];
    char within[140] = "";
    if (st.pending) {
      std::snprintf(within, sizeof within,
                    ", within the relaxation to Dx = %.6g d (paused at iteration %d of the flow, "
                    "continued on resume)",
                    st.pending->Dx, st.pending->flow.iteration);
    } else if (std::isfinite(abandoned_to)) {
      std::snprintf(within, sizeof within,
                    ", within the relaxation to Dx = %.6g d (repeated on resume)", abandoned_to);
    }
    std::snprintf(buf, sizeof buf, "interrupted at Dx = %.6g d%s%s", st.current.Dx,
                  st.stepping_done ? " (refining the peak)" : "", within);
    out.stop_reason = buf;
    out.mu = st.best;
    out.mu_over_alpha = st.best / params.alpha;
    out.mu_is_lower_bound = true;  // the static peak is not established yet
    out.peak_Dx = st.peak.Dx;
    out.Fz = st.peak.Fz;
    out.distance = st.current.Dx;
    out.kinetic = out.kinetic_over_static = std::numeric_limits<double>::quiet_NaN();
    return out;
  };
  auto last_checkpoint = std::chrono::steady_clock::now();
  const auto peak_held = [&] {
    return detail::peak_held(res.trace, best, state.Fx / state.Fz, state.Dx, d,
                             options.slips_to_stop);
  };

  const double h = options.protocol == Protocol::reference ? options.step : options.max_step;
  const auto slip_label = [](int event) {
    char label[32];
    std::snprintf(label, sizeof label, "slip_%03d", event);
    return std::string(label);
  };
  // Slip events whose relaxation paths are recorded: 1, 1 + k, 1 + 2k, ...
  const auto paths_of = [&](int event) {
    return options.path_frame_every > 0 && options.path_frame_slips > 0 && sink.wants_paths() &&
           (event - 1) % options.path_frame_slips == 0;
  };
  // Takes the next state of the slide (computed, or replayed from the repeating cycle) into the
  // trace; true when the slide stops there.
  // `frames`: the relaxation path of a computed step; `replay_of`: the slip event whose path a
  // replayed slip repeats, `periods` on (0: none).
  const auto accept = [&](State&& next, int iterations, std::size_t gf, double max_force, bool slip,
                          int sites, std::vector<PathFrame> frames, bool replayed,
                          int replay_of = 0, int periods = 0) {
    if (slip) {
      ++res.slip_events;
      const std::string label = slip_label(res.slip_events);
      for (auto [fields, suffix] :
           {std::pair<const State*, const char*>{&state, "_before"}, {&next, "_after"}}) {
        Snapshot frame = model.snapshot(*fields, label + suffix);
        frame.slipped_sites = sites;
        sink.state(frame);
      }
      // One Snapshot at a time: a path is held as displacements only (PathFrame).
      for (PathFrame& frame : frames) {
        sink.path_frame(model.snapshot(frame.fields, label + "_path", frame.iteration));
        frame.fields = {};
      }
      if (replay_of > 0 && paths_of(res.slip_events)) {
        sink.replayed_path(slip_label(replay_of) + "_path", periods, d, label + "_path");
      }
      // A slip that swept most of the contact (a Regime II loop, or several) may have brought
      // the state back to one of the last period: probe it. Not after the small slips of
      // Regime III (arrested loops; a few % of the sites each), where probes would be wasted.
      cycle_check_due =
          replay && !replayed &&
          static_cast<double>(sites) >= kSweptSlip * static_cast<double>(model.contact_sites());
    }
    earlier = std::move(previous);
    previous = std::move(state);
    state = std::move(next);
    record(state, iterations, gf, max_force, slip, sites, replayed);
    ++(replayed ? res.replayed_steps : res.steps);
    if (replay && !replayed) {
      window.push_back(state);
      window_rows.push_back(res.trace.size() - 1);
      std::size_t drop = 0;
      while (drop < window.size() &&
             (window[drop].Dx < state.Dx - d - h - 1e-9 * d || window.size() - drop > kMaxWindow))
        ++drop;
      window.erase(window.begin(), window.begin() + static_cast<std::ptrdiff_t>(drop));
      window_rows.erase(window_rows.begin(),
                        window_rows.begin() + static_cast<std::ptrdiff_t>(drop));
    }
    // A later maximum replaces the peak only if it is higher beyond the minimiser's noise: in
    // Regime I the trace repeats its first maximum a period later, and the first, which has
    // samples on both sides, is the one to refine.
    const double ratio = state.Fx / state.Fz;
    if (ratio > best + 1e-6 * std::abs(best)) {
      runner_up = std::move(peak);
      runner_up_ratio = best;
      best = ratio;
      peak = state;
    }
    report(SlidePhase::accepted, state.Dx);

    // Regime I: a smooth maximum (rise then fall, no slip yet).
    const std::size_t k = res.trace.size();
    if (first_max_Dx < 0.0 && res.slip_events == 0 && k >= 3 &&
        res.trace[k - 2].Fx > res.trace[k - 3].Fx && res.trace[k - 1].Fx < res.trace[k - 2].Fx) {
      first_max_Dx = res.trace[k - 2].Dx;
    }
    if (automatic && res.slip_events >= options.slips_to_stop && peak_held()) {
      res.stop_reason = "slip events reached";
      return true;
    }
    // Adaptive: the even steps start at most one step past the maximum, and the kinetic window
    // (the last period) must lie inside them.
    const double lead = options.protocol == Protocol::adaptive ? h : 0.0;
    if (automatic && res.slip_events == 0 && first_max_Dx >= 0.0 &&
        state.Dx >= first_max_Dx + lead + d - 1e-12) {
      res.stop_reason = "one period past the first maximum (no slip)";
      return true;
    }
    return false;
  };
  while (!stopped) {
    if (stop_requested()) return interrupt(capture(false));
    if (control.checkpoint) {
      const auto now = std::chrono::steady_clock::now();
      if (std::chrono::duration<double>(now - last_checkpoint).count() >=
          control.checkpoint_every_s) {
        control.checkpoint(capture(false));
        last_checkpoint = now;
      }
    }
    if (state.Dx >= limit - 1e-12) {
      res.stop_reason = automatic ? "distance cap reached" : "distance reached";
      break;
    }
    // Adaptive: a bracket [state.Dx, slip_at] around a known instability is bisected until it
    // is min_step wide; the slip is then taken from its stable end.
    // Smooth sliding (a maximum without a slip, Regime I): the kinetic friction is the mean of a
    // near-sinusoid over the last period, which the trapezoid rule gets right only from evenly
    // spread samples: eight per period from the first maximum on.
    const double step =
        options.protocol == Protocol::adaptive && first_max_Dx >= 0.0 && res.slip_events == 0
            ? std::min(h, 0.125 * d)
            : h;
    double Dx = std::min(state.Dx + step, limit);
    bool may_undo = false;
    if (options.protocol == Protocol::adaptive) {
      const double gap = slip_at - state.Dx;
      if (!std::isfinite(slip_at)) {
        may_undo = true;
      } else if (gap > options.min_step * 1.0001) {
        Dx = state.Dx + 0.5 * gap;
        may_undo = true;
      } else {
        Dx = slip_at;
      }
    }
    // Cycle replay: after a slip, a probe relaxes to one period d after the latest window state
    // within a step, to compare with it. A probe that does not find the cycle repeated (it
    // slipped, failed or differs) is dropped as if it had not been made: the slide goes on
    // with the step it would have taken, so a slide that never repeats (Regime III) follows the
    // same path as without the replay, at the probe's cost.
    std::optional<std::size_t> cycle_of;
    if (replay && cycle_check_due && !std::isfinite(slip_at)) {
      cycle_check_due = false;
      for (std::size_t i = window.size(); i-- > 0;) {
        const double target = window[i].Dx + d;
        if (target <= Dx && target > state.Dx + 1e-9 * d) {
          Dx = target;
          cycle_of = i;
          break;
        }
      }
    }
    State trial = state;
    // Warm start on a smooth branch: extrapolate the force field in Dx through the last two or
    // three states of the branch (Lagrange; u follows as G f). After a slip the branch is new.
    const std::size_t rows = res.trace.size();
    const bool on_branch1 = previous && !res.trace.back().slip && state.Dx > previous->Dx;
    const bool on_branch2 = on_branch1 && earlier && rows >= 3 && !res.trace[rows - 2].slip &&
                            previous->Dx > earlier->Dx;
    if (options.extrapolate && on_branch1) {
      State p1 = *previous;
      model.align(p1, trial);
      if (on_branch2) {
        State p2 = *earlier;
        model.align(p2, trial);
        const double x0 = p2.Dx, x1 = p1.Dx, x2 = state.Dx;
        const double l0 = (Dx - x1) * (Dx - x2) / ((x0 - x1) * (x0 - x2));
        const double l1 = (Dx - x0) * (Dx - x2) / ((x1 - x0) * (x1 - x2));
        const double l2 = (Dx - x0) * (Dx - x1) / ((x2 - x0) * (x2 - x1));
        for (std::size_t i = 0; i < trial.f.size(); ++i) {
          trial.f[i] = l0 * p2.f[i] + l1 * p1.f[i] + l2 * state.f[i];
        }
        trial.h = l0 * p2.h + l1 * p1.h + l2 * state.h;  // explicit model: tip height
      } else {
        const double w = (Dx - state.Dx) / (state.Dx - p1.Dx);
        for (std::size_t i = 0; i < trial.f.size(); ++i)
          trial.f[i] += w * (state.f[i] - p1.f[i]);
        trial.h += w * (state.h - p1.h);
      }
    }
    std::vector<PathFrame> frames;
    // Only a relaxation that will not be undone can become a slip event with a path (the next
    // one, if it slips).
    const bool want_frames = !may_undo && paths_of(res.slip_events + 1);
    // The slip relaxation paused in the slide this one continues: it belongs to this step, and
    // the relaxation that called the step a slip is not repeated.
    std::optional<PendingSlip> resuming = std::exchange(pending, std::nullopt);
    if (resuming && (resuming->Dx != Dx || may_undo || cycle_of ||
                     (!want_frames && !resuming->frames.empty()))) {
      char buf[240];
      std::snprintf(buf, sizeof buf,
                    "slide: the start state's paused slip relaxation goes to Dx = %.9g d, but "
                    "the step from it to Dx = %.9g d is %s",
                    resuming->Dx, Dx,
                    resuming->Dx != Dx || may_undo || cycle_of
                        ? "not a slip step"
                        : "one whose path is not recorded (the pause has path frames)");
      throw std::invalid_argument(buf);
    }
    report(cycle_of                  ? SlidePhase::probe
           : !std::isfinite(slip_at) ? SlidePhase::step
           : may_undo                ? SlidePhase::bisection
                                     : SlidePhase::slip,
           Dx);
    const std::size_t gf_at_top = model.gf_applications();
    minimize::MinimizeResult r;
    // With a slip minimiser, a step that the fast solver sees slip for certain (a site moved by
    // 3/4 d in the LFM, d/2 in the explicit model, as in the bisection) is handed to the slip
    // minimiser at once: relaxing the slip further would only be thrown away. (Before, it ran to
    // convergence: 5 908 iterations, about 25 minutes, before each flow at a = 430 d, R = 1700 d.)
    // A relaxation that would have moved a site that far and then come back (an overshoot) is
    // thereby also the flow's to decide, which is the reference's verdict (MODEL.md 5).
    const bool slip_goes_to_flow = options.slip_minimizer && !cycle_of && !may_undo;
    if (resuming) {
      r = resuming->fast;
    } else {
      may_abandon = true;
      r = model.relax(trial, Dx, want_frames ? &frames : nullptr, may_undo || slip_goes_to_flow);
      may_abandon = false;
      if (abandoned) return interrupt(capture(false, gf_at_top), Dx);
    }
    const bool stopped_at_slip = r.termination == Termination::interrupted;
    const minimize::MinimizerOptions* solver = &options.minimizer;  // the one whose result is r
    // A slip the minimiser would accept is relaxed again by the slip minimiser, if there is one
    // (SlideOptions::slip_minimizer), from the state moved to Dx without the warm start: where the
    // state goes after an instability, and whether the step is one, is the flow's to say
    // (MODEL.md 5). Trials that are undone when they slip (the bisection) only place the
    // bracket; the step that ends it is the one verified. If the slip minimiser finds it stable,
    // it is accepted as a stable state (a premature slip avoided) and the stepping goes on from
    // there. Probes of the cycle are dropped when they slip, so they are left alone.
    if (resuming ||
        (slip_goes_to_flow && (stopped_at_slip || (failure(r, trial, Dx, state.Dx).empty() &&
                                                   model.slipped_sites(state, trial) > 0)))) {
      const auto fast = r;
      trial = state;
      frames.clear();
      report(SlidePhase::slip, Dx);
      // The flow pauses (where the model can) rather than being abandoned: for a checkpoint
      // when one is due (not with checkpoint_every_s = 0, which would copy the state at every
      // step of the flow), and for a stop request, seen by the heartbeat.
      std::optional<SlideState> paused;
      bool relaxed = false;
      if constexpr (pausable) {
        if (options.slip_minimizer->method == minimize::Method::flow) {
          RelaxPausing pausing;
          if (resuming) {
            frames = std::move(resuming->frames);
            pausing.from = &resuming->flow;
            pausing.frame_interval = resuming->frame_interval;
          }
          pausing.pauses.due = [&](int) {
            if (pause_requested) return true;
            if (!control.checkpoint || !(control.checkpoint_every_s > 0.0)) return false;
            return std::chrono::duration<double>(std::chrono::steady_clock::now() - last_checkpoint)
                       .count() >= control.checkpoint_every_s;
          };
          pausing.pauses.pause = [&](const minimize::FlowPause& at) {
            SlideState st = capture(false);
            st.pending = PendingSlip{.Dx = Dx,
                                     .fast = fast,
                                     .flow = at,
                                     .frames = frames,
                                     .frame_interval = pausing.frame_interval};
            if (pause_requested) {
              paused = std::move(st);
              return true;
            }
            control.checkpoint(st);
            last_checkpoint = std::chrono::steady_clock::now();
            return false;
          };
          may_pause = true;
          r = model.relax(trial, Dx, want_frames ? &frames : nullptr, false,
                          &*options.slip_minimizer, &pausing);
          may_pause = false;
          relaxed = true;
          if (paused) return interrupt(*paused);
        }
      }
      if (!relaxed) {
        may_abandon = true;
        r = model.relax(trial, Dx, want_frames ? &frames : nullptr, false,
                        &*options.slip_minimizer);
        may_abandon = false;
      }
      // Counted only now: an abandoned step is repeated, both relaxations, by a resumed slide.
      if (abandoned) return interrupt(capture(false, gf_at_top), Dx);
      count(fast);
      solver = &*options.slip_minimizer;
      ++res.slip_relaxations;
      // The step's row carries the cost of both relaxations.
      r.iterations += fast.iterations;
      r.gf_applications += fast.gf_applications;
    }
    count(r);
    // A probe that failed or slipped did not find the cycle (nor one that differs, below).
    if (cycle_of && !failure(r, trial, Dx, state.Dx).empty()) continue;
    if (may_undo && r.termination == Termination::interrupted) {
      slip_at = Dx;  // slipped: bisect towards the instability
      continue;
    }
    if (const std::string why = failure(r, trial, Dx, state.Dx, solver); !why.empty()) {
      // The trial is dropped; the last accepted state is kept as a checkpoint (resumable) and
      // as snapshot "last_good".
      if (control.checkpoint) control.checkpoint(capture(false));
      res.failed = true;
      res.stop_reason = why;
      sink.state(model.snapshot(state, "last_good"));
      break;
    }
    const int sites = model.slipped_sites(state, trial);
    const bool slip = sites > 0;
    if (cycle_of && slip) continue;
    if (slip && may_undo) {
      slip_at = Dx;
      continue;
    }
    // After a slip the bracket is used up; a stable state at the bracket's end means the
    // instability lies further on (a trial from further back had slipped).
    if (slip || Dx >= slip_at) slip_at = std::numeric_limits<double>::infinity();
    // The state one period after a window state: if they are equal the cycle repeats, and the
    // period from the matched state to this one (the states after it, and this one), carried on
    // by whole periods, is the rest of the slide.
    const double cycle_mismatch =
        cycle_of ? mismatch(trial, window[*cycle_of]) : std::numeric_limits<double>::infinity();
    if (cycle_of && !(cycle_mismatch <= options.cycle_tolerance)) continue;
    const bool repeats = cycle_of.has_value();
    std::vector<State> cycle;
    std::vector<TraceRow> cycle_rows;
    std::vector<int> cycle_slip;  // slip event number of each row (0: none), for its path frames
    if (repeats) {
      for (std::size_t e = *cycle_of + 1; e < window.size(); ++e) {
        const std::size_t row = window_rows[e];
        cycle.push_back(std::move(window[e]));
        cycle_rows.push_back(res.trace[row]);
        cycle_slip.push_back(
            res.trace[row].slip
                ? static_cast<int>(std::count_if(
                      res.trace.begin(), res.trace.begin() + static_cast<std::ptrdiff_t>(row) + 1,
                      [](const TraceRow& t) { return t.slip; }))
                : 0);
      }
      cycle.push_back(trial);
      // Replayed states are not kept: the cycle holds them.
      window.clear();
      window_rows.clear();
    }
    if (accept(std::move(trial), r.iterations, r.gf_applications, r.max_force, slip, sites,
               std::move(frames), false)) {
      break;
    }
    if (!repeats) continue;
    cycle_rows.push_back(res.trace.back());
    cycle_slip.push_back(0);
    bool done = false, past_limit = false;
    for (int k = 1; !done && !past_limit; ++k) {
      for (std::size_t e = 0; e < cycle.size(); ++e) {
        State next = cycle[e];
        next.Dx += k * d;
        next.shift += k;
        if (next.Dx > limit + 1e-12) {
          past_limit = true;  // the computed steps take over up to the limit
          break;
        }
        if (res.cycle_verified_at < 0.0) {
          res.cycle_verified_at = state.Dx;
          res.cycle_mismatch = cycle_mismatch;
        }
        // A replayed slip's relaxation path is the computed one's, carried on by k periods.
        const TraceRow& row = cycle_rows[e];
        if (accept(std::move(next), 0, 0, row.max_force, row.slip, row.slipped_sites, {}, true,
                   cycle_slip[e], k)) {
          done = true;
          break;
        }
      }
    }
    if (done) break;
  }
  // The replay's window is of no use past the stepping (a resumed slide that had finished
  // stepping does not step again); its memory goes now, before the peak refinement.
  window.clear();
  window.shrink_to_fit();
  window_rows.clear();

  // mu and its resolution. Before a slip the peak is the last stable state: the instability
  // lies within one step after it, and mu is resolved to that step times the slope. A smooth
  // maximum (Regime I) is refined, in the adaptive protocol, by parabolic search on Dx in the
  // bracket of its neighbours (each point relaxed from the peak state); the reference protocol
  // keeps the classic sampled maximum, and reports the parabola's excess as its precision.
  // A maximum at the very end of the trace cannot be refined; if it only repeats an earlier one
  // within the minimiser's noise (Regime I a period later; 1e-6 relative is seen), the earlier
  // one, which has samples on both sides, is the peak.
  // (Not when the runner-up is the sample just before: that is a ramp, cut off by the distance.)
  // A stop requested during the refinement below returns this state: a resumed slide redoes
  // the refinement from it.
  // (Without the snapshots, which can be large and which the refinement leaves alone: they are
  // added back if the state is used.)
  std::optional<SlideState> stepping_end;
  if (control.stop_requested) {
    std::vector<Snapshot> snapshots = std::move(res.snapshots);
    res.snapshots.clear();
    stepping_end = capture(true);
    res.snapshots = std::move(snapshots);
  }
  const std::size_t n_rows = res.trace.size();
  if (runner_up && n_rows >= 2 && peak->Dx == res.trace.back().Dx &&
      runner_up->Dx < res.trace[n_rows - 2].Dx && best <= runner_up_ratio * (1.0 + 1e-4)) {
    peak = std::move(runner_up);
    best = runner_up_ratio;
  }
  // Still rising at the last sample (cap or a fixed distance hit on the loading ramp): the
  // static peak lies further on, mu is only a lower bound.
  // So is any peak when the automatic cap stopped a slide with slips: had the peak held, the
  // slide would have stopped at a slip before the cap (Regime III still hardening).
  res.mu_is_lower_bound =
      peak->Dx == res.trace.back().Dx ||
      (automatic && res.slip_events > 0 && res.stop_reason == "distance cap reached");
  res.mu = best;
  res.peak_Dx = peak->Dx;
  res.Fz = peak->Fz;
  const auto at_peak = std::find_if(res.trace.begin(), res.trace.end(),
                                    [&](const TraceRow& row) { return row.Dx == peak->Dx; });
  const auto ratio = [](const TraceRow& row) { return row.Fx / row.Fz; };
  if (at_peak != res.trace.begin() && at_peak != res.trace.end() &&
      at_peak + 1 != res.trace.end()) {
    const auto prev = at_peak - 1, next = at_peak + 1;
    if (next->slip) {
      res.peak_precision = (next->Dx - at_peak->Dx) *
                           std::abs((ratio(*at_peak) - ratio(*prev)) / (at_peak->Dx - prev->Dx));
    } else {
      double x0 = prev->Dx, x1 = at_peak->Dx, x2 = next->Dx;
      double y0 = ratio(*prev), y1 = ratio(*at_peak), y2 = ratio(*next);
      const auto vertex = [&](double& yv) {
        const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
        const double curv = (d12 - d01) / (x2 - x0);
        const double xv = 0.5 * (x0 + x1) - d01 / (2.0 * curv);
        yv = y1 + (xv - x1) * (d01 + curv * (xv - x0));  // Newton form through the 3 points
        return curv < 0.0 ? xv : x1;
      };
      double yv = y1;
      double xv = vertex(yv);
      res.peak_precision = std::max(0.0, yv - y1);
      // Parabolic steps converge fast on a smooth maximum but crawl on a kink (the explicit
      // model's Regime I peak sits within 0.02 d of the hollow, with a steep rise before it and
      // a slow fall after): as in Brent's method, a bracket that did not halve in two steps
      // is cut by a golden-section step into its larger side instead.
      double width_1ago = std::numeric_limits<double>::infinity(), width_2ago = width_1ago;
      for (int k = 0;
           k < 30 && options.protocol == Protocol::adaptive && x2 - x0 > 2.0 * options.min_step;
           ++k) {
        const double width = x2 - x0;
        const bool golden = width > 0.5 * width_2ago;
        width_2ago = width_1ago;
        width_1ago = width;
        constexpr double kGolden = 0.3819660112501051;  // (3 - sqrt 5) / 2
        xv = golden ? (x2 - x1 > x1 - x0 ? x1 + kGolden * (x2 - x1) : x1 - kGolden * (x1 - x0))
                    : vertex(yv);
        xv = std::clamp(xv, x0 + 0.25 * options.min_step, x2 - 0.25 * options.min_step);
        if (std::abs(xv - x1) < 0.25 * options.min_step) {
          xv = x1 + (x2 - x1 > x1 - x0 ? 0.5 : -0.5) * options.min_step;
        }
        if (stop_requested()) {
          stepping_end->partial.snapshots = std::move(res.snapshots);
          return interrupt(*stepping_end);
        }
        State probe = *peak;
        report(SlidePhase::peak, xv);
        may_abandon = true;
        const auto r = model.relax(probe, xv, nullptr);
        may_abandon = false;
        if (abandoned) {
          stepping_end->partial.snapshots = std::move(res.snapshots);
          return interrupt(*stepping_end, xv);
        }
        count(r);
        if (const std::string why = failure(r, probe, xv, peak->Dx); !why.empty()) {
          res.failed = true;
          res.stop_reason = "refining the peak: " + why;
          break;
        }
        const bool off_branch = model.slipped_sites(*peak, probe) > 0;
        const double y =
            off_branch ? -std::numeric_limits<double>::infinity() : probe.Fx / probe.Fz;
        if (y > y1) {
          (xv < x1 ? x2 : x0) = x1;
          (xv < x1 ? y2 : y0) = y1;
          x1 = xv;
          y1 = y;
          peak = probe;
        } else {
          (xv < x1 ? x0 : x2) = xv;
          (xv < x1 ? y0 : y2) = y;
        }
        if (!std::isfinite(y0) || !std::isfinite(y2)) break;
        vertex(yv);
        res.peak_precision = std::max(0.0, yv - y1);
        if (res.peak_precision < 1e-9 * std::abs(y1)) break;
      }
      res.mu = std::max(best, y1);
      res.peak_Dx = x1;
      res.Fz = peak->Fz;
    }
  }
  res.mu_over_alpha = res.mu / params.alpha;
  res.distance = state.Dx;
  res.kinetic = kinetic_friction(res.trace, state.Dx, d);
  res.kinetic_over_static = res.kinetic / res.mu;
  res.peak_snapshot = model.snapshot(*peak, "peak");
  if (control.frames) {
    control.frames->state(res.peak_snapshot);
  } else {
    res.snapshots.insert(res.snapshots.begin(), res.peak_snapshot);
  }
  res.gf_applications = gf_before + model.gf_applications() - gf_unused;
  res.wall_s = wall_before + elapsed();
  return res;
}

}  // namespace asperity::slide::detail
