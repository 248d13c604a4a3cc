// The lateral force model as a minimize::Problem: the unknowns are the in-plane displacements
// of the LFM's contact sites, the compliance is the free-boundary GF restricted to them
// (MODEL.md 2-3, SOLVERS.md "Free-boundary contact").
#pragma once

#include <numbers>

#include "asperity/core/elastic/surface_gf.hpp"
#include "asperity/core/interface/lfm.hpp"
#include "asperity/core/minimize/problem.hpp"

namespace asperity::slide {

class LfmProblem final : public minimize::Problem {
 public:
  LfmProblem(elastic::FreeSurfaceGF& gf, const interface::LateralForceModel& lfm)
      : gf_(gf), lfm_(lfm) {}

  [[nodiscard]] std::size_t size() const override { return 2 * lfm_.contact_sites().size(); }

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
    double tau = 0.0;
    for (std::size_t j = 0; j < m; ++j)
      tau += lfm_.tau_max()[sites[j]];
    const double d = lfm_.scene().d;
    double c =
        m > 0 ? filter_fraction * 2.0 * std::numbers::pi * d * tau / static_cast<double>(m) : 0.0;
    if (!lfm_.tip_frame().aligned()) c *= d / lfm_.tip_frame().spacing();
    gf_.apply_filter(sites, r, w, c);
  }

  double interface(std::span<const double> u, std::span<double> f_int) const override {
    return lfm_.energy_and_force(u, f_int, threads());
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
};

}  // namespace asperity::slide
