// The analytic checks every surface Green's function must pass (MODEL.md section 2), as
// functions returning plain structs: used by the analytic tests and by the gf_validate tool.
//
// - Hertz (MODEL.md 1): a rigid sphere z = R - sqrt(R^2 - r^2) pressed with the Hertz load of a
//   contact radius a: numerical contact radius d sqrt(N_contact/pi), approach, pressure.
// - Bonded rigid disk: sites with |X| < a held at u_x = delta; k = Fx/delta against
//   8 G a_eff/(2 - nu) with a_eff = d sqrt(N/pi), and the ring-averaged shear traction against
//   Fx/(2 pi a_eff^2) (1 - r^2/a_eff^2)^(-1/2).
// - Far field: the response to a unit force on one patch against the point-force solution.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "asperity/core/common/shape.hpp"
#include "asperity/core/common/termination.hpp"
#include "asperity/core/contact/bonded.hpp"
#include "asperity/core/contact/hertz.hpp"
#include "asperity/core/contact/normal_contact.hpp"
#include "asperity/core/fft/fft_engine.hpp"

namespace asperity::validation {

struct HertzCheck {
  contact::Hertz exact;             // the analytic solution at the requested a
  double contact_radius = 0.0;      // d sqrt(N_contact / pi)
  double radius_error = 0.0;        // contact_radius / a - 1
  double approach_error = 0.0;      // approach / (a^2/R) - 1
  double pressure_error = 0.0;      // max |p - p_Hertz| over r < 0.95 a, stress
  std::vector<double> r, pressure;  // per site of the block: distance, numerical pressure
  Shape2 block, fft_grid;
  contact::NormalContactResult solve;
  double wall_s = 0.0;
};

struct BondedDiskCheck {
  double radius = 0.0;           // a_eff = d sqrt(N / pi)
  double stiffness = 0.0;        // Fx / delta, units of G d
  double stiffness_exact = 0.0;  // 8 G a_eff / (2 - nu)
  double stiffness_error = 0.0;  // relative
  // Rings of width ring_width: mean radius, mean traction and the closed form there, both in
  // units of Fx / (2 pi a_eff^2). Rings reach out to 0.7 a_eff (traction_error) and, for the
  // figure, beyond (all rings inside the disk are listed).
  double ring_width = 2.0;
  std::vector<double> ring_r, ring_traction, ring_exact;
  double traction_error = 0.0;  // max relative ring error for r <= 0.7 a_eff
  Shape2 block, fft_grid;
  contact::BondedResult solve;
  double wall_s = 0.0;
};

struct FarFieldCheck {
  // Samples along x (axis 0) and along the diagonal: distance, patch response u_k per unit
  // force F_k for k = x, z, and the point-force solution.
  struct Sample {
    double r = 0.0;
    bool diagonal = false;
    double ux_patch = 0.0, ux_point = 0.0, uz_patch = 0.0, uz_point = 0.0;
  };
  std::vector<Sample> samples;
  double worst_scaled_error = 0.0;  // max |patch - point| / |point| * r^2 / d^2
  Shape2 block, fft_grid;
  double wall_s = 0.0;
};

HertzCheck check_hertz(const elastic::Material& m, double R, double a,
                       const contact::NormalContactOptions& options = {},
                       const fft::FFTOptions& fft = {});
BondedDiskCheck check_bonded_disk(const elastic::Material& m, double a,
                                  const contact::BondedOptions& options = {},
                                  const fft::FFTOptions& fft = {});
FarFieldCheck check_far_field(const elastic::Material& m, int max_distance,
                              const fft::FFTOptions& fft = {});

}  // namespace asperity::validation
