// Frictionless normal contact of a rigid indenter on the free-boundary half-space.
//
// Solves the linear complementarity problem (MODEL.md sections 1-2, Hertz check):
//   w = G_zz * P,  gap_i = h_i + w_i - delta >= 0,  P_i >= 0,  P_i gap_i = 0,  sum_i P_i = W,
// for the compressive atomic forces P, the deflection w (into the substrate) and the approach
// delta, with the constrained conjugate-gradient method of Polonsky & Keer (Wear 231, 1999),
// load-controlled variant.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "asperity/core/common/settings.hpp"
#include "asperity/core/common/termination.hpp"
#include "asperity/core/elastic/surface_gf.hpp"

namespace asperity::contact {

struct NormalContactOptions {
  double tolerance = 1e-12;    // stop when sum_i |P_i^new - P_i^old| / W falls below this
  int max_iterations = 20000;  // cap on CG iterations (each costs one GF application)

  // The settings (keys "tolerance", "max_iterations"): common/settings.hpp.
  static const settings::Table<NormalContactOptions>& settings();
  void validate() const;  // throws std::invalid_argument naming the violated constraint
};

struct NormalContactResult {
  std::vector<double> force;       // compressive normal force per site (>= 0), units of force
  std::vector<double> deflection;  // w = -u_z per site (> 0 into the substrate), length
  std::vector<double> gap;         // gap_i = h_i + w_i - delta (>= 0), length
  double approach = 0.0;           // delta: rigid-body approach of the indenter, length
  double load = 0.0;               // sum of forces (equals the requested load)
  std::size_t contact_sites = 0;   // sites with P > 0
  double max_penetration = 0.0;    // max(-gap) over all sites (should be ~ 0), length
  int iterations = 0;
  double residual = 0.0;  // last relative force change
  std::size_t gf_applications = 0;
  Termination termination = Termination::max_iterations;
};

// gf must have Components::normal; heights h (one per site of gf.region()) is the indenter
// profile above its lowest point; load W > 0.
NormalContactResult solve_normal_contact(elastic::FreeSurfaceGF& gf,
                                         std::span<const double> heights, double load,
                                         const NormalContactOptions& options = {});

}  // namespace asperity::contact
