// The sliding protocols of MODEL.md section 5 (slider.hpp: reference and adaptive, bisection of
// instabilities, slip detection, peak refinement, checkpoints), written once against a model of
// the contact so that the lateral force model (slider.cpp) and the explicit atomistic model
// (explicit/explicit_slide.cpp) slide through the same code. Pure functions over the trace (the
// stop rule, kinetic friction, the peak parabola) are in trace.hpp.
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
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "asperity/core/common/comm.hpp"
#include "asperity/core/common/validate.hpp"
#include "asperity/core/slide/trace.hpp"
#include "asperity/core/slide/types.hpp"

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
  // What friction is (types.hpp): Fx / Fz, or Fx / A where the contact carries no load.
  FrictionMeasure measure = FrictionMeasure::load;
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
    const int fast_iterations = st.pending->fast ? st.pending->fast->iterations : 0;
    if (fast_iterations < 0 || fast_iterations > kMaxCount ||
        st.pending->flow.iteration > kMaxCount) {
      reject("SlideState.pending iterations",
             std::to_string(fast_iterations) + " and " + std::to_string(st.pending->flow.iteration),
             "0 ... " + std::to_string(kMaxCount));
    }
    if (st.pending->frame_interval < 0)
      reject("SlideState.pending.frame_interval", std::to_string(st.pending->frame_interval),
             ">= 0");
  }
}

// One slide of a model (run_protocol below), split by what each part decides:
//   - start(): the state the stepping begins from (a resumed slide's, or the first relaxation);
//   - the stepper (step(), plan(), warm_start()): where the next step goes and how it is
//     relaxed; plan() holds the bisection of a bracketed instability (MODEL.md 5: the slip is
//     taken from the bracket's stable end, min_step wide) and the cycle probe;
//   - relax_step() and relax_slip(): the fast relaxation, and the slip minimiser's relaxation of
//     a slip the fast one would accept (pausable for checkpoints and stops); in creep the slip
//     minimiser first (flow_first(), take_fast_after_flow());
//   - accept(): the trace, the slip events' frames, the peak so far and the stop rule;
//   - the cycle replay (take_cycle(), replay()): a state equal to one a period d back repeats
//     the cycle, whose rows are carried on instead of being computed;
//   - refine_peak() and finish(): mu, its resolution and kinetic friction, from the pure
//     functions over the trace (trace.hpp).
// The object lives for one call of run_protocol: the model's heartbeat refers to it.
template <SlideModel Model>
class ProtocolRun {
 public:
  using State = SlideFields;

  ProtocolRun(Model& model, const ProtocolParams& params, const SlideOptions& options,
              const SlideControl& control, std::chrono::steady_clock::time_point t0)
      : model_(model),
        params_(params),
        options_(options),
        control_(control),
        t0_(t0),
        collect_(res_.snapshots),
        d_(params.d),
        automatic_(options.distance == 0.0),
        limit_(automatic_ ? (options.max_distance > 0.0 ? options.max_distance : params.default_cap)
                          : options.distance),
        replay_(comparable && options.replay_cycle && options.protocol == Protocol::adaptive),
        h_(options.protocol == Protocol::reference ? options.step : options.max_step) {}
  ProtocolRun(const ProtocolRun&) = delete;
  ProtocolRun& operator=(const ProtocolRun&) = delete;
  ~ProtocolRun() {
    if (heartbeat_slot_) *heartbeat_slot_ = nullptr;  // it refers to this object
  }

  SlideResult run() {
    // Of the earlier sessions of a resumed slide (counted in the start state).
    if (control_.start) {
      check_start(*control_.start, model_);
      // A distributed model keeps its rows of the start state's fields (which hold every row);
      // on one process the start state is used as it is, not copied.
      if constexpr (distributed_model) {
        if (spread()) {
          local_start_ = *control_.start;
          model_.localize(*local_start_);
        }
      }
      res_ = control_.start->partial;
      gf_before_ = res_.gf_applications;
      wall_before_ = res_.wall_s;
    }
    res_.block = model_.block_shape();
    res_.fft_grid = model_.fft_grid();
    sink_ = control_.frames ? control_.frames : &collect_;
    res_.Fz_continuum = params_.Fz_continuum;
    state_ = model_.initial();
    // The start state replaces the initial one: GF work the model spent building it (the
    // explicit model's Hertz start) was counted by the session that did use it.
    gf_unused_ = control_.start ? model_.gf_applications() : 0;
    install_heartbeat();
    start();
    last_checkpoint_ = std::chrono::steady_clock::now();
    while (!stopped_) {
      if (auto out = step()) return std::move(*out);
    }
    // The replay's window is of no use past the stepping (a resumed slide that had finished
    // stepping does not step again); its memory goes now, before the peak refinement.
    window_.clear();
    window_.shrink_to_fit();
    window_rows_.clear();
    if (auto out = refine_peak()) return std::move(*out);
    return finish();
  }

 private:
  // Only models that can compare states a period apart replay (the explicit model does not).
  static constexpr bool comparable = requires(const Model& m, const State& a) {
    m.period_mismatch(a, a);
  };
  // A model whose fields are spread over processes (the lateral force model over MPI ranks,
  // issue 26) says over which, and turns states between its rows and every row.
  static constexpr bool distributed_model = requires(Model & m, SlideState& st) {
    { m.comm() } -> std::convertible_to<const par::Comm&>;
    m.localize(st);
    m.globalize(st);
  };
  // Only models whose relax() takes a RelaxPausing can pause a slip relaxation.
  static constexpr bool pausable = requires(Model & m, State& s, std::vector<PathFrame>* frames,
                                            const minimize::MinimizerOptions* o, RelaxPausing* p) {
    m.relax(s, 0.0, frames, false, o, p);
  };
  // Fraction of the contact sites whose registry index changed in a slip worth a probe (seen:
  // 0.86 to 1.006 in Regime II, where edge sites catch up while sticking; mostly 0.001 to 0.03
  // in Regime III, with a few larger partial slips of 0.58 to 0.84).
  static constexpr double kSweptSlip = 0.5;

  // Where the next step goes: its tip position; whether it is a trial that is undone if it
  // slips (the adaptive protocol's steps and bisection); the window state it probes the cycle
  // against, if it is a probe.
  // closes_bracket: a step or bisection trial min_step wide (at most), whose slip would end the
  // bisection at once: it is not undone if it slips (may_undo false) but handed to the slip
  // minimiser, as the step to the bracket's end would be (plan()).
  struct Plan {
    double Dx = 0.0;
    bool may_undo = false;
    bool closes_bracket = false;
    std::optional<std::size_t> cycle_of;
  };

