// An energy minimisation problem in the pair representation of SOLVERS.md: the unknowns are
// displacements u of the sites that carry interface forces, the elastic energy is
// 1/2 u.K u with K the inverse of the (restricted) surface Green's function G, and K is never
// applied: the solver carries the pair (u, f) with u = G f, so that
//   energy   Pi = 1/2 f.u + V(u),
//   gradient r  = f - f_int(u),       f_int = -dV/du (the interface force),
// and the G-preconditioned direction -G r costs one GF application, its K-image -r nothing.
#pragma once

#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

#include "asperity/core/common/comm.hpp"

namespace asperity::minimize {

// Where a process's unknowns sit among those of every process (issue 26: a problem distributed
// over ranks). The unknowns come in `blocks` equal blocks (the components of the sites: x of
// every site, then y), and each process holds a contiguous run of every block: its unknown
// b * per_block + j is the global unknown b * global_per_block + offset + j. One process holds
// everything: blocks = 1, per_block = global_per_block = size(), offset = 0.
struct Share {
  std::size_t blocks = 1, per_block = 0, offset = 0, global_per_block = 0;
  [[nodiscard]] std::size_t global_size() const { return blocks * global_per_block; }
  [[nodiscard]] std::size_t global_index(std::size_t i) const {
    return (i / per_block) * global_per_block + offset + i % per_block;
  }
};

class Problem {
 public:
  virtual ~Problem() = default;

  // Number of unknowns (sites x components).
  [[nodiscard]] virtual std::size_t size() const = 0;

  // u = G f on the unknowns: one Green's function application.
  virtual void compliance(std::span<const double> f, std::span<double> u) = 0;

  // Interface energy V(u); writes the interface force f_int = -dV/du.
  virtual double interface(std::span<const double> u, std::span<double> f_int) const = 0;

  // Diagonal of the interface Hessian d2V/du2 (the interface couples no two sites).
  virtual void curvature(std::span<const double> u, std::span<double> h) const = 0;

  // Couplings of the interface Hessian between two components of one site, where the interface
  // has them (the lateral force model under a rotated tip: interface/tip_lattice.hpp): unknowns
  // j and j + stride, j < stride, are coupled by d2V/du_j du_(j+stride) = hxy[j]. Returns the
  // stride, having written stride values to hxy (which has size() values); 0, writing nothing:
  // the interface Hessian is the diagonal of curvature().
  [[nodiscard]] virtual std::size_t curvature_coupling(std::span<const double> u,
                                                       std::span<double> hxy) const {
    (void)u, (void)hxy;
    return 0;
  }

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

  // The processes the unknowns are spread over (issue 26): the minimisers reduce their dot
  // products, norms and maxima over them, and interface() returns the energy of every
  // process's sites. Serial: one process.
  [[nodiscard]] virtual const par::Comm& comm() const { return par::serial(); }
  // This process's part of the unknowns (see Share); what makes the minimisers' index-dependent
  // start vectors and random pushes the same on any number of processes.
  [[nodiscard]] virtual Share share() const {
    return {.blocks = 1, .per_block = size(), .offset = 0, .global_per_block = size()};
  }

  // Where each run of unknowns starts within one block of them (Share), and, last, the size of
  // a block: the rows of a problem on a block of lattice sites (the unknowns of each row are
  // contiguous). The minimisers' sums are made run by run and the partials added in order
  // (minimize/kernels.hpp), so that they do not depend on how the rows are spread over
  // processes. Empty: no runs (one sum per process).
  [[nodiscard]] virtual std::vector<std::size_t> runs() const { return {}; }

  // Threads the solver may use for its element-wise vector passes (those are bit for bit the
  // same on any number of threads; its sums stay serial): the threads of the problem's FFTs.
  [[nodiscard]] virtual int threads() const { return 1; }
};

// The interface Hessian of a problem at u (curvature() and curvature_coupling()), for the
// stability checks, the Newton-Krylov finish and the flow's spectral radius. Without couplings
// the callers keep their diagonal arithmetic (coupled() false), bit for bit as before.
class InterfaceHessian {
 public:
  void at(const Problem& p, std::span<const double> u) {
    h_.resize(p.size());
    hxy_.resize(p.size());
    p.curvature(u, h_);
    stride_ = p.curvature_coupling(u, hxy_);
  }
  [[nodiscard]] bool coupled() const { return stride_ > 0; }
  [[nodiscard]] const std::vector<double>& diagonal() const { return h_; }
  // out = H v.
  void apply(std::span<const double> v, std::span<double> out) const {
    for (std::size_t i = 0; i < h_.size(); ++i)
      out[i] = h_[i] * v[i];
    for (std::size_t j = 0; j < stride_; ++j) {
      out[j] += hxy_[j] * v[j + stride_];
      out[j + stride_] += hxy_[j] * v[j];
    }
  }
  // Whether H is positive semi-definite: every diagonal element and, where coupled, every
  // 2 x 2 block (h_jj h_kk >= h_jk^2). This process's part (a distributed problem's caller
  // combines the processes' answers).
  [[nodiscard]] bool positive_semidefinite() const {
    if (h_.empty()) return true;
    if (*std::min_element(h_.begin(), h_.end()) < 0.0) return false;
    for (std::size_t j = 0; j < stride_; ++j) {
      if (h_[j] * h_[j + stride_] < hxy_[j] * hxy_[j]) return false;
    }
    return true;
  }

 private:
  std::vector<double> h_, hxy_;
  std::size_t stride_ = 0;
};

}  // namespace asperity::minimize
