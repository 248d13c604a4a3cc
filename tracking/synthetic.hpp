// Synthetic snapshots with known dislocation loops (MODEL.md section 7), for the tests and the
// benchmark of tracking/: elliptical slipped islands with a Peierls-Nabarro profile across
// their edges, on an optional Hertz-like contact, with optional registry offsets and noise.
//
// With h the signed distance to the union of the islands (negative inside), the slip is the
// Peierls-Nabarro arctangent sigma = 1/2 - atan(h / w) / pi (sigma = 1/2 exactly on the
// ellipses), the relative position s_x = X + slip_sign sigma d + e, with e a registry offset
// e = A sin(2 pi x / lambda) sin(2 pi y / lambda), and tau_x = -tau_max sin(2 pi s_x / d) as in
// the lateral force model (MODEL.md section 3). The cores lie on the ellipses wherever e = 0.
#pragma once

#include <cstdint>
#include <vector>

#include "lines.hpp"

namespace asperity::tracking {

struct Island {
  double cx = 0.0, cy = 0.0;  // centre (d)
  double ax = 1.0, ay = 1.0;  // semi-axes along x and y (d)
};

struct SyntheticOptions {
  LatticeBlock block{.shape = {64, 64}, .origin0 = -32, .origin1 = -32};  // the sites
  bool periodic = false;         // the block is a periodic cell (distances by minimum image)
  double contact_radius = 0.0;   // (d) contact disk around (0, 0); 0: every site in contact
  double tau_peak = 0.1;         // tau_max at the centre (G); sqrt(1 - r^2/a^2) profile on a disk
  double core_width = 2.0;       // Peierls-Nabarro half-width w (d)
  int slip_sign = -1;            // registry-index change inside the islands
  double registry_offset = 0.0;  // amplitude A of the registry offset e (d), |A| < 0.5
  double offset_wavelength = 16.0;  // lambda (d)
  double noise_s = 0.0;             // standard deviation of Gaussian noise added to s_x (d)
  double noise_tau = 0.0;  // standard deviation of noise added to tau_x (fraction of tau_max)
  std::uint32_t seed = 1;  // of the noise

  void validate() const;  // throws std::invalid_argument naming the violated constraint
};

struct SyntheticField {
  LatticeBlock block;
  bool periodic = false;
  std::vector<double> sx, tau_x, tau_max;
  std::vector<std::uint8_t> in_contact;

  FieldView view() const;
};

SyntheticField synthetic_field(const SyntheticOptions& options, const std::vector<Island>& islands);

}  // namespace asperity::tracking
