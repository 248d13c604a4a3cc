// Minimiser for problems whose elastic stiffness K can be applied directly: periodic cells, where
// K(q) is diagonal in Fourier space (SOLVERS.md, "Periodic Peierls cell"). It minimises
//   Pi(u) = 1/2 u.K u + V(u) - f_ext.u,     gradient g = K u - f_int(u) - f_ext,
// by L-BFGS with the initial inverse Hessian P ~ (K + c)^-1 supplied by the problem (c of the
// order of the interface stiffness 2 pi tau_max d; K(0) = 0 makes the rigid shift free, and c
// keeps P finite there). Per iteration: one preconditioner application and one K application
// (K d along the search direction; along the line K u is then linear and free).
//
// Precision: the energy of a whole cell cannot resolve barriers of 1e-8 tau_max, so the line
// search never compares energies. It works on the slope phi'(t) = g(u + t d).d alone: it moves
// while the slope is negative (the energy then falls, whatever its round-off) and brackets its
// sign change with safeguarded secant steps (strong Wolfe curvature condition). The force
// tolerance is set by the caller from the stress it must resolve, and a run that can no longer
// lower the residual stops as `stalled`, reporting the floor it reached.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "asperity/core/common/settings.hpp"
#include "asperity/core/common/termination.hpp"

namespace asperity::minimize {

class StiffnessProblem {
 public:
  virtual ~StiffnessProblem() = default;

  // Unknowns (sites x components).
  [[nodiscard]] virtual std::size_t size() const = 0;
  // Ku = K u.
  virtual void stiffness(std::span<const double> u, std::span<double> Ku) = 0;
  // z = P r with P symmetric positive definite, close to the inverse Hessian.
  virtual void precondition(std::span<const double> r, std::span<double> z) = 0;
  // Writes the interface force f_int = -dV/du.
  virtual void interface_force(std::span<const double> u, std::span<double> f_int) const = 0;
  // Largest displacement of one site for a direction d (components of a site combined).
  [[nodiscard]] virtual double max_site_norm(std::span<const double> d) const = 0;
};

struct StiffnessOptions {
  double force_tolerance = 1e-8;  // stop when max |g_i| <= this (force per site, G d^2)
  int max_iterations = 50000;     // cap per minimisation
  int memory = 8;                 // L-BFGS pairs kept
  double max_displacement = 0.1;  // largest site displacement of one iteration (d)
  int refresh_interval = 100;     // recompute K u every this many iterations (drift)
  // Stop as stalled when the best max |g| has not fallen by 1% over this many iterations.
  int stall_window = 400;
  // ... and only while the residual stays within this factor of its best: a residual that has
  // risen far above its best means the state is moving (e.g. a line that has started to glide),
  // not stagnating. Infinity: the window alone decides.
  double stall_band = std::numeric_limits<double>::infinity();

  // The settings a scene may give (keys "max_iterations", "memory", "max_displacement",
  // "refresh_interval", "stall_window"): common/settings.hpp. force_tolerance is set by the
  // caller per relaxation, stall_band is infinite unless a caller asks otherwise.
  static const settings::Table<StiffnessOptions>& settings();
  // Throws std::invalid_argument naming the violated constraint.
  void validate() const;
};

struct StiffnessResult {
  Termination termination = Termination::max_iterations;
  int iterations = 0;
  std::size_t stiffness_applications = 0;  // K and P applications (one FFT pair each)
  std::size_t interface_evaluations = 0;
  double max_force = 0.0;       // max |g_i| at the end
  double best_max_force = 0.0;  // lowest max |g_i| seen (the floor if stalled)
};

// Called every iteration with the current displacements; returning true stops the run with
// Termination::interrupted (e.g. a dislocation that has started to glide).
using StiffnessObserver = std::function<bool(int iteration, std::span<const double> u)>;

// Minimises from u in place. f_ext: the external force per unknown (size() entries).
StiffnessResult minimize_stiffness(StiffnessProblem& problem, std::span<const double> f_ext,
                                   std::vector<double>& u, const StiffnessOptions& options,
                                   const StiffnessObserver& observer = {});

}  // namespace asperity::minimize
