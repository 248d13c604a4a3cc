// Energy minimisers for minimize::Problem (SOLVERS.md, "Free-boundary contact").
//
// Methods (all G-preconditioned, one GF application per iteration, line searches free):
// - lbfgs: limited-memory BFGS with H0 = G, or G M with the problem's interface filter M
//   (Preconditioner::interface; one more FFT pair per iteration, far fewer iterations on large
//   pinned contacts). Two-loop recursion on s = du, y = dr; the K-image
//   of the direction is q + sum_i c_i df_i (the stored force changes), so no K is needed.
// - cg: the classic reference, Polak-Ribiere+ conjugate gradients preconditioned with G.
// - fire: FIRE (Bitzek et al., PRL 97, 170201, 2006) on the preconditioned force -G r, with
//   powers and norms in the K metric (r.du, r.G r), which the pair makes free.
// - newton: lbfgs down to newton_start, then a Newton-Krylov finish (KINSOL, solve/) on
//   F(f) = f - f_int(G f) = 0 with J v = v + H_int G v (one GF application per product). Newton
//   finds any stationary point, so the stability check below is what keeps it on minima.
// - flow: the reference path of MODEL.md section 5, the overdamped gradient flow du/dt = -G r
//   (df/dt = -r: the pair stays exact), integrated under error control: a step is kept only if
//   its local error (largest displacement of a site) is within flow_tolerance and the energy has
//   not risen. flow_scheme rkc (default): second-order Runge-Kutta-Chebyshev, stages chosen for
//   stability, steps for accuracy; euler: explicit Euler with the error estimate of ODE12r
//   (Makri, Ortner & Kermode, J. Chem. Phys. 150, 094109, 2019), without ODE12r's acceptance on
//   a falling residual: the flow is the answer, not a way to it (details in flow.cpp,
//   class Flow). With preconditioner = interface the mobility is G M (the flow in the interface
//   filter's metric): not the reference, but cheaper. Slower than lbfgs through a slip (3-10x
//   the FFT passes, docs/solvers.md), it defines which minimum an instability falls into; the
//   path tier (tests/path) holds the other methods to it.
// Every method descends in energy (line searches accept no energy rise beyond round-off; FIRE
// stops and restarts when the power turns negative) and caps the largest displacement of an
// iteration (the flow with rkc: its error control instead), so that a state at an instability
// falls into the next minimum, not a distant one.
// After convergence the state is checked for stability, when some interface curvature is
// negative (otherwise K + H_int > 0 holds trivially), in one of two ways:
// - perturb (default): a random push of 1e-5 d (a force field f' with u' = G f') and a second
//   minimisation; if it ends lower in energy and away from the state, the state was unstable
//   and the new one is kept (and checked again). A descent method cannot stay on a saddle it
//   was pushed off, and a symmetric state cannot hide an antisymmetric instability. Limit: very
//   near a fold the unstable mode grows so slowly that the second minimisation may meet the
//   force tolerance first; the lanczos check has no such blind spot.
// - lanczos: the lowest eigenvalue of the Hessian K + H_int by Lanczos (Spectra) in the
//   congruent form A = G + G H_int G (same inertia, Sylvester); an unstable state is left along
//   its eigenvector. Exact, but the spectrum of A is clustered at its low end, so it costs
//   thousands of GF applications on a large contact.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "asperity/core/common/settings.hpp"
#include "asperity/core/common/termination.hpp"
#include "asperity/core/minimize/problem.hpp"

namespace asperity::minimize {

// Each method is a class behind detail::MinimizerMethod with a row in method_registry(), which
// gives its name (minimize/relaxation.hpp).
enum class Method { lbfgs, cg, fire, newton, flow };
enum class StabilityCheck { none, perturb, lanczos };
// Integrator of the flow (flow.cpp): rkc (second-order Runge-Kutta-Chebyshev, stages chosen
// for stability, steps limited by accuracy) or euler (explicit Euler, steps limited by the
// fastest interface mode: the simplest scheme, the cross-check).
enum class FlowScheme { rkc, euler };
std::string to_string(FlowScheme s);
FlowScheme flow_scheme_from_string(const std::string& name);  // throws std::invalid_argument
// H0 of lbfgs (and of newton's lbfgs phase): elastic = G; interface = G M with M the problem's
// interface filter (Problem::filter), if it has one; automatic = interface where the problem
// judges that it pays, else elastic.
enum class Preconditioner { elastic, interface, automatic };
std::string to_string(Preconditioner p);
Preconditioner preconditioner_from_string(const std::string& name);  // throws std::invalid_argument
std::string to_string(StabilityCheck c);
StabilityCheck stability_from_string(const std::string& name);  // throws std::invalid_argument
std::string to_string(Method m);
Method method_from_string(const std::string& name);  // throws std::invalid_argument

struct MinimizerOptions {
  Method method = Method::lbfgs;  // see minimizer.hpp
  double force_tolerance = 1e-6;  // stop when max |r_i| <= this (force per site, G d^2)
  int max_iterations = 20000;     // per minimisation, escapes included
  int memory = 8;                 // L-BFGS pairs kept
  double newton_start = 1e-3;     // newton: switch to Newton-Krylov below this max |r| (G d^2)
  double max_displacement = 0.1;  // largest |du_i| in one iteration (d)
  Preconditioner preconditioner = Preconditioner::automatic;  // lbfgs and newton (see above)
  int refresh_interval = 200;  // recompute u = G f every this many iterations (drift)
  StabilityCheck stability = StabilityCheck::perturb;  // check of converged states (see above)
  int max_escapes = 20;                                // unstable-state escapes per minimisation
  double escape_displacement = 0.05;  // largest |du_i| of the push off an unstable state (d)
  // Largest |du_i| of the random push of the perturb check (d); larger when needed for the
  // push to unbalance the state by 10x the force tolerance.
  double perturbation = 1e-5;
  // flow: largest local error of one step, as a displacement of a site (d). Halving it must not
  // change the end state (tests/path); 1e-3 d is far below a core width (>= 1 d) and the d/4
  // distance from a well's bottom to its unstable half.
  double flow_tolerance = 1e-3;
  FlowScheme flow_scheme = FlowScheme::rkc;  // flow: the integrator (see above)
  // lbfgs, newton: clear the pairs whenever a site enters or leaves the unstable half of its
  // well (experimental, issue 21: measured by the path tier, docs/solvers.md).
  bool curvature_reset = false;

