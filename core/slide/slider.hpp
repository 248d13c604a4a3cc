// Quasi-static sliding of the lateral force model (MODEL.md sections 3 and 5).
//
// The tip moves in +x; after each step the energy is minimised from the previous state
// (minimize/minimizer.hpp). The unknowns are the in-plane displacements of the contact sites
// only; they live in a block of (2H+1)^2 sites, H = ceil(a) + 2, that follows the tip in whole
// lattice steps (the GF is translation invariant and the interface periodic), so the FFT grid
// never grows with the sliding distance.
//
// Protocols:
// - reference: fixed steps (0.01 d), the classic protocol;
// - adaptive: steps up to max_step where the response is smooth; a step that produces a slip
//   event is undone and bisected until the instability is bracketed to min_step, so the static
//   peak (the last stable state before the slip) is located to min_step in Dx.
// Slip event: a step after which some contact site's registry index round(s/d) changed
// (MODEL.md 5) by a jump: its displacement changed by d/4 or more (the floor is ours, not the
// spec's: a contact riding smoothly over the barrier top changes every index; slider.cpp says
// why d/4). The state jumped to another minimum. A gliding core counts; a smooth crossing of
// the barrier top does not.
// Automatic distance: slide until the static peak is established, i.e. until it has held (not
// been exceeded beyond the trace's resolution) over one period d with `slips_to_stop` slip
// events after it, stopping at a slip (Regime II: the slips_to_stop-th slip, the cycle repeats
// with period d; Regime III: Fx rises through many small slips as arrested loops pile up, and
// the peak moves on with it), or, without slips (Regime I), one period d past the first
// maximum of Fx; capped (mu is then a lower bound unless the peak had held).
// Friction: mu = max Fx / Fz where the envelope carries a load (hertz, mixed), else the friction
// stress tau_fric = max Fx / A, A = N_c d^2 the contact-site area (adhesive; types.hpp,
// FrictionMeasure); the automatic distance's cap is 3 d + 3 F_I / k (F_I = alpha Fz, tau0 pi a^2
// or both: ContactScene::regime_one_force).
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <string>

#include "asperity/core/common/shape.hpp"
#include "asperity/core/interface/lfm.hpp"
#include "asperity/core/slide/frames.hpp"
#include "asperity/core/slide/types.hpp"

