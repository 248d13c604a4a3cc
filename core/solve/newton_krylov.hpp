// Newton-Krylov solution of F(x) = 0 with matrix-free Jacobian products: a small interface over
// SUNDIALS KINSOL (inexact Newton, GMRES, optional line search). Physics code never sees an
// N_Vector; it passes the residual and the Jacobian-vector product as functions.
#pragma once

#include <functional>
#include <span>

#include "asperity/core/common/termination.hpp"

namespace asperity::solve {

struct NewtonKrylovOptions {
  double tolerance = 1e-10;   // stop when max |F_i| <= tolerance (units of F)
  int max_iterations = 50;    // Newton iterations
  int krylov_dimension = 60;  // GMRES subspace size (restarts beyond it)
  bool line_search = true;    // KINSOL's globalising line search on |F|^2

  void validate() const;  // throws std::invalid_argument naming the violated constraint
};

struct NewtonKrylovResult {
  Termination termination = Termination::max_iterations;
  int iterations = 0;             // Newton iterations
  long linear_iterations = 0;     // GMRES iterations (one Jacobian product each)
  long function_evaluations = 0;  // residual evaluations
  double residual = 0.0;          // max |F_i| at the end
  int flag = 0;                   // KINSOL's return flag, for diagnostics
};

using Residual = std::function<void(std::span<const double> x, std::span<double> F)>;
// Jv = J(x) v.
using JacobianTimes =
    std::function<void(std::span<const double> x, std::span<const double> v, std::span<double> Jv)>;

// Solves in place from the initial guess in x.
NewtonKrylovResult newton_krylov(std::span<double> x, const Residual& residual,
                                 const JacobianTimes& jacobian_times,
                                 const NewtonKrylovOptions& options = {});

}  // namespace asperity::solve
