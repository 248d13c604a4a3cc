// Isotropic linear-elastic substrate (MODEL.md section 1).
#pragma once

#include "asperity/core/common/settings.hpp"

namespace asperity::elastic {

struct Material {
  double G = 1.0;   // shear modulus (unit of stress); > 0
  double nu = 0.5;  // Poisson ratio; in [0, 0.5] (negative ratios are not modelled here)

  // E* = 2 G / (1 - nu), the contact modulus of a rigid body on this half-space (MODEL.md 1).
  [[nodiscard]] double contact_modulus() const { return 2.0 * G / (1.0 - nu); }

  // The settings (keys "G", "nu"): common/settings.hpp.
  static const settings::Table<Material>& settings();
  // Throws std::invalid_argument naming the violated constraint.
  void validate() const;
};

// Which displacement/force components a Green's function couples.
enum class Components {
  in_plane,  // (x, y): the lateral force model and the Peierls cell
  normal,    // (z): frictionless normal contact
  full,      // (x, y, z): the explicit model; x,y and z couple through (1 - 2 nu)
};

[[nodiscard]] int component_count(Components c);
// Cartesian axis (0 = x, 1 = y, 2 = z) of component slot k of a field with components c.
[[nodiscard]] int component_axis(Components c, int k);

}  // namespace asperity::elastic