  // The settings (keys "method", "tolerance", ...; a slide's scene has them under "solver."):
  // common/settings.hpp. One allowed set each, checked by validate().
  static const settings::Table<MinimizerOptions>& settings();
  // Throws std::invalid_argument naming the violated constraint.
  void validate() const;
};

// Called every iteration with the current pair (relaxation-path frames, early stops); returning
// true stops the minimisation with Termination::interrupted.
using Observer =
    std::function<bool(int iteration, std::span<const double> u, std::span<const double> f)>;

struct MinimizeResult {
  Termination termination = Termination::max_iterations;
  int iterations = 0;
  std::size_t gf_applications = 0;
  std::size_t interface_evaluations = 0;
  std::size_t filter_applications = 0;  // interface filter passes (one FFT pair each)
  bool filtered = false;                // the interface filter was used
  double energy = 0.0;                  // Pi at the end
  double max_force = 0.0;               // max |r_i| at the end
  int escapes = 0;                      // unstable states left
  int rejected_steps = 0;               // flow: steps the error control rejected (in iterations)
  int memory_resets = 0;                // curvature_reset: times the pairs were cleared
  // Lowest eigenvalue of G + G H_int G at the final state if the Lanczos check ran, else NaN;
  // >= 0 means stable.
  double lowest_eigenvalue = 0.0;
  bool stability_checked = false;  // negative curvature was present and a check ran
};

// A flow relaxation (Method::flow) paused after an accepted step, from which minimize()
// continues it bit for bit: the pair, the integrator's state and the counts so far. A slip
// through a large contact relaxes under the flow for hours (R = 1700 d, a = 430 d: over 90
// minutes and 29 000 GF applications on 2 threads), longer than a run may last, so that a
// checkpoint has to be able to hold one (slide::PendingSlip).
struct FlowPause {
  int iteration = 0;                           // iterations done
  std::vector<double> u, f;                    // the pair (u = G f up to the flow's drift)
  std::vector<double> velocity_u, velocity_f;  // -(du/dt, df/dt) at the pair: (G P r, P r)
  double step = 0.0;                           // the next step to try (flow time)
  double radius = 0.0;                         // rkc: spectral radius estimate (0: none)
  int since_estimate = 0;                      // rkc: accepted steps since the estimate
  std::vector<double> power;                   // rkc: power-iteration vector (empty: none yet)
  MinimizeResult done;                         // counts and flags so far
};

// Where minimize() may pause a flow relaxation: after every accepted step `due` is asked (with
// the iteration); if it says yes, `pause` receives the state, and if `pause` returns true the
// minimisation stops there with Termination::interrupted (the caller keeps the FlowPause and
// may continue from it).
struct FlowPauses {
  std::function<bool(int iteration)> due;
  std::function<bool(const FlowPause&)> pause;
};

// Minimises from the pair (u, f), which must satisfy u = G f, and leaves the result there.
// With `resume` (a flow relaxation paused by `pauses` of an earlier call with the same problem
// and options) it continues from there instead, bit for bit as if it had not paused, and the
// counts of the result include the work before the pause; u and f need only have the right size.
// Throws std::invalid_argument if `resume` is not a flow's pause of this problem's size.
MinimizeResult minimize(Problem& problem, std::vector<double>& u, std::vector<double>& f,
                        const MinimizerOptions& options, const Observer& observer = {},
                        const FlowPause* resume = nullptr, const FlowPauses* pauses = nullptr);

// max |r_i| with r = f - f_int(u) at the pair (u, f), over the unknowns of every process: the
// number minimize() compares with force_tolerance (MinimizeResult::max_force), for a pair that
// did not come out of a converged call (a flow's pause, a checkpoint). One interface evaluation,
// no GF application; NaN if any r_i is NaN. Throws std::invalid_argument if u or f is not of the
// problem's size.
double max_residual(Problem& problem, std::span<const double> u, std::span<const double> f);

// Lowest eigenvalue of A = G + G H_int G at u (sign = stability) and, if wanted, the unstable
// direction in displacement space (v = G w) with its force image w.
struct Stability {
  double lowest = 0.0;
  std::vector<double> direction_u, direction_f;
  bool converged = false;
  std::size_t gf_applications = 0;
};
Stability lowest_mode(Problem& problem, std::span<const double> u);

}  // namespace asperity::minimize
