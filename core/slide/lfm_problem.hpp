// The lateral force model as a minimize::Problem: the unknowns are the in-plane displacements
// of the LFM's contact sites, the compliance is the free-boundary GF restricted to them
// (MODEL.md 2-3, SOLVERS.md "Free-boundary contact"). Over several processes (issue 26) each
// holds the contact sites of its rows of the block (the GF's local rows): the unknowns are
// theirs, the energy and the filter's mean stiffness those of every process.
#pragma once

#include <algorithm>
#include <numbers>
#include <vector>

#include "asperity/core/elastic/surface_gf.hpp"
#include "asperity/core/interface/lfm.hpp"
#include "asperity/core/minimize/problem.hpp"

namespace asperity::slide {

class LfmProblem final : public minimize::Problem {
 public:
  // comm: the processes over which gf's rows (and lfm's block) are spread; not owned.
  LfmProblem(elastic::FreeSurfaceGF& gf, const interface::LateralForceModel& lfm,
             const par::Comm& comm = par::serial())
      : gf_(gf), lfm_(lfm), comm_(comm) {}

  [[nodiscard]] std::size_t size() const override { return 2 * lfm_.contact_sites().size(); }

  // To be called by every process whenever the model's contact sites change (set_tip): where
  // this process's sites sit among every process's (rank order, x then y of each).
  void distribute() {
    const std::size_t m = lfm_.contact_sites().size();
    share_ = {.blocks = 2, .per_block = m, .offset = 0, .global_per_block = m};
    if (!comm_.distributed()) return;
    const std::vector<long long> counts = comm_.all_gather(static_cast<long long>(m));
    share_.global_per_block = 0;
    for (int r = 0; r < comm_.size(); ++r) {
      const auto c = static_cast<std::size_t>(counts[static_cast<std::size_t>(r)]);
      if (r < comm_.rank()) share_.offset += c;
      share_.global_per_block += c;
    }
  }
  [[nodiscard]] const par::Comm& comm() const override { return comm_; }
  // The contact sites row by row (minimize/problem.hpp): where each block row's sites start in
  // the list, and its size.
  [[nodiscard]] std::vector<std::size_t> runs() const override {
    const auto& sites = lfm_.contact_sites();
    const auto n0 = static_cast<std::size_t>(lfm_.block().shape.n0);
    const auto n1 = static_cast<std::size_t>(lfm_.block().shape.n1);
    std::vector<std::size_t> starts(n0 + 1, sites.size());
    for (std::size_t j = sites.size(); j-- > 0;)
      starts[sites[j] / n1] = j;
    for (std::size_t r = n0; r-- > 0;)  // a row without sites starts where the next one does
      starts[r] = std::min(starts[r], starts[r + 1]);
    return starts;
  }
  // Sums over the contact sites made row by row, as the minimisers' (runs()).
  template <class Term>
  [[nodiscard]] double row_sum(Term term) const {
    const auto& sites = lfm_.contact_sites();
    const auto n1 = static_cast<std::size_t>(lfm_.block().shape.n1);
    std::vector<double> rows(static_cast<std::size_t>(lfm_.block().shape.n0), 0.0);
    for (std::size_t j = 0; j < sites.size(); ++j)
      rows[sites[j] / n1] += term(j);
    return comm_.ordered_sum(rows);
  }
  // Two blocks (x, then y of every contact site); one process holds all of them.
  [[nodiscard]] minimize::Share share() const override {
    if (comm_.distributed()) return share_;
    const std::size_t m = lfm_.contact_sites().size();
    return {.blocks = 2, .per_block = m, .offset = 0, .global_per_block = m};
  }

  void compliance(std::span<const double> f, std::span<double> u) override {
    gf_.apply(lfm_.contact_sites(), f, u);
  }

  // The interface filter M = (I + c G)^-1 (FreeSurfaceGF::apply_filter) with c half the mean
  // in-registry stiffness of the contact sites, 2 pi tau_max d (MODEL.md 3: V_i'' at s = 0;
  // 2 pi tau_max d^2 / d_tip under a tip of another spacing, interface/tip_lattice.hpp).
  // Half, because the stiffness a relaxation sees is lower than in registry (sites away from
  // their wells, and at a slip front negative): on a = 80 d, R = 535 d, fractions 0.25, 0.5, 1
  // and 2 of the in-registry mean took 331, 291, 291 and 324 iterations through the slip
  // (675 unfiltered), and 0.5 was fastest overall (docs/solvers.md).
  static constexpr double filter_fraction = 0.5;
  // Automatic use from this a / b_core^0 on: the filter costs an FFT pair per iteration and
  // pays only where the contact is wide compared with its core width (measured: 15% slower at
  // a / b_core^0 = 6.2, break-even near 8 to 10, 1.7x faster at 21, 2.4x at 64).
  static constexpr double filter_from_a_over_bcore0 = 10.0;

  // The automatic choice for a scene (also what the benchmark compares against).
  [[nodiscard]] static bool filter_pays(const interface::ContactScene& scene) {
    return scene.a_over_bcore0() >= filter_from_a_over_bcore0;
  }

  [[nodiscard]] bool wants_filter(bool automatic) const override {
    return !automatic || filter_pays(lfm_.scene());
  }
  void filter(std::span<const double> r, std::span<double> w) override {
    const auto& sites = lfm_.contact_sites();
    const std::size_t m = sites.size();
    // The mean over the sites of every process: one stiffness for the whole (global) filter.
    const double tau = row_sum([&](std::size_t j) { return lfm_.tau_max()[sites[j]]; });
    const double d = lfm_.scene().d;
    const std::size_t m_all = comm_.distributed() ? share_.global_per_block : m;
    double c = m_all > 0
                   ? filter_fraction * 2.0 * std::numbers::pi * d * tau / static_cast<double>(m_all)
                   : 0.0;
    if (!lfm_.tip_frame().aligned()) c *= d / lfm_.tip_frame().spacing();
    gf_.apply_filter(sites, r, w, c);
  }

  double interface(std::span<const double> u, std::span<double> f_int) const override {
    thread_local std::vector<double> rows;
    rows.resize(static_cast<std::size_t>(lfm_.block().shape.n0));
    lfm_.energy_and_force_rows(u, f_int, rows, threads());
    return comm_.ordered_sum(rows);
  }
  void curvature(std::span<const double> u, std::span<double> h) const override {
    lfm_.curvature(u, h);
  }
  // A rotated tip couples the x and y of a site (unknowns j and m + j).
  [[nodiscard]] std::size_t curvature_coupling(std::span<const double> u,
                                               std::span<double> hxy) const override {
    return lfm_.curvature_coupling(u, hxy) ? lfm_.contact_sites().size() : 0;
  }
  [[nodiscard]] std::size_t gf_applications() const override { return gf_.applications(); }
  [[nodiscard]] int threads() const override { return gf_.threads(); }

 private:
  elastic::FreeSurfaceGF& gf_;
  const interface::LateralForceModel& lfm_;
  const par::Comm& comm_;
  minimize::Share share_;
};

}  // namespace asperity::slide
