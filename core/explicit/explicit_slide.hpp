// Sliding of the explicit atomistic model at fixed normal load (MODEL.md 4 protocol, MODEL.md 5
// sliding): the tip is loaded to a target Fz, then moved in +x with the protocols of
// slide/slider.hpp (reference and adaptive, bisection of instabilities, slip detection, peak
// refinement). The protocol code is shared with the lateral force model (slide/protocol.hpp);
// this file supplies the model:
// - a step to tip position Dx is a minimisation at fixed apex height h followed, until
//   |Fz - target| <= load_tolerance * target, by secant steps on h (each a warm-started
//   minimisation): the state of a step is (Dx, h(Dx)), and the warm start extrapolates both the
//   force field and h along the branch; a relaxation at a new h that lands on another branch
//   (an atom moved on to the next hollow) restarts the search on h, since Fz(h) jumps there and
//   heights seen on the old branch bracket nothing on the new one;
// - the unknowns are the atoms of the active disk of ExplicitContact, which follows the tip and
//   grows; states live on blocks of different size and origin, and are mapped onto each other
//   by lattice index (warm starts, slip detection, snapshots);
// - slip (MODEL.md 5): an atom that feels a force in both states whose registry index against
//   the tip lattice changed between them by a jump (registry_slips below), as in the LFM;
// - snapshots on a fixed square block around the tip (the same for every frame): displacement
//   (with u_z), interface force as stress, pressure p = -f_z / d^2 per atom, and
//   tau_max = alpha p with the alpha of the potential.
// - checkpoints and resume (SlideControl) as in the LFM: a state carries its block (by its
//   size and shift), h and the load loop's secant slope dFz/dh, so a resumed slide repeats
//   the uninterrupted one.
// Not available for this model: relaxation-path frames (SlideOptions::path_frame_every is
// ignored).
#pragma once

#include <span>

#include "asperity/core/explicit/explicit_contact.hpp"
#include "asperity/core/slide/types.hpp"

namespace asperity::explicit_model {

struct ExplicitSlideOptions {
  double load = 0.0;             // target Fz (G d^2); > 0
  double load_tolerance = 1e-4;  // per step, |Fz - target| <= this * target: mu = Fx/Fz of the
                                 // state itself, so this only fixes the load mu refers to
  int max_load_steps = 20;       // secant steps on h per tip position
  double margin = 3.0;           // active disk beyond the farthest loaded atom (d)
  int max_growths = 50;          // disk growths per minimisation
  double alpha = 0.0;            // local friction coefficient of the potential, for mu/alpha and
                                 // tau_max (alpha_path at the central load); > 0

  void validate() const;  // throws std::invalid_argument naming the violated constraint
};

// Atoms that slipped between two states (MODEL.md 5: a slip is a change of a site's registry
// index). An atom that feels a force in both states (in the contact at both tip positions, as
// the LFM asks; an atom outside the earlier state's block has no force there) slipped if
// round(rho), per axis of the tip lattice, of its relative position s = X + u - (Dx, 0)
// (TipFrame::registry: s / d for the aligned tip, whose hollows sit over the lattice sites)
// changed, by a jump: its displacement along that axis changed by at least d/4
// (TipFrame::registry_jumped, the LFM's test too). The floor keeps out the smooth crossings
// that are not instabilities (a whole Regime I contact riding over the barrier top changes
// every index without a jump), while a gliding core, which carries its atoms across a
// half-period by less than d/2, counts. Fields on `block`, component-major (x, y, and z for
// forces: an atom is loaded if any component is nonzero; u_z is ignored); the earlier state's
// fields mapped onto `block` by lattice index (0 where its block had no site).
int registry_slips(const interface::TipFrame& frame, double d, const LatticeBlock& block,
                   double Dx_before, std::span<const double> u_before,
                   std::span<const double> f_before, double Dx_after,
                   std::span<const double> u_after, std::span<const double> f_after);

// Loads, then slides (options: protocol, steps, distance, minimiser, FFT threads). The automatic
// distance cap is 3 d + 3 alpha Fz / k with k = 8 G a_H / (2 - nu), as in the LFM. Returns the
// LFM's result type: trace, mu (max Fx/Fz of the states), mu/alpha, snapshots ("peak",
// "slip_NNN_before/after", "last_good"), cost. `control` as in slide::slide (progress,
// checkpoints, stop requests, a start state from a checkpoint of the same scene and options).
// Throws std::invalid_argument for bad options, a/R >= 0.1, or a start state that does not fit.
slide::SlideResult slide_explicit(const ExplicitScene& scene, const ExplicitSlideOptions& eo,
                                  const slide::SlideOptions& options,
                                  const slide::SlideControl& control = {});

}  // namespace asperity::explicit_model
