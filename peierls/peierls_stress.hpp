// Peierls stress of the periodic cell (MODEL.md section 6; SOLVERS.md "Periodic Peierls cell").
//
// Loading: a uniform applied shear stress, i.e. a force tau d^2 along x on every site. The other
// choice, displacing the top body, does not load this cell at all: K(0) = 0 (a half-space has no
// stiffness against a uniform shift of its surface), so a rigid shift of the top body drags the
// whole surface with it. Under stress the line stays in its Peierls valley up to tau_P; above it
// no equilibrium exists and the line glides forever through the periodic cell.
//
// Threshold: from the relaxed zero-stress state, the stress is raised geometrically until a
// relaxation glides (some site moves more than glide_threshold from the zero-stress state:
// under stress every site already shifts by up to d/4 on its sine branch, so a test on the mean
// gives false alarms), then bisected geometrically to the requested relative precision. Every
// relaxation starts from the last stable state. A relaxation that neither converges nor glides
// (near-threshold slowing down) counts as unstable, so tau_P is never above a stress with a
// verified equilibrium; such relaxations are counted.
//
// Precision: each relaxation at stress tau stops at max |g| <= tolerance * tau d^2 (tolerances
// scale with the stress being resolved). The zero-stress relaxation is run until it stalls,
// which measures the residual's round-off floor r0 of this cell; stresses below
// floor = 2 r0 / (tolerance d^2) cannot be relaxed to their tolerance. A threshold below its
// floor is reported unresolved, with the floor, never as a number.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "asperity/core/common/termination.hpp"
#include "asperity/core/minimize/stiffness_minimizer.hpp"
#include "asperity/peierls/cell.hpp"

namespace asperity::peierls {

struct PeierlsOptions {
  CellOptions cell;
  double precision = 1e-3;        // relative half-width of the final bracket of tau_P
  double tolerance = 1e-3;        // force tolerance per site as a fraction of tau d^2
  double glide_threshold = 0.75;  // displacement from the zero-stress state that means glide (d)
  bool both_signs = true;         // also the threshold for negative stress
  // Largest random displacement added to the initial state of the full cell (d), so that an
  // instability that breaks the line's translation symmetry (kinks) can show; fixed seed.
  double perturbation = 1e-3;
  // Minimiser settings (its force_tolerance is set per relaxation from `tolerance`).
  minimize::StiffnessOptions minimizer;

  // The settings (the cell's, "solver.precision", "solver.tolerance", "solver.glide_threshold",
  // "solver.both_signs", "solver.perturbation", and the minimiser's under "solver.").
  static const settings::Table<PeierlsOptions>& settings();
  // Throws std::invalid_argument naming the violated constraint.
  void validate() const;
};

// Threshold for one sign of the applied stress. Stresses in G.
struct Threshold {
  bool resolved = false;
  double tau_P = 0.0;  // geometric midpoint of [lower, upper]; only meaningful if resolved
  double lower = 0.0;  // largest stress with a verified equilibrium
  double upper = 0.0;  // smallest stress without one
  int relaxations = 0;
  int undetermined = 0;  // relaxations that neither converged nor glided (counted unstable)
  double floor = 0.0;    // resolution floor of this threshold (G): the cell's, raised past any
                         // stress whose relaxation stalled at round-off
  long iterations = 0;
  // A relaxation that diverged (non-finite forces): the bracket stops there, the threshold is
  // not resolved, and this says at which stress. Empty: no numerical failure.
  std::string failure;
};

struct PeierlsResult {
  // What was computed.
  int L = 0, mx = 0, my = 0;
  double theta_deg = 0.0, b_core = 0.0, tau_max = 0.0, nu = 0.0;
  CellModel model = CellModel::reduced;
  double precision = 0.0, tolerance = 0.0;
  // Thresholds for +x and -x stress (negative: `both_signs` was off).
  Threshold positive, negative;
  // Resolution: round-off floor of the residual at zero stress (G d^2), and the smallest
  // stress a threshold can be resolved at (G).
  double noise_force = 0.0, floor = 0.0;
  // Relaxed zero-stress core: d/4 -> 3d/4 width and the continuum PN value (d).
  double core_width = 0.0, core_width_continuum = 0.0, core_position = 0.0;
  double rigid_estimate = 0.0;  // rigid-profile PN tau_P / tau_max (cell.hpp)
  Termination zero_stress_termination = Termination::max_iterations;
  // Cost.
  long iterations = 0;
  std::size_t transforms = 0;  // FFT pairs (K and P applications)
  std::size_t interface_evaluations = 0;
  // Numerical failures of the zero-stress relaxation or of either threshold, joined; empty if
  // none. A failed point is not a result: callers report it and exit with an error status.
  std::string failure;
  // States for snapshots: relaxed at zero stress, and the last stable one under +tau.
  std::vector<double> u_zero, u_loaded;
  double tau_loaded = 0.0;
};

PeierlsResult peierls_stress(const PeierlsOptions& options);

// Convergence in the cell size. The periodic images of the line, L/|m| apart, shift tau_P by a
// relative amount that falls as 1/L^2 and grows with b_core |m| (measured: 0.1% from L = 256 to
// 512 for an edge line at b_core = 4 d, 2.6% at 12 d, 2.4% at 63.4 degrees and 6 d). A fixed L
// is therefore either wasteful for narrow cores or wrong for wide ones.
struct CellSizeOptions {
  // Relative change of tau_P on doubling L below which the cell counts as large enough; 0 keeps
  // L as given (one cell).
  double tolerance = 0.01;
  int max_L = 4096;  // largest cell tried (sites per period); the last change is reported
  // The settings ("cell.L_tolerance", "cell.max_L").
  static const settings::Table<CellSizeOptions>& settings();
  // Throws std::invalid_argument naming the violated constraint.
  void validate() const;
};

struct CellSizeResult {
  PeierlsResult result;  // at the largest cell computed (result.L); cost summed over all cells
  int cells = 1;         // cells computed: L, 2L, ...
  // |tau_P(L) / tau_P(L/2) - 1| of the last doubling (the largest over the resolved signs); NaN
  // with one cell or when a sign was resolved in one cell only. Since the change falls as
  // 1/L^2, the error of the final cell is about a third of it.
  double change = 0.0;
  bool converged = false;  // change <= tolerance (or tolerance = 0)
};

// peierls_stress at options.cell.L, 2L, 4L, ... until the change is within the tolerance, a
// threshold is unresolved (nothing to compare) or L would exceed max_L.
CellSizeResult peierls_stress_converged(const PeierlsOptions& options,
                                        const CellSizeOptions& cell_size);

}  // namespace asperity::peierls
