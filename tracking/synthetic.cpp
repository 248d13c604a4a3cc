// Synthetic snapshots with known dislocation loops (MODEL.md section 7); see synthetic.hpp.
#include "synthetic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "asperity/core/common/validate.hpp"

namespace asperity::tracking {

void SyntheticOptions::validate() const {
  if (block.shape.n0 < 2 || block.shape.n1 < 2) {
    reject("SyntheticOptions.block.shape",
           std::to_string(block.shape.n0) + " x " + std::to_string(block.shape.n1),
           "at least 2 x 2");
  }
  if (!std::isfinite(contact_radius) || contact_radius < 0.0) {
    reject("SyntheticOptions.contact_radius", std::to_string(contact_radius), "finite and >= 0");
  }
  require_positive("SyntheticOptions.tau_peak", tau_peak);
  require_positive("SyntheticOptions.core_width", core_width);
  if (slip_sign != -1 && slip_sign != 1) {
    reject("SyntheticOptions.slip_sign", std::to_string(slip_sign), "-1 or +1");
  }
  if (!(std::abs(registry_offset) < 0.5)) {
    reject("SyntheticOptions.registry_offset", std::to_string(registry_offset), "|A| < 0.5");
  }
  require_positive("SyntheticOptions.offset_wavelength", offset_wavelength);
  if (!(noise_s >= 0.0 && noise_s < 0.5)) {
    reject("SyntheticOptions.noise_s", std::to_string(noise_s), ">= 0 and < 0.5");
  }
  if (!(noise_tau >= 0.0 && noise_tau < 1.0)) {
    reject("SyntheticOptions.noise_tau", std::to_string(noise_tau), ">= 0 and < 1");
  }
}

FieldView SyntheticField::view() const {
  return FieldView{.block = block,
                   .d = 1.0,
                   .periodic = periodic,
                   .sx = sx,
                   .tau_x = tau_x,
                   .tau_max = tau_max,
                   .in_contact = in_contact};
}

namespace {

// Signed distance to an ellipse to first order, g / |grad g| with g = sqrt(q) - 1: exact on the
// ellipse, which is all the cores need.
double ellipse_distance(double dx, double dy, const Island& e) {
  const double ux = dx / e.ax, uy = dy / e.ay;
  const double r = std::hypot(ux, uy);
  if (r < 1e-12) return -std::min(e.ax, e.ay);
  const double gx = ux / e.ax, gy = uy / e.ay;
  return (r - 1.0) * r / std::hypot(gx, gy);
}

}  // namespace

SyntheticField synthetic_field(const SyntheticOptions& o, const std::vector<Island>& islands) {
  o.validate();
  SyntheticField f;
  f.block = o.block;
  f.periodic = o.periodic;
  const std::size_t n = o.block.shape.count();
  f.sx.assign(n, 0.0);
  f.tau_x.assign(n, 0.0);
  f.tau_max.assign(n, 0.0);
  f.in_contact.assign(n, 0);
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double L0 = o.block.shape.n0, L1 = o.block.shape.n1;
  constexpr double pi = std::numbers::pi;
  for (int i0 = 0; i0 < o.block.shape.n0; ++i0) {
    for (int i1 = 0; i1 < o.block.shape.n1; ++i1) {
      const std::size_t s = o.block.shape.index(i0, i1);
      const double x = o.block.x(i0, 1.0), y = o.block.y(i1, 1.0);
      double h = std::numeric_limits<double>::infinity();
      for (const Island& e : islands) {
        double dx = x - e.cx, dy = y - e.cy;
        if (o.periodic) {
          dx -= image_offset(dx, L0);
          dy -= image_offset(dy, L1);
        }
        h = std::min(h, ellipse_distance(dx, dy, e));
      }
      const double sigma = std::isfinite(h) ? 0.5 - std::atan(h / o.core_width) / pi : 0.0;
      const double offset = o.registry_offset * std::sin(2.0 * pi * x / o.offset_wavelength) *
                            std::sin(2.0 * pi * y / o.offset_wavelength);
      double tau_max = o.tau_peak;
      if (o.contact_radius > 0.0) {
        const double rho2 = (x * x + y * y) / (o.contact_radius * o.contact_radius);
        tau_max = rho2 < 1.0 ? o.tau_peak * std::sqrt(1.0 - rho2) : 0.0;
      }
      double sx = x + o.slip_sign * sigma + offset;
      if (o.noise_s > 0.0) sx += o.noise_s * normal(rng);
      double tau = -tau_max * std::sin(2.0 * pi * sx);
      if (o.noise_tau > 0.0) tau += o.noise_tau * tau_max * normal(rng);
      f.sx[s] = sx;
      f.tau_x[s] = tau;
      f.tau_max[s] = tau_max;
      f.in_contact[s] = tau_max > 0.0 ? 1 : 0;
    }
  }
  return f;
}

}  // namespace asperity::tracking