namespace asperity::slide {

SlideResult slide(const interface::ContactScene& scene, const SlideOptions& options,
                  const SlideProgress& progress = {});

// Throws std::invalid_argument if control.start does not fit the scene (other block size).
SlideResult slide(const interface::ContactScene& scene, const SlideOptions& options,
                  const SlideControl& control);

// The friction at the peak over its Regime I (rigid) value there (MODEL.md 3): Fx / F_I with Fx =
// mu Fz or tau_fric A (the result's measure) and F_I = alpha Fz + tau0 A (= sum_i tau_max(r_i) d^2
// over the contact sites, ContactScene::regime_one_force). 1 in Regime I; mu / alpha for the
// Hertz envelope, tau_fric / tau0 for the adhesive one (to round-off), and for the mixed one
// 1 / (alpha Fz / Fx + tau0 A / Fx). NaN if the result has no peak (failed before a state).
double friction_over_regime_one(const interface::ContactScene& scene, const SlideResult& r);

// Sites along each side of the block of unknowns that follows the tip: 2 H + 1, H = ceil(a/d) + 2
// (the contact radius and two sites of margin). Snapshots are frames of this block.
int block_side(const interface::ContactScene& scene);

// One relaxation of the lateral force model, as a step of a slide makes it: the state `from` (of
// a slide on this scene) moved to tip position Dx and minimised with options.minimizer, without
// warm-start extrapolation. What the path tier (tests/path) and path_check use to relax one
// and the same step with several solvers. gf_applications counts those of the relaxation and of
// bringing the state to Dx (u = G f); slipped_sites is registry_jumps(from, state).
struct StepRelaxation {
  SlideFields state;
  minimize::MinimizeResult result;
  int slipped_sites = 0;
  double wall_s = 0.0;
};
// `watch`, if given, sees the flow's state after every accepted step (iteration, counts so far,
// pair, velocity; a FlowPause that is not kept): how a flow relaxation spends its steps
// (path_check --flow-profile). Methods other than the flow never call it.
using FlowWatch = std::function<void(const minimize::FlowPause&)>;
StepRelaxation relax_step(const interface::ContactScene& scene, const SlideOptions& options,
                          const SlideFields& from, double Dx, const FlowWatch& watch = {});

// The snapshot (frames.hpp) of a state of a slide on this scene, as the slide would hand it
// over: for path checks and tools that look at states made by relax_step.
Snapshot snapshot_of(const interface::ContactScene& scene, const SlideFields& state,
                     std::string label);

// Where a slip flow paused in a checkpoint stands (SlideState::pending; lateral force model):
// the state at the paused iteration on the step's block, as the slide would hold it had the
// flow ended there (the pair on the contact sites, u = G f off it), the sites that have
// slipped since the last accepted state (registry_jumps), and how far the state is from
// equilibrium: max |r_i| over the contact sites, r = f - f_int(u) (SOLVERS.md), the measure a
// minimiser's force_tolerance bounds. A line that creeps through a long flow leaves a state a
// minimiser with a looser tolerance than that would stop in, calling the line held. A slip through
// a large contact flows for hours: this is how a run is looked at inside it (friction_sweep --peek,
// for track_loops). `options` are the slide's: its FFT settings make u = G f off the contact bit
// for bit the run's. Throws std::invalid_argument if the state holds no paused flow, or one whose
// tip position is not finite and beyond the last accepted state's, or does not fit the scene.
struct PausedSlip {
  SlideFields state;
  int iteration = 0;       // the flow's iterations done
  int slipped_sites = 0;   // since SlideState::current
  double max_force = 0.0;  // max |r_i| of the pair at the pause (G d^2 per site)
};
PausedSlip paused_slip(const interface::ContactScene& scene, const SlideOptions& options,
                       const SlideState& state);

// Slip test of MODEL.md 5 (slider.cpp): the number of sites of `block` in the contact at both tip
// positions whose registry index round(s/d) (x or y) changed between the two displacement fields
// (2 per block site, x then y, both on this block) by a jump of at least d/4 in that component;
// under a tip out of registry the index round(rho) and the component along each tip axis
// (interface/tip_lattice.hpp).
// The last `entered_rows` rows along x came into the block between the two states (no
// displacement before) and are skipped. Throws std::invalid_argument on fields of another size.
int registry_jumps(const interface::ContactScene& scene, const LatticeBlock& block,
                   double Dx_before, std::span<const double> u_before, double Dx_after,
                   std::span<const double> u_after, int entered_rows = 0);

// Estimated peak memory of slide() on this scene (bytes), with a FrameSink taking the frames, so
// that callers can refuse a contact that cannot fit before allocating: the padded FFT grid of
// the block (the smallest 7-smooth size >= 2n - 1 per axis, n = 2 (ceil(a/d) + 2) + 1) times 260
// bytes per grid point, the measured peak without the cycle replay (docs/benchmarks.md, scaling:
// 248-254 bytes for a = 256 and 512 d), plus the replay's window of kCycleWindow states (force
// and displacement, 2 components: 32 bytes per block site each), twice: a checkpoint copies it,
// plus the path frames of one relaxation (max_path_frames x 16 bytes per block site), two
// snapshots (65 bytes per block site each) in flight, the minimiser's vectors on the contact
// sites (the L-BFGS pairs and about 18 working vectors), with the flow as slip minimiser the
// copies of a paused flow and its path frames that a checkpoint inside it makes (PendingSlip),
// and 32 MB for the program itself. Independent of the number of slips.
// Over `ranks` processes (SlideParallel): the fullest rank's share, rank 0's, which holds a slab
// of ceil(N / ranks) of the N grid rows, the block rows and contact sites within it (at most
// all: the block fills the first half of the padded rows), and the whole-block copies the root
// makes of snapshots and checkpoints.
double estimated_slide_bytes(const interface::ContactScene& scene, const SlideOptions& options,
                             int ranks = 1);

}  // namespace asperity::slide
