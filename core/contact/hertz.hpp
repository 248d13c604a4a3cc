// Hertz contact of a rigid sphere on the elastic half-space (MODEL.md section 1):
//   a^3 = 3 Fz R / (4 E*),  p0 = 3 Fz / (2 pi a^2) = 2 a E* / (pi R),
//   p(r) = p0 sqrt(1 - r^2/a^2) for r < a, else 0,  approach delta = a^2 / R.
#pragma once

#include "elastic/material.hpp"

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
};

}  // namespace asperity::contact
