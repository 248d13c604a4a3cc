// Model-neutral types of a quasi-static slide (MODEL.md section 5): its options, trace, result,
// state (checkpoints), progress reports and control. Both contact models slide with them
// through run_protocol (protocol.hpp): the lateral force model (slider.hpp) and the explicit
// model (explicit/explicit_slide.hpp). Split from slider.hpp (issue 24) so that the protocol
// and the explicit model do not depend on the lateral force model.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "asperity/core/common/comm.hpp"
#include "asperity/core/common/settings.hpp"
#include "asperity/core/common/shape.hpp"
#include "asperity/core/fft/fft_engine.hpp"
#include "asperity/core/minimize/minimizer.hpp"
#include "asperity/core/slide/frames.hpp"

namespace asperity::slide {

enum class Protocol { reference, adaptive };

// What the friction force is divided by to give the friction a slide maximises and reports
// (MODEL.md 3; issue 27): the load (mu = Fx / Fz: the Hertz and mixed envelopes, the explicit
// model) or the contact-site area (tau_fric = Fx / A, A = N_c d^2: the adhesive envelope, whose
// load is zero, so mu is undefined there).
enum class FrictionMeasure { load, area };
std::string to_string(FrictionMeasure m);
// Fx / Fz or Fx / area.
inline double friction_ratio(double Fx, double Fz, double area, FrictionMeasure m) {
  return m == FrictionMeasure::load ? Fx / Fz : Fx / area;
}
std::string to_string(Protocol p);
Protocol protocol_from_string(const std::string& name);  // throws std::invalid_argument

// The minimiser settings a slide starts from: MinimizerOptions with force_tolerance = 1e-5 and
// max_displacement = 0.2.
minimize::MinimizerOptions slide_minimizer_defaults();

// The slip minimiser (SlideOptions::slip_minimizer) made from the slide's minimiser `base`: the
// same tolerances with another method and preconditioner, and an iteration budget of at least
// 2 000 000 (a relaxation through a slip takes the flow tens of times the iterations of lbfgs).
minimize::MinimizerOptions slip_minimizer_from(const minimize::MinimizerOptions& base,
                                               minimize::Method method,
                                               minimize::Preconditioner preconditioner);

struct SlideOptions {
  Protocol protocol = Protocol::adaptive;  // see slider.hpp
  double step = 0.01;                      // reference protocol: tip step (d)
  double max_step = 0.4;                   // adaptive protocol: largest step (d), < d/2
  double min_step = 1e-2;                  // adaptive protocol: instabilities bracketed to this (d)
  // Adaptive protocol: after a slip event the step restarts at min_step and grows by this
  // factor with every accepted step, up to max_step (0: off, every step max_step). In Regime III
  // the next instability often lies within min_step of the last slip; a full step would then be
  // relaxed, found to slip and bisected back each time (docs/solvers.md, step growth).
  double step_growth = 0.0;
  double distance = 0.0;      // sliding distance (d); 0 = automatic
  double max_distance = 0.0;  // cap of the automatic distance (d); 0 = 3 d + 3 alpha Fz / k
  int slips_to_stop = 2;      // automatic distance: slip events after the peak (which must
                              // also have held over d) before the slide stops
  int max_slips = 0;          // stop at this slip event, whatever the distance (0: no limit);
                              // mu is then a lower bound: the bound on a long Regime III run
  bool extrapolate = true;    // warm start each step by linear extrapolation along the branch
  // Adaptive protocol: after a slip that moved at least half the contact, probe one period d
  // after an accepted state of the last period; if the probe equals that state carried on by d
  // (largest force difference <= cycle_tolerance), the stick-slip cycle repeats exactly (the
  // interface is periodic in Dx with period d, and the quasi-static path is fixed by the state)
  // and its rows are replayed from the computed ones instead of being recomputed
  // (TraceRow::replayed); a probe that differs is dropped. Off: every step is computed. The
  // reference protocol (the classic one) never replays. docs/solvers.md.
  bool replay_cycle = true;
  double cycle_tolerance = 1e-3;  // largest force difference of a site (G d^2) for equal states
  int path_frame_every = 0;       // relaxation-path frames through slip events every N iterations
                                  // (0: none)
  int path_frame_slips = 25;      // ... of slip events 1, 1 + k, 1 + 2k, ... (1: every one; 0:
                                  // none); 25: a Regime III slide of about 100 small slips
                                  // records four paths (docs/benchmarks.md, output)
  int max_path_frames = 32;       // frames kept per slip event (the interval doubles when full,
                                  // so they stay evenly spread); held until the slip is accepted:
                                  // 16 bytes per block site each (32: 540 MB at a = 510 d)
  // Tolerance, method, ...; sliding defaults: force tolerance 1e-5 G d^2 and a displacement cap
  // of 0.2 d per iteration (docs/benchmarks.md: mu within 3e-4 of converged at 1/7 of the
  // classic protocol's GF applications).
  minimize::MinimizerOptions minimizer = slide_minimizer_defaults();
  // Relaxes again every slip that `minimizer` would accept (the step that ends a bisection, or
  // a slipping step of the reference protocol), from the state moved to the new Dx without the
  // warm start, and takes its verdict and end state instead: a path-faithful solver (method
  // flow) where the path matters, a fast one elsewhere (docs/solvers.md, "Path fidelity"). A slip
  // it finds stable is accepted as a stable state. Empty (the default here): every step by
  // `minimizer`. The tools (contact_slide, friction_sweep) set it by default to the flow in the
  // interface filter's metric (solver.slip_method = "flow", apps/common/slide_io.cpp), made from
  // their final `minimizer` by slip_minimizer_from(); a library caller who wants the faithful
  // path does the same after setting `minimizer`.
  std::optional<minimize::MinimizerOptions> slip_minimizer;
  // With a slip minimiser, in creep (the last `flow_first_after` accepted steps all slips:
  // Regime III's arrested loops moving on at every push), a step at most min_step wide goes to
  // the slip minimiser first, and the fast minimiser relaxes it only if the flow finds it
  // stable, the step then taken as it would have been without this. Where the fast minimiser
  // would call the step a slip (at R = 800 d, a = 300 d every such step), the flow starts from
  // the same state either way, so the path is the same bit for bit and the fast trial's cost is
  // saved (about 1 000 GF applications of each slip there); where the flow slips and the fast
  // minimiser would not, the flow's verdict stands (MODEL.md 5). 0: never. Why 4 by default:
  // docs/solvers.md, "Creep: the flow first".
  int flow_first_after = 4;
  fft::FFTOptions fft;  // threads and planning of the GF transforms

