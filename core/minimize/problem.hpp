// An energy minimisation problem in the pair representation of SOLVERS.md: the unknowns are
// displacements u of the sites that carry interface forces, the elastic energy is
// 1/2 u.K u with K the inverse of the (restricted) surface Green's function G, and K is never
// applied: the solver carries the pair (u, f) with u = G f, so that
//   energy   Pi = 1/2 f.u + V(u),
//   gradient r  = f - f_int(u),       f_int = -dV/du (the interface force),
// and the G-preconditioned direction -G r costs one GF application, its K-image -r nothing.
#pragma once

#include <cstddef>
#include <span>

namespace asperity::minimize {

class Problem {
 public:
  virtual ~Problem() = default;

  // Number of unknowns (sites x components).
  [[nodiscard]] virtual std::size_t size() const = 0;

  // u = G f on the unknowns: one Green's function application.
  virtual void compliance(std::span<const double> f, std::span<double> u) = 0;

  // Interface energy V(u); writes the interface force f_int = -dV/du.
  virtual double interface(std::span<const double> u, std::span<double> f_int) const = 0;

  // Diagonal of the interface Hessian d2V/du2 (the interface couples no two unknowns).
  virtual void curvature(std::span<const double> u, std::span<double> h) const = 0;

  // Green's function applications so far (the unit of cost).
  [[nodiscard]] virtual std::size_t gf_applications() const = 0;
};

}  // namespace asperity::minimize
