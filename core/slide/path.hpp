// Path checks (MODEL.md 5): which minimum a relaxation through an instability ends in, measured
// against the reference path, the overdamped gradient flow (minimize::Method::flow).
//
// The reference path fixes "the next minimum" after an instability: the same registry index
// round(s/d) on every contact site (round(rho) per tip axis under a tip out of registry,
// interface/tip_lattice.hpp) as the flow's end state, and the same friction force
// (|dFx| / Fx <= 1e-4: the force tolerance of a slide, 1e-5 G d^2 per site, moves Fx by far
// less). A solver that ends elsewhere took another path, however small its residual. And at a
// fold, a trial step a solver calls a slip must be one the flow calls a slip from the same state.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "asperity/core/slide/slider.hpp"

namespace asperity::slide {

// A bracketed instability of a slide: the last stable state before slip event `event` and the
// tip position of the trial step from it that slipped (at most min_step further on).
struct Instability {
  SlideFields stable;
  double slip_Dx = 0.0;
  int event = 1;
  SlideResult slide;  // the slide that found it, stopped there (interrupted)
};

// Slides `scene` with `options` (adaptive protocol, no cycle replay: every slip is computed) until
// slip event `event` is bracketed to min_step, and returns its bracket. Throws
// std::runtime_error if the slide ends or fails before that slip.
Instability bracket_slip(const interface::ContactScene& scene, SlideOptions options, int event = 1);

// Two states of the same scene at the same tip position (and block), compared site by site.
struct StateComparison {
  int sites = 0;                 // contact sites compared
  int registry_differences = 0;  // of them, sites whose registry index (x or y) differs
  double Fx_a = 0.0, Fx_b = 0.0;
  double relative_Fx = 0.0;  // |Fx_a - Fx_b| / |Fx_b|
  double max_du = 0.0;       // largest |u_a - u_b| over the contact sites (d)
  // The same minimum (MODEL.md 5): the same registry on every site and Fx within fx_tolerance.
  [[nodiscard]] bool same_minimum(double fx_tolerance = 1e-4) const {
    return registry_differences == 0 && relative_Fx <= fx_tolerance;
  }
};
// Throws std::invalid_argument if the states are not at the same tip position and block.
StateComparison compare_states(const interface::ContactScene& scene, const SlideFields& a,
                               const SlideFields& b);

// A flow relaxation after one accepted step (path_check --flow-profile): where its cost goes,
// leaving the fold, the glide of the slip, or settling into the minimum. The stability check of
// the end state (solver.stability) relaxes on without samples.
struct FlowSample {
  int iteration = 0;          // accepted and rejected steps so far
  std::size_t gf = 0;         // GF applications so far
  std::size_t filter = 0;     // interface filter passes so far
  double step = 0.0;          // the next step the error control tries (flow time)
  double radius = 0.0;        // rkc: spectral radius estimate (0: none yet)
  double max_speed = 0.0;     // max |du/dt| over the contact coordinates (d per flow time)
  double max_residual = 0.0;  // max |P r|, P = I or the filter (G d^2)
  double max_move = 0.0;      // max |u - u at the previous sample| (d)
  int moved = 0;              // contact coordinates moved over d/2 since the first sample
};
using FlowProfile = std::vector<FlowSample>;

// One solver's relaxation of a bracketed slip step against the flow's.
struct PathCheckRow {
  std::string solver;  // method and preconditioner, e.g. "lbfgs/interface"
  StepRelaxation step;
  FlowProfile profile;  // a flow's, if check_path was asked for profiles
  StateComparison against_flow;
  bool slipped = false;  // called the step a slip (registry_jumps > 0)
};
struct PathCheck {
  Instability instability;
  StepRelaxation flow, flow_half;  // the flow at its tolerance and at half of it
  StateComparison flow_self;       // flow against flow_half: the step control's own test
  FlowProfile flow_profile;        // the reference flow's, if asked for
  std::vector<PathCheckRow> rows;
};

// Relaxes the slip step of `at` with the flow (options.minimizer with method flow, at
// flow_tolerance and flow_tolerance / 2, up to flow_max_iterations steps: through a slip the
// flow takes tens of times the iterations of lbfgs) and with each of `solvers` (minimiser
// settings; the other options as given), and compares each end state with the flow's.
// halve = false skips the flow at half its tolerance (flow_half and flow_self stay empty);
// profile = true samples the reference flow and every flow among `solvers` after each accepted
// step (FlowProfile; it copies the pair once per step, so it costs a little time).
PathCheck check_path(const interface::ContactScene& scene, const SlideOptions& options,
                     const Instability& at, const std::vector<minimize::MinimizerOptions>& solvers,
                     int flow_max_iterations = 2'000'000, bool halve = true, bool profile = false);

// "lbfgs/interface", "cg", ...: the method, and for lbfgs and newton the preconditioner.
std::string solver_label(const minimize::MinimizerOptions& m);

}  // namespace asperity::slide