  // The settings, keyed as in a scene ("slide.max_step", "solver.tolerance", "fft.threads",
  // "output.path_frames", ...): common/settings.hpp. slip_minimizer is made from `minimizer`
  // (slip_minimizer_from) and checked by validate() like it.
  static const settings::Table<SlideOptions>& settings();
  // Throws std::invalid_argument naming the violated constraint: the table's allowed sets,
  // min_step <= max_step, the slip minimiser's settings.
  void validate() const;
  // Whether a gap in Dx (d) is a closed bracket: at most min_step, with a relative slack of
  // 1e-4 for the round-off of positions summed from steps and halvings. The one test the
  // protocol's bisection, its closing trials and bracket_slip (path.hpp) share, so that what
  // the slide takes as a closed bracket is what the path check finds.
  [[nodiscard]] bool within_min_step(double gap) const { return gap <= min_step * 1.0001; }
};

struct TraceRow {
  double Dx = 0.0, Fx = 0.0, Fz = 0.0, energy = 0.0;
  int iterations = 0;  // minimiser iterations of this step
  std::size_t gf_applications = 0;
  double max_force = 0.0;  // residual reached
  bool slip = false;       // a slip event happened during this step
  int slipped_sites = 0;   // sites whose registry index changed in this step
  bool replayed = false;   // copied from the computed row one or more periods d back (the cycle
                           // repeats, SlideOptions::replay_cycle), not computed: no iterations
  double area = 0.0;       // contact-site area N_c d^2 (d^2; lateral force model; explicit: 0)
};

// The stop reasons (SlideResult::stop_reason) that other layers test: friction_sweep continues a
// lower bound stopped at one of these limits when a later run raises it.
inline constexpr std::string_view kStopDistanceCap = "distance cap reached";  // slide.max_distance
inline constexpr std::string_view kStopSlipLimit = "slip event limit reached (slide.max_slips)";

struct SlideResult {
  std::vector<TraceRow> trace;  // accepted steps, Dx increasing (first row: Dx = 0)
  // Which friction the slide maximised: Fx / Fz (mu) or Fx / A (tau_fric).
  FrictionMeasure measure = FrictionMeasure::load;
  double mu = 0.0;             // max Fx / Fz; NaN where there is no load (FrictionMeasure::area)
  double mu_over_alpha = 0.0;  // NaN likewise
  // The friction stress at the peak, Fx / A with A the contact-site area there (G): the maximum of
  // Fx / A (FrictionMeasure::area), or mu Fz / A at the peak of Fx / Fz (load). NaN for a model
  // without contact sites (explicit).
  double tau_fric = 0.0;
  double area = 0.0;  // contact-site area at the peak, N_c d^2 (d^2; explicit model: 0)
  double peak_Dx = 0.0;
  double peak_precision = 0.0;     // uncertainty of mu (or tau_fric, FrictionMeasure::area) from
                                   // the step resolution at the peak
  bool mu_is_lower_bound = false;  // the maximum is the last sample (the slide ended on the
                                   // ramp), or the automatic cap came before it had held
  double Fz = 0.0;                 // discrete Hertz load at the peak
  double Fz_continuum = 0.0;       // 4 E* a^3 / (3 R)
  double kinetic = 0.0;            // mean Fx / Fz (Fx / A: FrictionMeasure::area) after the first
                                   // slip; without slips over the last period d; NaN if not
                                   // measured (no slip, slide shorter than d)
  double kinetic_over_static = 0.0;
  int slip_events = 0;
  double distance = 0.0;  // Dx reached
  std::string stop_reason;
  int steps = 0;                    // accepted steps (computed; replayed rows not counted)
  int replayed_steps = 0;           // rows of the trace replayed from the repeating cycle
  double cycle_verified_at = -1.0;  // Dx at which the state equalled the one a period d back,
                                    // from where the cycle was replayed (-1: never)
  double cycle_mismatch = -1.0;     // its largest force difference of a site (G d^2; -1: none)
  int minimizations = 0;            // including undone trial steps
  int slip_relaxations = 0;         // steps relaxed again by SlideOptions::slip_minimizer
  int flow_first_steps = 0;         // steps the slip minimiser relaxed first (flow_first_after)
  int flow_first_stable = 0;        // ... of which it found stable or could not relax (the fast
                                    // minimiser then relaxed them)
  std::size_t gf_applications = 0;
  std::size_t gradient_evaluations = 0;  // interface force evaluations (line searches included)
  std::size_t filter_applications = 0;   // interface filter passes (an FFT pair each, like a GF
                                         // application; see MinimizerOptions::preconditioner)
  bool filtered = false;                 // some minimisation used the interface filter
  long long iterations = 0;
  double wall_s = 0.0;  // summed over the sessions of a resumed slide
  bool failed = false;  // a minimisation did not converge or gave non-finite values; see
                        // stop_reason (step, Dx, step size, solver); snapshot "last_good" holds
                        // the state before it
  bool interrupted = false;  // stopped on request (SlideControl::stop_requested): the results
                             // are partial; the state went to SlideControl::checkpoint
  Shape2 block, fft_grid;
  std::size_t contact_sites = 0;  // unknown sites at Dx = 0
  Snapshot peak_snapshot;         // the state at the peak (also handed to the sink as "peak");
                                  // empty if the slide was interrupted
  // The frames of the slide ("peak" first), when no SlideControl::frames sink took them.
  std::vector<Snapshot> snapshots;
};

// What a slide is doing when it reports progress. A slide at a million sites spends most of its
// time in a few relaxations (a slip sweeps the contact in thousands of iterations), so it says
// which relaxation starts, not only which step was taken.
enum class SlidePhase {
  start,      // relaxing the first state (Dx = 0)
  accepted,   // a state was taken into the trace (computed or replayed)
  step,       // relaxing a step that is undone if it slips (one at most min_step long is taken
              // as the slip if it slips: the slip minimiser's relaxation follows, phase slip)
  bisection,  // relaxing a trial inside the bracket of an instability (the same for the last)
  slip,       // relaxing through a bracketed instability: the slip itself, often the longest
  probe,      // relaxing one period on, to compare with a kept state (cycle replay)
  peak,       // relaxing a point of the peak refinement, after the stepping
};

struct SlideProgressInfo {
  SlidePhase phase = SlidePhase::accepted;
  double Dx = 0.0;                  // tip position of the last accepted state (d)
  double target_Dx = 0.0;           // tip position the relaxation starting now goes to (d); = Dx
                                    // for `accepted`
  double limit = 0.0;               // distance requested, or the automatic distance's cap (d)
  int slip_events = 0;              // so far
  int steps = 0;                    // computed steps accepted so far
  int replayed_steps = 0;           // replayed steps so far
  std::size_t gf_applications = 0;  // so far, earlier sessions of a resumed slide included
  double wall_s = 0.0;              // so far, earlier sessions included (s)
  int iteration = 0;  // minimiser iterations of the relaxation in progress; 0: it starts now (the
                      // lateral force model reports every 16 iterations while it relaxes)
  // The friction of the last accepted state and the largest so far (the static peak's
  // candidate, never below the first), in the slide's measure: Fx/Fz (mu), or Fx/area (G) with
  // FrictionMeasure::area. NaN before the first state. A Regime III slide runs for hours through
  // small slips; whether the first climbs past the second is what one watches for (the upturn,
  // MODEL.md 8).
  FrictionMeasure measure = FrictionMeasure::load;
  double friction = std::numeric_limits<double>::quiet_NaN();
  double peak_friction = std::numeric_limits<double>::quiet_NaN();
};
using SlideProgress = std::function<void(const SlideProgressInfo&)>;

// One state of the slide on the block of sites that follows the tip.
struct SlideFields {
  double Dx = 0.0;           // tip position (d)
  int shift = 0;             // block offset along x (lattice steps)
  std::vector<double> f, u;  // force (G d^2) and displacement (d) per block site, x then y
  double Fx = 0.0, Fz = 0.0, energy = 0.0;
  double area = 0.0;    // contact-site area N_c d^2 (d^2; lateral force model; explicit: 0)
  double h = 0.0;       // explicit model: apex height of the tip (d); unused (0) in the LFM
  double dFz_dh = 0.0;  // explicit model: the load loop's last secant slope of Fz(h) (G d),
                        // carried so that a resumed slide repeats it; 0: none yet (and LFM)
};

// A frame of a relaxation path as the slide holds it until the relaxation is accepted as a slip:
// the displacement field of the state at a minimiser iteration (fields.f is left empty), from
// which Model::snapshot makes the Snapshot (8 fields) only when it is handed over.
struct PathFrame {
  int iteration = 0;
  SlideFields fields;
};

// A slip relaxation by the slip minimiser's flow, paused (lateral force model): the step it
// relaxes, the relaxation that called the step a slip (counted when the slip is accepted), where
// the flow was, and the relaxation-path frames taken so far. A slip through a large contact
// relaxes for hours, so checkpoints (every checkpoint_every_s, and on a stop request) are taken
// inside it too, and a resumed slide continues it instead of repeating it.
struct PendingSlip {
  double Dx = 0.0;  // tip position of the step (d)
  // The slide minimiser's relaxation of the step; none if the step went to the flow first
  // (SlideOptions::flow_first_after).
  std::optional<minimize::MinimizeResult> fast;
  minimize::FlowPause flow;       // the slip minimiser's flow, paused
  std::vector<PathFrame> frames;  // path frames of the flow so far
  int frame_interval = 0;         // their interval (iterations; doubles when they fill up)
};

// Everything slide() needs to continue a slide exactly where it was (checkpoint and resume): a
// plain struct, so that the caller chooses the file format (core does no file I/O). A slide
// resumed from a state continues bit for bit as the uninterrupted one would have, given the same
// scene, options and FFT threads (the caller checks that they match).
struct SlideState {
  SlideFields current;                   // last accepted state
  std::optional<SlideFields> previous;   // the two before it on the branch (warm-start
  std::optional<SlideFields> earlier;    // extrapolation)
  SlideFields peak;                      // highest Fx/Fz so far
  std::optional<SlideFields> runner_up;  // the peak it replaced
  double best = 0.0;                     // Fx/Fz (or Fx/A, FrictionMeasure) at the peak
  double runner_up_ratio = 0.0;          // the same at the runner-up (-inf: none)
  double first_max_Dx = -1.0;            // Regime I: first maximum of Fx without a slip (-1: none)
  double slip_at = 0.0;                  // adaptive: known unstable Dx beyond current (inf: none)
  bool stepping_done = false;       // the stepping had ended (stop_reason set); the peak refinement
                                    // and the summary quantities remain
  std::vector<SlideFields> window;  // cycle replay: accepted states of the last period
  std::vector<std::size_t> window_rows;  // and their rows in partial.trace
  bool cycle_check_due = false;          // a probe of the cycle is due at the next step
  SlideResult partial;  // trace, counts, slip events, stop reason so far; the snapshots
                        // only if no sink took them
  std::optional<PendingSlip> pending;  // a slip relaxation paused at the next step, if any
};

// How a caller steers a slide besides its options: progress reports, checkpoints, a stop request,
// a start state. Checkpoints are taken between steps. Stop requests are polled between steps and,
// in the lateral force model, every 16 iterations inside a relaxation (not the first one), which
// is then abandoned: the state before it is handed over, and a resumed slide repeats it. The
// exception is the slip minimiser's flow (SlideOptions::slip_minimizer with method flow, lateral
// force model): it is paused instead, at the next accepted step, and checkpoints are also taken
// inside it when they are due; the state handed over holds it (SlideState::pending), and a
// resumed slide continues it bit for bit. A checkpoint inside a flow is followed by one at the
// top of the next step, due or not: a state between steps, which a slide with other limits can
// continue too (a paused flow belongs to its step; friction_sweep keeps the one between steps for
// a point stopped at a limit). With checkpoint_every_s = 0 there are no checkpoints inside flows.
// A second exception: the fast relaxation after a flow that went first and found its step stable
// (SlideOptions::flow_first_after) is not abandoned, since the flow would be lost with it; the
// stop is seen at the next step.
// The processes one slide is spread over (issue 26; the lateral force model): each holds the
// rows of the block that its slab of the Green's function's padded grid covers, with their
// contact sites. engine: the GF's FFT backend (fft::mpi_engine_factory(comm) over MPI); comm: the
// same processes (par::MpiComm); both empty or null: one process. Every process calls slide()
// with the same scene, options and control (each callback set on every process or on none);
// frames and checkpoints carry every row on the root process (rank 0) and no field values on the
// others, which should write nothing; a checkpoint resumes on any number of processes.
struct SlideParallel {
  fft::EngineFactory engine;
  const par::Comm* comm = nullptr;  // not owned
};

struct SlideControl {
  SlideProgress progress;  // after every accepted step and before every relaxation
  // Receives the state: every checkpoint_every_s of wall time, on a stop request (before slide()
  // returns with interrupted = true) and on a numerical failure (the last good state).
  std::function<void(const SlideState&)> checkpoint;
  double checkpoint_every_s = 300.0;  // wall time between checkpoints (s); 0: after every step
  // Polled between steps and inside relaxations (above); true: checkpoint, then return with
  // interrupted = true. Called from the sliding thread; a signal handler sets a flag that this
  // reads.
  std::function<bool()> stop_requested;
  const SlideState* start = nullptr;  // continue from this state instead of Dx = 0 (not owned)
  // Takes the frames as they are made (not owned); null: they are collected in
  // SlideResult::snapshots (and in the checkpoints' partial result).
  FrameSink* frames = nullptr;
  SlideParallel parallel;  // one process unless set (see SlideParallel)

  void validate() const;  // throws std::invalid_argument naming the violated constraint
};

// Accepted states the cycle replay keeps at most (SlideOptions::replay_cycle): a period of
// adaptive steps with a bisected slip is 10-15 of them; beyond this the oldest go, and a cycle
// whose start went with them is computed instead of replayed.
inline constexpr std::size_t kCycleWindow = 16;

}  // namespace asperity::slide
