// Hertz contact of a rigid sphere on the elastic half-space (MODEL.md section 1):
//   a^3 = 3 Fz R / (4 E*),  p0 = 3 Fz / (2 pi a^2) = 2 a E* / (pi R),
//   p(r) = p0 sqrt(1 - r^2/a^2) for r < a, else 0,  approach delta = a^2 / R;
// the surface deflection (Johnson, Contact Mechanics, 3.41-3.42) and the Cattaneo-Mindlin
// traction under a tangential load (Johnson 7.2).
#pragma once

#include "asperity/core/elastic/material.hpp"

namespace asperity::contact {

struct Hertz {
  double R = 0.0;         // sphere radius, length
  double a = 0.0;         // contact radius, length
  double load = 0.0;      // Fz, force
  double p0 = 0.0;        // peak pressure, stress
  double approach = 0.0;  // delta, length
  double estar = 0.0;     // contact modulus E*, stress

  // Both throw std::invalid_argument unless R, a (or load) are finite and > 0.
  static Hertz from_radius(const elastic::Material& m, double R, double a);
  static Hertz from_load(const elastic::Material& m, double R, double load);

  [[nodiscard]] double pressure(double r) const;  // p(r), stress
  // Surface deflection w(r) = -u_z (length): delta - r^2/(2R) inside; outside
  // [(2 a^2 - r^2) asin(a/r) + a r sqrt(1 - a^2/r^2)] / (pi R) (continuous at r = a, where both
  // give a^2/(2R), and ~ a^3 / (r R) far away).
  [[nodiscard]] double deflection(double r) const;
};

// c in the control parameter of the lateral force model, a / b_core^0 = c alpha a^2 / (R d)
// (MODEL.md 3): c = 2 E* / (pi G) = 4 / (pi (1 - nu)), 8/pi at nu = 0.5.
double bcore_factor(double nu);

// Cattaneo-Mindlin tangential traction of a Hertz contact under Q = mu Fz with local friction
// coefficient alpha (Johnson 7.2), over alpha p0, at rho = r/a: sqrt(1 - rho^2) in the slip
// annulus, minus sqrt(c^2 - rho^2) inside the stick zone rho < c (Johnson's
// (c/a) p0 sqrt(1 - r^2/c^2)), c = (1 - mu/alpha)^(1/3) in units of a; 0 outside the contact.
// It carries Q = (2 pi/3) a^2 alpha p0 (1 - c^3) = mu Fz.
double cattaneo_mindlin(double rho, double mu_over_alpha);

}  // namespace asperity::contact
