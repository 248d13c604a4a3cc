// The lateral force model as a minimize::Problem: the unknowns are the in-plane displacements
// of the LFM's contact sites, the compliance is the free-boundary GF restricted to them
// (MODEL.md 2-3, SOLVERS.md "Free-boundary contact").
#pragma once

#include <vector>

#include "elastic/surface_gf.hpp"
#include "interface/lfm.hpp"
#include "minimize/problem.hpp"

namespace asperity::slide {

class LfmProblem final : public minimize::Problem {
 public:
  LfmProblem(elastic::FreeSurfaceGF& gf, const interface::LateralForceModel& lfm)
      : gf_(gf), lfm_(lfm), f_(gf.size(), 0.0), u_(gf.size(), 0.0) {}

  [[nodiscard]] std::size_t size() const override { return 2 * lfm_.contact_sites().size(); }

  void compliance(std::span<const double> f, std::span<double> u) override {
    const auto& sites = lfm_.contact_sites();
    const std::size_t m = sites.size(), n = lfm_.block().shape.count();
    for (std::size_t j = 0; j < m; ++j) {
      f_[sites[j]] = f[j];
      f_[n + sites[j]] = f[m + j];
    }
    gf_.apply(f_, u_);
    for (std::size_t j = 0; j < m; ++j) {
      u[j] = u_[sites[j]];
      u[m + j] = u_[n + sites[j]];
      f_[sites[j]] = f_[n + sites[j]] = 0.0;  // the scratch stays zero off the call
    }
  }

  double interface(std::span<const double> u, std::span<double> f_int) const override {
    return lfm_.energy_and_force(u, f_int);
  }
  void curvature(std::span<const double> u, std::span<double> h) const override {
    lfm_.curvature(u, h);
  }
  [[nodiscard]] std::size_t gf_applications() const override { return gf_.applications(); }

 private:
  elastic::FreeSurfaceGF& gf_;
  const interface::LateralForceModel& lfm_;
  std::vector<double> f_, u_;
};

}  // namespace asperity::slide