  double elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  }
  std::size_t gf_total(std::size_t model_gf) const { return gf_before_ + model_gf - gf_unused_; }
  // A stop request or a due checkpoint, decided by every process of a distributed model
  // together (each asks its own clock and signal flag; one that says yes decides for all).
  bool agree(bool local) const {
    if constexpr (distributed_model) {
      if (spread()) return model_.comm().any(local);
    }
    return local;
  }
  // Whether this slide's model runs over several processes.
  bool spread() const {
    if constexpr (distributed_model) {
      return model_.comm().distributed();
    } else {
      return false;
    }
  }
  bool stop_requested() const {
    return agree(control_.stop_requested && control_.stop_requested());
  }
  bool checkpoint_due() const {
    return agree(std::chrono::duration<double>(std::chrono::steady_clock::now() - last_checkpoint_)
                     .count() >= control_.checkpoint_every_s);
  }
  // Hands a state to SlideControl::checkpoint; a distributed model's fields are gathered first
  // (its checkpoint holds every row, so that it resumes on any number of processes), and every
  // process calls this together.
  void checkpoint(const SlideState& st) const {
    if (!control_.checkpoint) return;
    if constexpr (distributed_model) {
      if (spread()) {  // on one process the state is whole already: no copy
        SlideState whole = st;
        model_.globalize(whole);
        control_.checkpoint(whole);
        return;
      }
    }
    control_.checkpoint(st);
  }

  // Progress report: what starts now (or was just accepted), with the cost so far; a model that
  // can (one with a `heartbeat` slot) also reports while it relaxes, so that a relaxation of
  // many minutes (a slip through a large contact) shows what it is and that it runs.
  void report(SlidePhase phase, double target, int iteration = 0) {
    if (!control_.progress) return;
    if (iteration == 0) {
      relaxing_ = phase;
      relaxing_to_ = target;
    }
    // Before the first state (phase start) there is no friction to show.
    const bool have_state = phase != SlidePhase::start && denominator(state_) > 0.0;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double now = have_state ? ratio(state_) : nan;
    // The largest is never shown below the friction beside it: the peak refinement can take
    // back best_ to a runner-up up to 1e-4 below the last state (refine_peak).
    control_.progress(SlideProgressInfo{.phase = phase,
                                        .Dx = state_.Dx,
                                        .target_Dx = target,
                                        .limit = limit_,
                                        .slip_events = res_.slip_events,
                                        .steps = res_.steps,
                                        .replayed_steps = res_.replayed_steps,
                                        .gf_applications = gf_total(model_.gf_applications()),
                                        .wall_s = wall_before_ + elapsed(),
                                        .iteration = iteration,
                                        .measure = params_.measure,
                                        .friction = now,
                                        .peak_friction = have_state ? std::max(best_, now) : nan});
  }

  // A stop request is also polled from inside a relaxation of the stepping or of the peak
  // refinement (not the first one, before which there is no state to hand over): the
  // relaxation, of a copy of the state, is abandoned and the state it started from is handed
  // over, so that the resumed slide repeats it. A slip through a large contact relaxes for most
  // of an hour (R = 1700 d, a = 510 d: 12 854 iterations), which a stop must not wait for. The
  // slip minimiser's flow is paused instead (SlideState::pending), at its next accepted step.
  void install_heartbeat() {
    if constexpr (requires { model_.heartbeat = std::function<bool(int)>{}; }) {
      if (control_.progress || control_.stop_requested) {
        model_.heartbeat = [this](int iteration) {
          report(relaxing_, relaxing_to_, iteration);
          const bool stop = (may_abandon_ || may_pause_) && stop_requested();
          abandoned_ = may_abandon_ && stop;
          pause_requested_ = pause_requested_ || (may_pause_ && stop);
          return abandoned_;
        };
        heartbeat_slot_ = &model_.heartbeat;
      }
    }
  }

  // A relaxation the heartbeat may abandon for a stop request.
  minimize::MinimizeResult relax_abandonable(State& s, double Dx, std::vector<PathFrame>* frames,
                                             bool stop_on_slip,
                                             const minimize::MinimizerOptions* solver = nullptr) {
    may_abandon_ = true;
    auto r = solver ? model_.relax(s, Dx, frames, stop_on_slip, solver)
                    : model_.relax(s, Dx, frames, stop_on_slip);
    may_abandon_ = false;
    return r;
  }

  // A trace row of state s; replayed rows cost no iterations.
  void record(const State& s, int iterations, std::size_t gf, double max_force, bool slip,
              int sites, bool replayed) {
    res_.trace.push_back(TraceRow{s.Dx, s.Fx, s.Fz, s.energy, iterations, gf, max_force, slip,
                                  sites, replayed, s.area});
    res_.iterations += iterations;
  }
  void count(const minimize::MinimizeResult& r) {
    ++res_.minimizations;
    res_.gradient_evaluations += r.interface_evaluations;
    res_.filter_applications += r.filter_applications;
    res_.filtered = res_.filtered || r.filtered;
  }

  // Why a relaxation to Dx (from the state at `from`) cannot be accepted: the minimiser did not
  // converge, or the relaxed state has non-finite forces or energy. Empty if it can. The message
  // names the step and the parameters needed to reproduce it.
  std::string failure(const minimize::MinimizeResult& r, const State& s, double Dx, double from,
                      const minimize::MinimizerOptions* solver = nullptr) const {
    const minimize::MinimizerOptions& m = solver ? *solver : options_.minimizer;
    const char* what = nullptr;
    if (r.termination != Termination::converged) {
      what = "";
    } else if (!std::isfinite(s.Fx) || !std::isfinite(s.Fz) || !std::isfinite(s.energy) ||
               !(denominator(s) > 0.0)) {
      // Fz = 0 (a load that underflowed) would make mu = Fx / Fz NaN; A = 0 (no contact site)
      // tau_fric = Fx / A.
      what = params_.measure == FrictionMeasure::load
                 ? "non-finite force or energy, or no load, after "
                 : "non-finite force or energy, or no contact site, after ";
    } else {
      return {};
    }
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "%sminimizer %s at Dx = %.9g d (step %d, from Dx = %.9g d, step size %.3g d; "
                  "%d iterations, max force %.3g, energy %.9g; %s, tolerance %g, max "
                  "iterations %d)",
                  what, to_string(r.termination).c_str(), Dx, res_.steps + 1, from, Dx - from,
                  r.iterations, r.max_force, r.energy, minimize::to_string(m.method).c_str(),
                  m.force_tolerance, m.max_iterations);
    return buf;
  }

  // The friction ratio of a state (types.hpp, FrictionMeasure) and what it divides Fx by.
  double ratio(const State& s) const { return friction_ratio(s.Fx, s.Fz, s.area, params_.measure); }
  double denominator(const State& s) const {
    return params_.measure == FrictionMeasure::load ? s.Fz : s.area;
  }

  // The friction of a result from the largest friction ratio `peak` at the peak state `at`: mu
  // and mu / alpha where there is a load, and the friction stress at the peak's contact-site
  // area.
  void set_friction(SlideResult& out, double peak, const State& at) const {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    out.measure = params_.measure;
    out.Fz = at.Fz;
    out.area = at.area;
    if (params_.measure == FrictionMeasure::load) {
      out.mu = peak;
      out.mu_over_alpha = peak / params_.alpha;
      out.tau_fric = at.area > 0.0 ? peak * at.Fz / at.area : nan;
    } else {
      out.tau_fric = peak;
      out.mu = out.mu_over_alpha = nan;
    }
  }

  double mismatch(const State& later, const State& before) const {
    if constexpr (comparable) {
      return model_.period_mismatch(later, before);
    } else {
      return std::numeric_limits<double>::infinity();
    }
  }

  // The state the stepping begins from: a resumed slide's (its paused slip relaxation checked
  // against this slide's settings), or the first relaxation at Dx = 0.
  void start() {
    if (control_.start) {
      const SlideState& st = local_start_ ? *local_start_ : *control_.start;
      state_ = st.current;
      previous_ = st.previous;
      earlier_ = st.earlier;
      peak_ = st.peak;
      runner_up_ = st.runner_up;
      best_ = st.best;
      runner_up_ratio_ = st.runner_up_ratio;
      first_max_Dx_ = st.first_max_Dx;
      slip_at_ = st.slip_at;
      stopped_ = st.stepping_done;
      window_ = st.window;
      window_rows_ = st.window_rows;
      cycle_check_due_ = st.cycle_check_due;
      pending_ = st.pending;
      after_paused_checkpoint_ = pending_.has_value();  // it came from a paused checkpoint
      if (pending_) {
        const char* why =
            !pausable  ? "this model cannot continue"
            : stopped_ ? "a state past the stepping cannot have"
            : !options_.slip_minimizer || options_.slip_minimizer->method != minimize::Method::flow
                ? "only a flow as slip minimiser makes"
            : pending_->Dx > limit_ + 1e-12 ? "lies beyond the distance of this slide"
                                            : nullptr;
        if (why) {
          throw std::invalid_argument(
              std::string("slide: the start state holds a paused slip relaxation, which ") + why);
        }
      }
      return;
    }
    report(SlidePhase::start, 0.0);
    auto first = model_.relax(state_, 0.0, nullptr);
    count(first);
    res_.contact_sites = model_.contact_sites();
    record(state_, first.iterations, first.gf_applications, first.max_force, false, 0, false);
    if (replay_) {
      window_.push_back(state_);
      window_rows_.push_back(0);
    }
    best_ = ratio(state_);
    peak_ = state_;
    if (const std::string why = failure(first, state_, 0.0, 0.0); !why.empty()) {
      res_.failed = true;  // no good state yet to keep
      res_.stop_reason = why;
      stopped_ = true;
      return;
    }
    // The loaded contact before the slide: what exists without nucleation, e.g. the misfit
    // dislocations under a tip lattice out of registry (interface/tip_lattice.hpp). A resumed
    // slide has handed it over already.
    sink_->state(model_.snapshot(state_, "start"));
  }

  // The state at the top of the stepping loop (or after it), for checkpoints. Its cost is the
  // model's so far, or `at_top` (the counts before an abandoned relaxation, whose work the
  // resumed slide repeats: counted once, a resumed slide reports an uninterrupted one's GF
  // counts; its wall time differs by each session's set-up and by work lost after the last
  // checkpoint of a killed run).
  struct Cost {
    std::size_t model_gf = 0;
    double elapsed = 0.0;  // of this session (s)
  };
  SlideState capture(bool stepping_done, std::optional<Cost> at_top = {}) const {
    SlideState st{.current = state_,
                  .previous = previous_,
                  .earlier = earlier_,
                  .peak = *peak_,
                  .runner_up = runner_up_,
                  .best = best_,
                  .runner_up_ratio = runner_up_ratio_,
                  .first_max_Dx = first_max_Dx_,
                  .slip_at = slip_at_,
                  .stepping_done = stepping_done,
                  .window = window_,
                  .window_rows = window_rows_,
                  .cycle_check_due = cycle_check_due_,
                  .partial = res_,
                  // A paused slip not yet continued (a resumed slide stopped or checkpointed
                  // before its first step) is handed on: its work is in `res` already.
                  .pending = pending_};
    st.partial.gf_applications = gf_total(at_top ? at_top->model_gf : model_.gf_applications());
    st.partial.wall_s = wall_before_ + (at_top ? at_top->elapsed : elapsed());
    return st;
  }

  // Stop on request: hand the state over and return what is known so far.
  // `abandoned_to`: the target of a relaxation abandoned for the stop, if one was.
  // A state with a pending slip relaxation (st.pending) was paused within it instead.
  SlideResult interrupt(const SlideState& st,
                        double abandoned_to = std::numeric_limits<double>::quiet_NaN()) const {
    checkpoint(st);
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
    set_friction(out, st.best, st.peak);
    out.mu_is_lower_bound = true;  // the static peak is not established yet
    out.peak_Dx = st.peak.Dx;
    out.distance = st.current.Dx;
    out.kinetic = out.kinetic_over_static = std::numeric_limits<double>::quiet_NaN();
    return out;
  }

  // Slip events whose relaxation paths are recorded: 1, 1 + k, 1 + 2k, ...
  bool paths_of(int event) const {
    return options_.path_frame_every > 0 && options_.path_frame_slips > 0 && sink_->wants_paths() &&
           (event - 1) % options_.path_frame_slips == 0;
  }

  // The frames of slip event res_.slip_events: the states before and after, its relaxation
  // path (one Snapshot at a time: a path is held as displacements only, PathFrame), or for a
  // replayed slip the path of event `replay_of`, `periods` back.
  void slip_frames(const State& next, int sites, std::vector<PathFrame>& frames, int replay_of,
                   int periods) {
    const std::string label = slip_label(res_.slip_events);
    for (auto [fields, suffix] :
         {std::pair<const State*, const char*>{&state_, "_before"}, {&next, "_after"}}) {
      Snapshot frame = model_.snapshot(*fields, label + suffix);
      frame.slipped_sites = sites;
      frame.replay_of = replay_of;
      if (fields == &next) {
        frame.gf_applications = gf_total(model_.gf_applications());
        frame.wall_s = wall_before_ + elapsed();
      }
      sink_->state(frame);
    }
    for (PathFrame& frame : frames) {
      sink_->path_frame(model_.snapshot(frame.fields, label + "_path", frame.iteration));
      frame.fields = {};
    }
    if (replay_of > 0 && paths_of(res_.slip_events)) {
      sink_->replayed_path(slip_label(replay_of) + "_path", periods, d_, label + "_path");
    }
  }

  // The replay's window: the accepted states of the last period d and a step, with their trace
  // rows, so that a state one period after one of them can be compared.
  void push_window() {
    window_.push_back(state_);
    window_rows_.push_back(res_.trace.size() - 1);
    std::size_t drop = 0;
    while (drop < window_.size() && (window_[drop].Dx < state_.Dx - d_ - h_ - 1e-9 * d_ ||
                                     window_.size() - drop > kCycleWindow))
      ++drop;
    window_.erase(window_.begin(), window_.begin() + static_cast<std::ptrdiff_t>(drop));
    window_rows_.erase(window_rows_.begin(),
                       window_rows_.begin() + static_cast<std::ptrdiff_t>(drop));
  }

  // Takes the next state of the slide (computed, or replayed from the repeating cycle) into the
  // trace; true when the slide stops there.
  // `frames`: the relaxation path of a computed step; `replay_of`: the slip event whose path a
  // replayed slip repeats, `periods` on (0: none).
  bool accept(State&& next, int iterations, std::size_t gf, double max_force, bool slip, int sites,
              std::vector<PathFrame> frames, bool replayed, int replay_of = 0, int periods = 0) {
    if (slip) {
      ++res_.slip_events;
      slip_frames(next, sites, frames, replay_of, periods);
      // A slip that swept most of the contact (a Regime II loop, or several) may have brought
      // the state back to one of the last period: probe it. Not after the small slips of
      // Regime III (arrested loops; a few % of the sites each), where probes would be wasted.
      cycle_check_due_ =
          replay_ && !replayed &&
          static_cast<double>(sites) >= kSweptSlip * static_cast<double>(model_.contact_sites());
    }
    earlier_ = std::move(previous_);
    previous_ = std::move(state_);
    state_ = std::move(next);
    record(state_, iterations, gf, max_force, slip, sites, replayed);
    ++(replayed ? res_.replayed_steps : res_.steps);
    if (replay_ && !replayed) push_window();
    // A later maximum replaces the peak only if it is higher beyond the minimiser's noise: in
    // Regime I the trace repeats its first maximum a period later, and the first, which has
    // samples on both sides, is the one to refine.
    const double now = ratio(state_);
    if (now > best_ + 1e-6 * std::abs(best_)) {
      runner_up_ = std::move(peak_);
      runner_up_ratio_ = best_;
      best_ = now;
      peak_ = state_;
    }
    report(SlidePhase::accepted, state_.Dx);
    return stops_here();
  }

  // The automatic distance's stop rules, at the state just accepted.
  bool stops_here() {
    // Regime I: a smooth maximum (rise then fall, no slip yet).
    const std::size_t k = res_.trace.size();
    if (first_max_Dx_ < 0.0 && res_.slip_events == 0 && k >= 3 &&
        res_.trace[k - 2].Fx > res_.trace[k - 3].Fx &&
        res_.trace[k - 1].Fx < res_.trace[k - 2].Fx) {
      first_max_Dx_ = res_.trace[k - 2].Dx;
    }
    if (automatic_ && res_.slip_events >= options_.slips_to_stop &&
        peak_held(res_.trace, best_, ratio(state_), state_.Dx, d_, options_.slips_to_stop,
                  params_.measure)) {
      res_.stop_reason = "slip events reached";
      return true;
    }
    // The user's bound on the slips (a long Regime III run): after the automatic rule, so that a
    // peak that held at this slip is reported as established.
    if (options_.max_slips > 0 && res_.slip_events >= options_.max_slips) {
      res_.stop_reason = kStopSlipLimit;
      return true;
    }
    // Adaptive: the even steps start at most one step past the maximum, and the kinetic window
    // (the last period) must lie inside them.
    const double lead = options_.protocol == Protocol::adaptive ? h_ : 0.0;
    if (automatic_ && res_.slip_events == 0 && first_max_Dx_ >= 0.0 &&
        state_.Dx >= first_max_Dx_ + lead + d_ - 1e-12) {
      res_.stop_reason = "one period past the first maximum (no slip)";
      return true;
    }
    return false;
  }

  // The stepper: where the next step goes.
  Plan plan() {
    // Smooth sliding (a maximum without a slip, Regime I): the kinetic friction is the mean of a
    // near-sinusoid over the last period, which the trapezoid rule gets right only from evenly
    // spread samples: eight per period from the first maximum on.
    const double step =
        options_.protocol == Protocol::adaptive && first_max_Dx_ >= 0.0 && res_.slip_events == 0
            ? std::min(h_, 0.125 * d_)
            : grown_step();
    Plan p{.Dx = std::min(state_.Dx + step, limit_)};
    // Adaptive: the bisection. A bracket [state.Dx, slip_at] around a known instability is
    // halved until it is min_step wide; the slip is then taken from its stable end.
    if (options_.protocol == Protocol::adaptive) {
      const double gap = slip_at_ - state_.Dx;
      if (!std::isfinite(slip_at_)) {
        p.may_undo = true;
      } else if (!options_.within_min_step(gap)) {
        p.Dx = state_.Dx + 0.5 * gap;
        p.may_undo = true;
      } else {
        p.Dx = slip_at_;
      }
    }
    // Cycle replay: after a slip, a probe relaxes to one period d after the latest window state
    // within a step, to compare with it. A probe that does not find the cycle repeated (it
    // slipped, failed or differs) is dropped as if it had not been made: the slide goes on
    // with the step it would have taken, so a slide that never repeats (Regime III) follows the
    // same path as without the replay, at the probe's cost.
    // While the step still grows after the slip (slide.step_growth), a step that reaches no
    // window state's period keeps the probe due for the next one.
    if (replay_ && cycle_check_due_ && !std::isfinite(slip_at_)) {
      if (step >= h_) cycle_check_due_ = false;
      for (std::size_t i = window_.size(); i-- > 0;) {
        const double target = window_[i].Dx + d_;
        if (target <= p.Dx && target > state_.Dx + 1e-9 * d_) {
          p.Dx = target;
          p.cycle_of = i;
          cycle_check_due_ = false;
          break;
        }
      }
    }
    // A trial at most min_step from the stable state: if it slipped, slip_at_ would be its Dx
    // and the bracket would be closed, so the next step would relax the same step again, from
    // the same state with the same warm start, only to find it slip again before the slip
    // minimiser takes it (at a = 300 d, R = 800 d, about 1 000 GF of each small slip's 3 000 to
    // 16 000). With a slip minimiser that step is taken now: the same relaxations in the same
    // order, less the repeated one. (Without one the slip step relaxes to convergence where the
    // trial stops at the slip, so there is nothing to share.)
    if (options_.protocol == Protocol::adaptive && options_.slip_minimizer && p.may_undo &&
        !p.cycle_of && options_.within_min_step(p.Dx - state_.Dx)) {
      p.may_undo = false;
      p.closes_bracket = true;
    }
    return p;
  }

  // The step of the adaptive protocol: max_step, or with slide.step_growth, after a slip event,
  // min_step times the growth factor to the power of the steps accepted since that slip (capped
  // at max_step). It follows from the trace alone, so a resumed slide takes the same steps.
  double grown_step() const {
    const double g = options_.step_growth;
    if (options_.protocol != Protocol::adaptive || !(g > 1.0) || res_.slip_events == 0) return h_;
    std::size_t since = 0;
    for (std::size_t i = res_.trace.size(); i-- > 0 && !res_.trace[i].slip;)
      ++since;
    double step = options_.min_step;
    for (std::size_t k = 0; k < since && step < h_; ++k)
      step *= g;
    return std::min(step, h_);
  }

  // Warm start on a smooth branch: extrapolate the force field in Dx through the last two or
  // three states of the branch (Lagrange; u follows as G f). After a slip the branch is new.
  void warm_start(State& trial, double Dx) {
    const std::size_t rows = res_.trace.size();
    const bool on_branch1 = previous_ && !res_.trace.back().slip && state_.Dx > previous_->Dx;
    const bool on_branch2 = on_branch1 && earlier_ && rows >= 3 && !res_.trace[rows - 2].slip &&
                            previous_->Dx > earlier_->Dx;
    if (!options_.extrapolate || !on_branch1) return;
    State p1 = *previous_;
    model_.align(p1, trial);
    if (on_branch2) {
      State p2 = *earlier_;
      model_.align(p2, trial);
      const double x0 = p2.Dx, x1 = p1.Dx, x2 = state_.Dx;
      const double l0 = (Dx - x1) * (Dx - x2) / ((x0 - x1) * (x0 - x2));
      const double l1 = (Dx - x0) * (Dx - x2) / ((x1 - x0) * (x1 - x2));
      const double l2 = (Dx - x0) * (Dx - x1) / ((x2 - x0) * (x2 - x1));
      for (std::size_t i = 0; i < trial.f.size(); ++i) {
        trial.f[i] = l0 * p2.f[i] + l1 * p1.f[i] + l2 * state_.f[i];
      }
      trial.h = l0 * p2.h + l1 * p1.h + l2 * state_.h;  // explicit model: tip height
    } else {
      const double w = (Dx - state_.Dx) / (state_.Dx - p1.Dx);
      for (std::size_t i = 0; i < trial.f.size(); ++i)
        trial.f[i] += w * (state_.f[i] - p1.f[i]);
      trial.h += w * (state_.h - p1.h);
    }
  }

  // Checkpoints at the top of the stepping loop, when one is due or the last one was inside a
  // paused slip flow (SlideControl: the state between steps follows it). Not while a resumed
  // slide's paused flow is still to be continued (pending_): that state is the paused one again.
  void checkpoint_if_due() {
    if (!control_.checkpoint) return;
    if ((after_paused_checkpoint_ && !pending_) || checkpoint_due()) {
      checkpoint(capture(false));
      last_checkpoint_ = std::chrono::steady_clock::now();
      if (!pending_) after_paused_checkpoint_ = false;
    }
  }

  // One step of the stepping loop: a result if the slide was interrupted within it; stopped_
  // when the stepping ends.
  std::optional<SlideResult> step() {
    if (stop_requested()) return interrupt(capture(false));
    if (state_.Dx >= limit_ - 1e-12) {
      res_.stop_reason = automatic_ ? std::string(kStopDistanceCap) : "distance reached";
      stopped_ = true;
      return std::nullopt;
    }
    // After the distance test: the last checkpoint of a slide stopped by its cap is then from
    // before the step that was cut to land on the cap, so that a longer cap continuing it takes
    // the steps a slide with that cap takes from the start (friction_sweep keeps it).
    checkpoint_if_due();
    // The slip relaxation paused in the slide this one continues: it belongs to this step, and
    // the relaxation that called the step a slip is not repeated.
    std::optional<PendingSlip> resuming = std::exchange(pending_, std::nullopt);
    const Plan p = resuming ? resumed_plan(*resuming) : plan();
    State trial = state_;
    warm_start(trial, p.Dx);
    std::vector<PathFrame> frames;
    // Only a relaxation that will not be undone can become a slip event with a path (the next
    // one, if it slips).
    const bool want_frames = !p.may_undo && paths_of(res_.slip_events + 1);
    if (resuming) check_resuming(*resuming, p, want_frames);
    // A step that goes to the flow first is reported as the slip relaxation it starts with.
    if (!flow_first(p, resuming)) report(step_phase(p), p.Dx);
    minimize::MinimizeResult r;
    const minimize::MinimizerOptions* solver = &options_.minimizer;  // the one whose result is r
    if (auto out = relax_step(trial, p, want_frames, frames, resuming, r, solver)) return out;
    stopped_ = take_step(std::move(trial), p, r, solver, std::move(frames));
    return std::nullopt;
  }

  SlidePhase step_phase(const Plan& p) const {
    return p.cycle_of                       ? SlidePhase::probe
           : !std::isfinite(slip_at_)       ? SlidePhase::step
           : p.may_undo || p.closes_bracket ? SlidePhase::bisection
                                            : SlidePhase::slip;
  }

  // Creep (SlideOptions::flow_first_after): the last flow_first_after accepted steps were all
  // slips, the last of them computed (not replayed), as when Regime III's arrested loops move on
  // at every push (R = 800 d, a = 300 d: 19 slips in a row at 0.01 d steps after the first, then
  // one stable step, then slips again). The next step then most likely slips too. After a slip
  // there is no warm start (warm_start()), so the fast minimiser and the flow would both start
  // from the state moved to Dx.
  bool creeping() const {
    const auto& t = res_.trace;
    const auto n = static_cast<std::size_t>(options_.flow_first_after);
    if (n == 0 || t.size() < n || t.back().replayed) return false;
    return std::all_of(t.end() - static_cast<std::ptrdiff_t>(n), t.end(),
                       [](const TraceRow& row) { return row.slip; });
  }

  // Whether the step goes to the slip minimiser before the fast one: a step that would be handed
  // to it if it slipped (a closing trial, min_step wide at most) in creep; a resumed one if its
  // pause came from such a step (it holds no fast relaxation).
  bool flow_first(const Plan& p, const std::optional<PendingSlip>& resuming) const {
    if (resuming) return !resuming->fast.has_value();
    return options_.slip_minimizer && p.closes_bracket && !p.cycle_of && creeping();
  }

  // The step a paused slip relaxation belongs to. A pause of the flow after the fast minimiser
  // saw the step slip carries the closed bracket (slip_at_ = its Dx), so plan() lands on it
  // under any settings that keep it a closing step. A flow-first flow's pause (no fast result)
  // closed none, so plan() finds its Dx again only under the settings it was made with. A slide
  // adopted with others (a longer distance after a step cut to the old one, another
  // step_growth or max_step; docs/reliability.md) continues that step as well, if it is a
  // closing step under them (within min_step of the state, not past the limit); check_resuming()
  // refuses the rest.
  Plan resumed_plan(const PendingSlip& resuming) {
    const bool due = cycle_check_due_;
    const Plan p = plan();
    const double gap = resuming.Dx - state_.Dx;
    if (resuming.fast || p.Dx == resuming.Dx || !(gap > 0.0) || !options_.within_min_step(gap) ||
        resuming.Dx > limit_)
      return p;
    cycle_check_due_ = due;  // plan() may have taken a due probe for its own step
    return Plan{.Dx = resuming.Dx, .closes_bracket = true};
  }

  void check_resuming(const PendingSlip& resuming, const Plan& p, bool want_frames) const {
    if (resuming.Dx == p.Dx && !p.may_undo && !p.cycle_of &&
        (want_frames || resuming.frames.empty()))
      return;
    char buf[240];
    std::snprintf(buf, sizeof buf,
                  "slide: the start state's paused slip relaxation goes to Dx = %.9g d, but "
                  "the step from it to Dx = %.9g d is %s",
                  resuming.Dx, p.Dx,
                  resuming.Dx != p.Dx || p.may_undo || p.cycle_of
                      ? "not a slip step"
                      : "one whose path is not recorded (the pause has path frames)");
    throw std::invalid_argument(buf);
  }

  // Relaxes the step: the fast minimiser, then, for a slip it would accept, the slip minimiser
  // (SlideOptions::slip_minimizer) from the state moved to Dx without the warm start: where the
  // state goes after an instability, and whether the step is one, is the flow's to say
  // (MODEL.md 5). Trials that are undone when they slip (the bisection) only place the bracket;
  // the step that ends it is the one verified. If the slip minimiser finds it stable, it is
  // accepted as a stable state (a premature slip avoided) and the stepping goes on from there.
  // Probes of the cycle are dropped when they slip, so they are left alone.
  // `r` and `solver`: the relaxation whose verdict stands and its minimiser; a result if the
  // slide was interrupted.
  std::optional<SlideResult> relax_step(State& trial, const Plan& p, bool want_frames,
                                        std::vector<PathFrame>& frames,
                                        std::optional<PendingSlip>& resuming,
                                        minimize::MinimizeResult& r,
                                        const minimize::MinimizerOptions*& solver) {
    const Cost at_top{.model_gf = model_.gf_applications(), .elapsed = elapsed()};
    // With a slip minimiser, a step that the fast solver sees slip for certain (a site moved by
    // 3/4 d in the LFM, d/2 in the explicit model, as in the bisection) is handed to the slip
    // minimiser at once: relaxing the slip further would only be thrown away. (Before, it ran to
    // convergence: 5 908 iterations, about 25 minutes, before each flow at a = 430 d, R = 1700
    // d.) A relaxation that would have moved a site that far and then come back (an overshoot)
    // is thereby also the flow's to decide, which is the reference's verdict (MODEL.md 5).
    const bool slip_goes_to_flow = options_.slip_minimizer && !p.cycle_of && !p.may_undo;
    const bool first = flow_first(p, resuming);
    if (resuming) {
      if (resuming->fast) r = *resuming->fast;
    } else if (!first) {
      // Its path frames would be thrown away: a slip is the flow's (and its path with it), and
      // a step that does not slip shows none. Recording them cost a copy of the block's
      // displacement every path_frame_every iterations.
      r = relax_abandonable(trial, p.Dx, want_frames && !slip_goes_to_flow ? &frames : nullptr,
                            p.may_undo || slip_goes_to_flow);
      if (abandoned_) {
        // plan() took the due probe of the cycle for this relaxation: the resumed slide is to
        // make it again (without, it would never probe, and its path would leave the
        // uninterrupted one's).
        SlideState st = capture(false, at_top);
        if (p.cycle_of) st.cycle_check_due = true;
        return interrupt(st, p.Dx);
      }
    }
    if (first || resuming || (slip_goes_to_flow && fast_slips(r, trial, p.Dx))) {
      std::optional<minimize::MinimizeResult> fast;
      if (!first) fast.emplace(r);
      trial = state_;
      frames.clear();
      // The bracket the slipped trial closes, as a trial undone at its slip would have left it
      // (a checkpoint of the paused flow carries it, and a stable verdict of the flow clears it).
      // A flow-first step has no trial yet: its bracket stays as it was until one slips.
      if (p.closes_bracket && !first) slip_at_ = p.Dx;
      report(SlidePhase::slip, p.Dx);
      if (auto out = relax_slip(trial, p.Dx, want_frames, frames, resuming, fast, r)) return out;
      // Counted only now: an abandoned step is repeated, both relaxations, by a resumed slide.
      if (abandoned_) return interrupt(capture(false, at_top), p.Dx);
      if (first) {
        if (!converged_slip(r, trial, p.Dx, &*options_.slip_minimizer)) {
          take_fast_after_flow(p, trial, frames, r, solver);
          return std::nullopt;
        }
        ++res_.flow_first_steps;
      }
      if (fast) count(*fast);
      solver = &*options_.slip_minimizer;
      ++res_.slip_relaxations;
      // The step's row carries the cost of both relaxations.
      if (fast) {
        r.iterations += fast->iterations;
        r.gf_applications += fast->gf_applications;
      }
    }
    count(r);
    return std::nullopt;
  }

  // Whether the fast minimiser's relaxation r of a step to `trial` calls it a slip: stopped at
  // a site moved by 3/4 d, or converged with a site's registry changed.
  bool fast_slips(const minimize::MinimizeResult& r, const State& trial, double Dx) const {
    return r.termination == Termination::interrupted || converged_slip(r, trial, Dx);
  }
  // Whether a relaxation r (by `solver`, the fast minimiser if none) to `trial` converged to a
  // state with a site's registry changed.
  bool converged_slip(const minimize::MinimizeResult& r, const State& trial, double Dx,
                      const minimize::MinimizerOptions* solver = nullptr) const {
    return failure(r, trial, Dx, state_.Dx, solver).empty() &&
           model_.slipped_sites(state_, trial) > 0;
  }

  // A flow-first step the flow found stable (or could not relax): the step is relaxed by the
  // fast minimiser from its warm start (made again as step() makes it: state_ and the branch
  // are unchanged since, and after a slip there is none), as it would have been without
  // flow_first_after, and the verdict is the one that step would have had: the fast
  // minimiser's end state if it does not slip; the flow's (already made, from the same state as
  // it would have been) if it does.
  // `flow` and `flow_r` hold the flow's end state and result; on return `trial`, `r` and
  // `solver` are the step's.
  void take_fast_after_flow(const Plan& p, State& trial, std::vector<PathFrame>& frames,
                            minimize::MinimizeResult& r,
                            const minimize::MinimizerOptions*& solver) {
    State flow = std::move(trial);
    const minimize::MinimizeResult flow_r = r;
    trial = state_;
    warm_start(trial, p.Dx);
    report(step_phase(p), p.Dx);
    // Not abandoned for a stop request, unlike the fast relaxation of other steps: the flow
    // before it (thousands of GF applications at R = 800 d) would be thrown away with it, and
    // the state handed over could not say that the flow's part of the cost was already counted
    // (a flow resumed from a pause has its earlier part in the slide's counts). The stop waits
    // for this relaxation, which ends at a site moved by 3/4 d or converges (105 GF
    // applications for a stable step at R = 800 d, a = 300 d, and about 700 to 1 900 for a
    // slipping one), and is seen at the next step.
    const minimize::MinimizeResult fast = model_.relax(trial, p.Dx, nullptr, true);
    ++res_.flow_first_steps;
    ++res_.flow_first_stable;
    count(fast);
    if (fast_slips(fast, trial, p.Dx)) {
      // What the step without flow_first_after does: the slipped trial closes the bracket and
      // the slip goes to the flow, whose verdict (this one: stable, or its failure) and end
      // state stand.
      if (p.closes_bracket) slip_at_ = p.Dx;
      trial = std::move(flow);
      r = flow_r;
      solver = &*options_.slip_minimizer;
      ++res_.slip_relaxations;
      r.iterations += fast.iterations;
      r.gf_applications += fast.gf_applications;
      count(flow_r);
      return;
    }
    // The fast minimiser's stable state, as without flow_first_after: no path frames; the row
    // carries the flow's cost too. If the fast minimiser failed, the slide stops with its
    // failure, whose message names its iterations alone.
    frames.clear();
    count(flow_r);
    r = fast;
    solver = &options_.minimizer;
    if (!failure(fast, trial, p.Dx, state_.Dx).empty()) return;
    r.iterations += flow_r.iterations;
    r.gf_applications += flow_r.gf_applications;
  }

  // The slip minimiser's relaxation to Dx from trial (the state before the step). The flow
  // pauses (where the model can) rather than being abandoned: for a checkpoint when one is due
  // (not with checkpoint_every_s = 0, which would copy the state at every step of the flow),
  // and for a stop request, seen by the heartbeat. A result if it paused for a stop.
  std::optional<SlideResult> relax_slip(State& trial, double Dx, bool want_frames,
                                        std::vector<PathFrame>& frames,
                                        std::optional<PendingSlip>& resuming,
                                        const std::optional<minimize::MinimizeResult>& fast,
                                        minimize::MinimizeResult& r) {
    if constexpr (pausable) {
      if (options_.slip_minimizer->method == minimize::Method::flow) {
        std::optional<SlideState> paused;
        RelaxPausing pausing;
        if (resuming) {
          frames = std::move(resuming->frames);
          pausing.from = &resuming->flow;
          pausing.frame_interval = resuming->frame_interval;
        }
        pausing.pauses.due = [&](int) {
          if (pause_requested_) return true;
          if (!control_.checkpoint || !(control_.checkpoint_every_s > 0.0)) return false;
          return checkpoint_due();
        };
        pausing.pauses.pause = [&](const minimize::FlowPause& at) {
          SlideState st = capture(false);
          st.pending = PendingSlip{.Dx = Dx,
                                   .fast = fast,
                                   .flow = at,
                                   .frames = frames,
                                   .frame_interval = pausing.frame_interval};
          if (pause_requested_) {
            paused = std::move(st);
            return true;
          }
          checkpoint(st);
          last_checkpoint_ = std::chrono::steady_clock::now();
          after_paused_checkpoint_ = true;
          return false;
        };
        may_pause_ = true;
        r = model_.relax(trial, Dx, want_frames ? &frames : nullptr, false,
                         &*options_.slip_minimizer, &pausing);
        may_pause_ = false;
        if (paused) return interrupt(*paused);
        return std::nullopt;
      }
    }
    r = relax_abandonable(trial, Dx, want_frames ? &frames : nullptr, false,
                          &*options_.slip_minimizer);
    return std::nullopt;
  }

  // The verdict on a relaxed step: dropped (a probe that did not find the cycle, a trial that
  // slipped and narrows the bracket), failed, or accepted, and then perhaps the start of a
  // replayed cycle. True when the stepping ends.
  bool take_step(State&& trial, const Plan& p, const minimize::MinimizeResult& r,
                 const minimize::MinimizerOptions* solver, std::vector<PathFrame>&& frames) {
    // A probe that failed or slipped did not find the cycle (nor one that differs, below).
    if (p.cycle_of && !failure(r, trial, p.Dx, state_.Dx).empty()) return false;
    if (p.may_undo && r.termination == Termination::interrupted) {
      slip_at_ = p.Dx;  // slipped: bisect towards the instability
      return false;
    }
    if (const std::string why = failure(r, trial, p.Dx, state_.Dx, solver); !why.empty()) {
      // The trial is dropped; the last accepted state is kept as a checkpoint (resumable) and
      // as snapshot "last_good".
      checkpoint(capture(false));
      res_.failed = true;
      res_.stop_reason = why;
      sink_->state(model_.snapshot(state_, "last_good"));
      return true;
    }
    const int sites = model_.slipped_sites(state_, trial);
    const bool slip = sites > 0;
    if (p.cycle_of && slip) return false;
    if (slip && p.may_undo) {
      slip_at_ = p.Dx;
      return false;
    }
    // After a slip the bracket is used up; a stable state at the bracket's end means the
    // instability lies further on (a trial from further back had slipped).
    if (slip || p.Dx >= slip_at_) slip_at_ = std::numeric_limits<double>::infinity();
    // The state one period after a window state: if they are equal the cycle repeats, and the
    // period from the matched state to this one (the states after it, and this one), carried on
    // by whole periods, is the rest of the slide.
    const double cycle_mismatch = p.cycle_of ? mismatch(trial, window_[*p.cycle_of])
                                             : std::numeric_limits<double>::infinity();
    if (p.cycle_of && !(cycle_mismatch <= options_.cycle_tolerance)) return false;
    std::optional<Cycle> cycle;
    if (p.cycle_of) cycle = take_cycle(*p.cycle_of, trial);
    if (accept(std::move(trial), r.iterations, r.gf_applications, r.max_force, slip, sites,
               std::move(frames), false)) {
      return true;
    }
    if (!cycle) return false;
    cycle->rows.push_back(res_.trace.back());
    cycle->slip_event.push_back(0);
    return replay(*cycle, cycle_mismatch);
  }

  // A period of the slide that repeats: its states (after the matched window state, up to the
  // probe), their trace rows and the slip event number of each row (0: none).
  struct Cycle {
    std::vector<State> states;
    std::vector<TraceRow> rows;
    std::vector<int> slip_event;
  };

  // The window states after the matched one, and the probe: the cycle. Replayed states are not
  // kept in the window: the cycle holds them.
  Cycle take_cycle(std::size_t matched, const State& probe) {
    Cycle c;
    for (std::size_t e = matched + 1; e < window_.size(); ++e) {
      const std::size_t row = window_rows_[e];
      c.states.push_back(std::move(window_[e]));
      c.rows.push_back(res_.trace[row]);
      c.slip_event.push_back(
          res_.trace[row].slip
              ? static_cast<int>(std::count_if(
                    res_.trace.begin(), res_.trace.begin() + static_cast<std::ptrdiff_t>(row) + 1,
                    [](const TraceRow& t) { return t.slip; }))
              : 0);
    }
    c.states.push_back(probe);
    window_.clear();
    window_rows_.clear();
    return c;
  }

  // The cycle carried on by whole periods until the slide stops or reaches its limit (past
  // which the computed steps take over). True when the slide stops.
  bool replay(const Cycle& cycle, double cycle_mismatch) {
    for (int k = 1;; ++k) {
      for (std::size_t e = 0; e < cycle.states.size(); ++e) {
        State next = cycle.states[e];
        next.Dx += k * d_;
        next.shift += k;
        if (next.Dx > limit_ + 1e-12) return false;
        if (res_.cycle_verified_at < 0.0) {
          res_.cycle_verified_at = state_.Dx;
          res_.cycle_mismatch = cycle_mismatch;
        }
        // A replayed slip's relaxation path is the computed one's, carried on by k periods.
        const TraceRow& row = cycle.rows[e];
        if (accept(std::move(next), 0, 0, row.max_force, row.slip, row.slipped_sites, {}, true,
                   cycle.slip_event[e], k)) {
          return true;
        }
      }
    }
  }

  // mu and its resolution. Before a slip the peak is the last stable state: the instability
  // lies within one step after it, and mu is resolved to that step times the slope. A smooth
  // maximum (Regime I) is refined, in the adaptive protocol, by parabolic search on Dx in the
  // bracket of its neighbours (each point relaxed from the peak state); the reference protocol
  // keeps the classic sampled maximum, and reports the parabola's excess as its precision.
  // A maximum at the very end of the trace cannot be refined; if it only repeats an earlier one
  // within the minimiser's noise (Regime I a period later; 1e-6 relative is seen), the earlier
  // one, which has samples on both sides, is the peak.
  // (Not when the runner-up is the sample just before: that is a ramp, cut off by the distance.)
  // A stop requested during the refinement returns the state after the stepping: a resumed
  // slide redoes the refinement from it. A result if the slide was interrupted.
  std::optional<SlideResult> refine_peak() {
    // (Without the snapshots, which can be large and which the refinement leaves alone: they are
    // added back if the state is used.)
    if (control_.stop_requested) {
      std::vector<Snapshot> snapshots = std::move(res_.snapshots);
      res_.snapshots.clear();
      stepping_end_ = capture(true);
      res_.snapshots = std::move(snapshots);
    }
    const std::size_t n_rows = res_.trace.size();
    if (runner_up_ && n_rows >= 2 && peak_->Dx == res_.trace.back().Dx &&
        runner_up_->Dx < res_.trace[n_rows - 2].Dx && best_ <= runner_up_ratio_ * (1.0 + 1e-4)) {
      peak_ = std::move(runner_up_);
      best_ = runner_up_ratio_;
    }
    // Still rising at the last sample (cap or a fixed distance hit on the loading ramp): the
    // static peak lies further on, mu is only a lower bound.
    // So is any peak when the automatic cap stopped a slide with slips: had the peak held, the
    // slide would have stopped at a slip before the cap (Regime III still hardening).
    // So is a peak of a slide stopped by SlideOptions::max_slips before the peak had held.
    res_.mu_is_lower_bound =
        peak_->Dx == res_.trace.back().Dx ||
        (automatic_ && res_.slip_events > 0 && res_.stop_reason == kStopDistanceCap) ||
        res_.stop_reason == kStopSlipLimit;
    peak_value_ = best_;
    res_.peak_Dx = peak_->Dx;
    const auto at_peak = std::find_if(res_.trace.begin(), res_.trace.end(),
                                      [&](const TraceRow& row) { return row.Dx == peak_->Dx; });
    if (at_peak == res_.trace.begin() || at_peak == res_.trace.end() ||
        at_peak + 1 == res_.trace.end())
      return std::nullopt;
    const auto prev = at_peak - 1, next = at_peak + 1;
    if (next->slip) {
      res_.peak_precision = peak_precision_before_slip(*prev, *at_peak, *next, params_.measure);
      return std::nullopt;
    }
    const auto y = [&](const TraceRow& row) { return ratio_of(row, params_.measure); };
    PeakBracket b{prev->Dx, at_peak->Dx, next->Dx, y(*prev), y(*at_peak), y(*next)};
    return search_peak(b);
  }

  // Parabolic steps converge fast on a smooth maximum but crawl on a kink (the explicit model's
  // Regime I peak sits within 0.02 d of the hollow, with a steep rise before it and a slow fall
  // after): as in Brent's method, a bracket that did not halve in two steps is cut by a
  // golden-section step into its larger side instead.
  std::optional<SlideResult> search_peak(PeakBracket& b) {
    double yv = b.y1;
    double xv = b.vertex(yv);
    res_.peak_precision = std::max(0.0, yv - b.y1);
    double width_1ago = std::numeric_limits<double>::infinity(), width_2ago = width_1ago;
    const double min_step = options_.min_step;
    for (int k = 0;
         k < 30 && options_.protocol == Protocol::adaptive && b.x2 - b.x0 > 2.0 * min_step; ++k) {
      const double width = b.x2 - b.x0;
      const bool golden = width > 0.5 * width_2ago;
      width_2ago = width_1ago;
      width_1ago = width;
      constexpr double kGolden = 0.3819660112501051;  // (3 - sqrt 5) / 2
      xv = golden ? (b.x2 - b.x1 > b.x1 - b.x0 ? b.x1 + kGolden * (b.x2 - b.x1)
                                               : b.x1 - kGolden * (b.x1 - b.x0))
                  : b.vertex(yv);
      xv = std::clamp(xv, b.x0 + 0.25 * min_step, b.x2 - 0.25 * min_step);
      if (std::abs(xv - b.x1) < 0.25 * min_step) {
        xv = b.x1 + (b.x2 - b.x1 > b.x1 - b.x0 ? 0.5 : -0.5) * min_step;
      }
      if (stop_requested()) {
        stepping_end_->partial.snapshots = std::move(res_.snapshots);
        return interrupt(*stepping_end_);
      }
      State probe = *peak_;
      report(SlidePhase::peak, xv);
      const auto r = relax_abandonable(probe, xv, nullptr, false);
      if (abandoned_) {
        stepping_end_->partial.snapshots = std::move(res_.snapshots);
        return interrupt(*stepping_end_, xv);
      }
      count(r);
      if (const std::string why = failure(r, probe, xv, peak_->Dx); !why.empty()) {
        res_.failed = true;
        res_.stop_reason = "refining the peak: " + why;
        break;
      }
      const bool off_branch = model_.slipped_sites(*peak_, probe) > 0;
      const double y = off_branch ? -std::numeric_limits<double>::infinity() : ratio(probe);
      if (y > b.y1) {
        (xv < b.x1 ? b.x2 : b.x0) = b.x1;
        (xv < b.x1 ? b.y2 : b.y0) = b.y1;
        b.x1 = xv;
        b.y1 = y;
        peak_ = probe;
      } else {
        (xv < b.x1 ? b.x0 : b.x2) = xv;
        (xv < b.x1 ? b.y0 : b.y2) = y;
      }
      if (!std::isfinite(b.y0) || !std::isfinite(b.y2)) break;
      b.vertex(yv);
      res_.peak_precision = std::max(0.0, yv - b.y1);
      if (res_.peak_precision < 1e-9 * std::abs(b.y1)) break;
    }
    peak_value_ = std::max(best_, b.y1);
    res_.peak_Dx = b.x1;
    return std::nullopt;
  }

  // The result: mu / alpha (or tau_fric), kinetic friction (trace.hpp), the peak's frame and the
  // cost.
  SlideResult finish() {
    set_friction(res_, peak_value_, *peak_);
    res_.distance = state_.Dx;
    res_.kinetic = kinetic_friction(res_.trace, state_.Dx, d_, params_.measure);
    res_.kinetic_over_static = res_.kinetic / peak_value_;
    res_.peak_snapshot = model_.snapshot(*peak_, "peak");
    if (control_.frames) {
      control_.frames->state(res_.peak_snapshot);
    } else {
      res_.snapshots.insert(res_.snapshots.begin(), res_.peak_snapshot);
    }
    res_.gf_applications = gf_total(model_.gf_applications());
    res_.wall_s = wall_before_ + elapsed();
    return std::move(res_);
  }

  Model& model_;
  const ProtocolParams& params_;
  const SlideOptions& options_;
  const SlideControl& control_;
  std::chrono::steady_clock::time_point t0_;
  SlideResult res_;
  CollectFrames collect_;  // the sink without SlideControl::frames: res_.snapshots
  FrameSink* sink_ = nullptr;
  const double d_;
  const bool automatic_;
  const double limit_;
  const bool replay_;  // SlideOptions::replay_cycle, for a model that can compare states
  const double h_;     // the step: reference step or adaptive max_step (d)
  std::size_t gf_before_ = 0;
  double wall_before_ = 0.0;
  std::size_t gf_unused_ = 0;
  State state_;
  std::optional<State> peak_, previous_, earlier_, runner_up_;
  double runner_up_ratio_ = -std::numeric_limits<double>::infinity();
  double best_ = 0.0;
  double peak_value_ = 0.0;     // the peak's friction ratio, refined (refine_peak, search_peak)
  double first_max_Dx_ = -1.0;  // Regime I: first maximum of Fx without a slip
  double slip_at_ = std::numeric_limits<double>::infinity();  // bisection: the slipping end
  bool stopped_ = false;
  std::vector<State> window_;  // the cycle replay's window (push_window)
  std::vector<std::size_t> window_rows_;
  bool cycle_check_due_ = false;
  // A slip relaxation paused in the slide this one continues.
  std::optional<PendingSlip> pending_;
  std::optional<SlideState> local_start_;   // a distributed model's rows of the start state
  std::optional<SlideState> stepping_end_;  // refine_peak(): the state a stop hands over
  std::chrono::steady_clock::time_point last_checkpoint_;
  bool after_paused_checkpoint_ = false;  // the last checkpoint was inside a paused slip flow
  // The heartbeat's view: the relaxation running, and what a stop request does within it.
  SlidePhase relaxing_ = SlidePhase::start;
  double relaxing_to_ = 0.0;
  bool may_abandon_ = false;
  bool abandoned_ = false;
  bool may_pause_ = false;
  bool pause_requested_ = false;
  std::function<bool(int)>* heartbeat_slot_ = nullptr;
};

template <SlideModel Model>
SlideResult run_protocol(Model& model, const ProtocolParams& params, const SlideOptions& options,
                         const SlideControl& control, std::chrono::steady_clock::time_point t0) {
  ProtocolRun<Model> run(model, params, options, control, t0);
  return run.run();
}

}  // namespace asperity::slide::detail
