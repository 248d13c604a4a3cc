// Bonded (no-slip) contact: the sites in a mask are held at prescribed displacements and the
// forces that hold them are found, u = G * f on the mask (MODEL.md section 2: the bonded rigid
// disk, k = 8 G a / (2 - nu), tau(r) = Fx / (2 pi a^2) (1 - r^2/a^2)^-1/2). G restricted to the
// mask is symmetric positive definite, so the system is solved by conjugate gradients (Eigen's,
// matrix-free, one GF application per iteration).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "asperity/core/common/settings.hpp"
#include "asperity/core/common/termination.hpp"
#include "asperity/core/elastic/surface_gf.hpp"

namespace asperity::contact {

struct BondedOptions {
  double tolerance = 1e-10;   // relative residual |G f - u| / |u| on the mask
  int max_iterations = 5000;  // CG iteration cap

  // The settings (keys "tolerance", "max_iterations"): common/settings.hpp.
  static const settings::Table<BondedOptions>& settings();
  void validate() const;  // throws std::invalid_argument naming the violated constraint
};

struct BondedResult {
  std::vector<double> force;         // per site and component, like the GF's fields; 0 off mask
  std::vector<double> displacement;  // G * force everywhere in the region
  double energy = 0.0;               // 1/2 f.u
  int iterations = 0;
  double residual = 0.0;  // relative residual reached
  std::size_t gf_applications = 0;
  Termination termination = Termination::max_iterations;
};

// mask: one entry per site of gf.region() (non-zero: bonded); prescribed: a field of gf.size()
// values, read on the mask only.
BondedResult solve_bonded(elastic::FreeSurfaceGF& gf, std::span<const std::uint8_t> mask,
                          std::span<const double> prescribed, const BondedOptions& options = {});

}  // namespace asperity::contact
