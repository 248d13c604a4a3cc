// The local friction coefficient alpha of the explicit model's interface potential (MODEL.md
// section 4): one atom pushed with a fixed normal force Fz onto a rigid square lattice (spacing d,
// plane z = 0, atoms at (i, j) d) through the repulsive Lennard-Jones potential of
// lennard_jones.hpp, moved along x from one hollow site, (d/2, d/2), over the bridge site,
// (d, d/2), to the next hollow site. The line y = d/2 is a mirror line of the lattice, so the
// force along y vanishes on it, and hollow -> bridge -> hollow is the minimum-energy path.
//
// At each x the height z(x) solves the normal balance  dV/dz (x, z) = -Fz  on the branch with
// d2V/dz2 > 0 (V = sum over lattice atoms within the cutoff). Along the path:
//   slope        z'(x) = -V_xz / V_zz                     (implicit differentiation, exact)
//   lateral force  Fx(x) = V_x                             (what holds the atom at x)
//   enthalpy     H(x) = V + Fz z,  dH/dx = Fx              (the barrier is H(bridge) - H(hollow))
// alpha = max_x z'(x), the largest slope of the height profile (MODEL.md 4); alpha_force =
// max_x Fx/Fz is reported too: the two agree for a hard-sphere contact, where the force is normal
// to the (iso-energy) surface, and differ for a soft one by how far the height profile at fixed
// force departs from an iso-energy surface.
#pragma once

#include <vector>

#include "asperity/core/common/settings.hpp"

namespace asperity::explicit_model {

struct AlphaPathOptions {
  double sigma_over_d = 0.8908987181403393;  // LJ sigma in lattice spacings (2^(-1/6): d = r_c)
  double normal_force = 1.0;                 // Fz, eps/sigma
  int samples = 401;  // points along x over one period d (odd, so that the bridge is one)

  // The settings (keys "sigma_over_d", "normal_force", "samples"): common/settings.hpp.
  static const settings::Table<AlphaPathOptions>& settings();
  // Throws std::invalid_argument naming the violated constraint.
  void validate() const;
};

struct AlphaPath {
  // Per sample, x from the hollow site (0) over the bridge (d/2) to the next hollow site (d):
  std::vector<double> x;                            // d
  std::vector<double> height;                       // z above the lattice plane, d
  std::vector<double> slope;                        // dz/dx
  std::vector<double> lateral;                      // Fx = dV/dx, eps/sigma
  std::vector<double> enthalpy;                     // H = V + Fz z, eps
  double alpha = 0.0;                               // max slope
  double x_at_alpha = 0.0;                          // where it is reached, d
  double alpha_force = 0.0;                         // max Fx / Fz
  double barrier = 0.0;                             // H(bridge) - H(hollow), eps
  double height_hollow = 0.0, height_bridge = 0.0;  // d
  // Check of the slope: |integral of z' from hollow to bridge - rise of z| / rise.
  double slope_check = 0.0;
};

// Throws std::invalid_argument for bad options and std::runtime_error if the normal balance has
// no solution (a force beyond what the lattice can hold at that point).
AlphaPath alpha_path(const AlphaPathOptions& options);

}  // namespace asperity::explicit_model
