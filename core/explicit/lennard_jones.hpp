// The interface potential of the explicit atomistic model (MODEL.md section 4): purely repulsive
// Lennard-Jones, cut and shifted at its minimum,
//   V(r) = 4 eps ((sigma/r)^12 - (sigma/r)^6) + eps   for r < r_c = 2^(1/6) sigma, else 0,
// so V, V' are continuous at r_c (V'' jumps there, from 57.1 eps/sigma^2 to 0).
//   V'(r)/r = 24 eps ((sigma/r)^6 - 2 (sigma/r)^12) / r^2,
//   V''(r)  = 4 eps (156 (sigma/r)^12 - 42 (sigma/r)^6) / r^2.
// The contact simulator works in units of d (length) and G (stress): eps is then G d^3 times
// (sigma/d)^3 / (G sigma^3/eps), see in_substrate_units().
#pragma once

#include <cmath>

namespace asperity::explicit_model {

struct PairTerms {
  double v = 0.0;     // V(r)
  double dv_r = 0.0;  // V'(r) / r (negative: repulsion)
  double d2v = 0.0;   // V''(r)
};

class LennardJones {
 public:
  // eps: energy; sigma: length (any consistent units). Throws std::invalid_argument unless both
  // are finite and > 0.
  LennardJones(double eps, double sigma);

  // The scaled potential of a scene: lengths in d, energies in G d^3. G_eps_sigma3 is the
  // substrate shear modulus in eps/sigma^3, sigma_over_d the LJ length in lattice spacings.
  static LennardJones in_substrate_units(double G_eps_sigma3, double sigma_over_d, double d = 1.0);

  [[nodiscard]] double eps() const { return eps_; }
  [[nodiscard]] double sigma() const { return sigma_; }
  [[nodiscard]] double cutoff() const { return rc_; }
  [[nodiscard]] double cutoff2() const { return rc_ * rc_; }

  // Terms at squared distance r2 (zero at and beyond the cutoff).
  [[nodiscard]] PairTerms at(double r2) const {
    if (r2 >= rc_ * rc_) return {};
    const double s2 = sigma_ * sigma_ / r2;
    const double s6 = s2 * s2 * s2;
    const double s12 = s6 * s6;
    return {.v = 4.0 * eps_ * (s12 - s6) + eps_,
            .dv_r = 24.0 * eps_ * (s6 - 2.0 * s12) / r2,
            .d2v = 4.0 * eps_ * (156.0 * s12 - 42.0 * s6) / r2};
  }

 private:
  double eps_, sigma_, rc_;
};

}  // namespace asperity::explicit_model
