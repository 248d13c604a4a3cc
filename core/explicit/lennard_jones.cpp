// Repulsive Lennard-Jones interface potential, MODEL.md section 4; equations in the header.
#include "asperity/core/explicit/lennard_jones.hpp"

#include <cmath>

#include "asperity/core/common/validate.hpp"

namespace asperity::explicit_model {

LennardJones::LennardJones(double eps, double sigma)
    : eps_(eps), sigma_(sigma), rc_(std::pow(2.0, 1.0 / 6.0) * sigma) {
  require_positive("LennardJones.eps", eps);
  require_positive("LennardJones.sigma", sigma);
}

LennardJones LennardJones::in_substrate_units(double G_eps_sigma3, double sigma_over_d, double d) {
  require_positive("LennardJones G (eps/sigma^3)", G_eps_sigma3);
  require_positive("LennardJones sigma/d", sigma_over_d);
  // eps = (G sigma^3 / G_eps_sigma3) with sigma = sigma_over_d d and G = 1 (the stress unit).
  const double sigma = sigma_over_d * d;
  return {sigma * sigma * sigma / G_eps_sigma3, sigma};
}

}  // namespace asperity::explicit_model
