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

  // Optional interface filter M, an approximation of (I + D G)^-1 with D the interface
  // stiffness: preconditioned directions become du = G M r, whose K-image is M r, so the pair
  // stays exact at one extra filter pass per direction. Where the interface is much stiffer
  // than the elastic half-space over the contact (long wavelengths of a pinned contact), the
  // G-preconditioned operator I + G H has a condition number of order a / b_core and the
  // filter removes most of it (docs/solvers.md).
  // wants_filter(automatic): whether filter() should be used; automatic = true asks for the
  // problem's own judgement of whether it pays, false for whether it has one at all.
  [[nodiscard]] virtual bool wants_filter(bool automatic) const {
    (void)automatic;
    return false;
  }
  // w = M r; called only if wants_filter() said yes.
  virtual void filter(std::span<const double> r, std::span<double> w) { (void)r, (void)w; }

  // Green's function applications so far (the unit of cost).
  [[nodiscard]] virtual std::size_t gf_applications() const = 0;

  // Threads the solver may use for its element-wise vector passes (those are bit for bit the
  // same on any number of threads; its sums stay serial): the threads of the problem's FFTs.
  [[nodiscard]] virtual int threads() const { return 1; }
};

}  // namespace asperity::minimize
