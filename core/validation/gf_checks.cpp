// Analytic GF checks of MODEL.md sections 1-2; formulas in gf_checks.hpp.
#include "asperity/core/validation/gf_checks.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "asperity/core/elastic/influence.hpp"
#include "asperity/core/elastic/surface_gf.hpp"

namespace asperity::validation {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

HertzCheck check_hertz(const elastic::Material& m, double R, double a,
                       const contact::NormalContactOptions& options, const fft::FFTOptions& fft) {
  const auto t0 = std::chrono::steady_clock::now();
  HertzCheck c;
  c.exact = contact::Hertz::from_radius(m, R, a);
  // The block must hold the whole contact: 25% margin beyond the Hertz radius.
  const LatticeBlock block = LatticeBlock::centred_disk(1.25 * a);
  elastic::FreeSurfaceGF gf(m, elastic::Components::normal, block.shape, 1.0, fft);
  c.block = block.shape;
  c.fft_grid = gf.fft_shape();
  std::vector<double> h(gf.size());
  c.r.resize(gf.size());
  for (int i0 = 0; i0 < block.shape.n0; ++i0) {
    for (int i1 = 0; i1 < block.shape.n1; ++i1) {
      const std::size_t i = block.shape.index(i0, i1);
      c.r[i] = std::hypot(block.x(i0, 1.0), block.y(i1, 1.0));
      h[i] = R - std::sqrt(R * R - c.r[i] * c.r[i]);
    }
  }
  c.solve = contact::solve_normal_contact(gf, h, c.exact.load, options);
  c.pressure = c.solve.force;  // d = 1: force per site is the pressure
  c.contact_radius = std::sqrt(static_cast<double>(c.solve.contact_sites) / std::numbers::pi);
  c.radius_error = c.contact_radius / a - 1.0;
  c.approach_error = c.solve.approach / c.exact.approach - 1.0;
  for (std::size_t i = 0; i < c.r.size(); ++i) {
    if (c.r[i] < 0.95 * a) {
      c.pressure_error =
          std::max(c.pressure_error, std::abs(c.pressure[i] - c.exact.pressure(c.r[i])));
    }
  }
  c.wall_s = seconds_since(t0);
  return c;
}

BondedDiskCheck check_bonded_disk(const elastic::Material& m, double a,
                                  const contact::BondedOptions& options,
                                  const fft::FFTOptions& fft) {
  const auto t0 = std::chrono::steady_clock::now();
  BondedDiskCheck c;
  const LatticeBlock block = LatticeBlock::centred_disk(a);
  elastic::FreeSurfaceGF gf(m, elastic::Components::in_plane, block.shape, 1.0, fft);
  c.block = block.shape;
  c.fft_grid = gf.fft_shape();
  const std::size_t n = block.shape.count();
  std::vector<std::uint8_t> mask(n, 0);
  std::vector<double> prescribed(gf.size(), 0.0), r(n);
  const double delta = 0.01;
  std::size_t count = 0;
  for (int i0 = 0; i0 < block.shape.n0; ++i0) {
    for (int i1 = 0; i1 < block.shape.n1; ++i1) {
      const std::size_t i = block.shape.index(i0, i1);
      r[i] = std::hypot(block.x(i0, 1.0), block.y(i1, 1.0));
      if (r[i] < a) {
        mask[i] = 1;
        prescribed[i] = delta;
        ++count;
      }
    }
  }
  c.solve = contact::solve_bonded(gf, mask, prescribed, options);
  double fx = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    fx += c.solve.force[i];
  c.stiffness = fx / delta;
  c.radius = std::sqrt(static_cast<double>(count) / std::numbers::pi);
  c.stiffness_exact = 8.0 * m.G * c.radius / (2.0 - m.nu);
  c.stiffness_error = c.stiffness / c.stiffness_exact - 1.0;

  const auto rings = static_cast<std::size_t>(c.radius / c.ring_width);
  std::vector<double> sum_r(rings, 0.0), sum_t(rings, 0.0), sum_e(rings, 0.0);
  std::vector<int> hits(rings, 0);
  const double unit = fx / (2.0 * std::numbers::pi * c.radius * c.radius);
  for (std::size_t i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(r[i] / c.ring_width);
    if (mask[i] == 0 || k >= rings) continue;
    const double rho = r[i] / c.radius;
    sum_r[k] += r[i];
    sum_t[k] += c.solve.force[i] / unit;
    sum_e[k] += 1.0 / std::sqrt(1.0 - rho * rho);
    ++hits[k];
  }
  for (std::size_t k = 0; k < rings; ++k) {
    if (hits[k] == 0) continue;
    c.ring_r.push_back(sum_r[k] / hits[k]);
    c.ring_traction.push_back(sum_t[k] / hits[k]);
    c.ring_exact.push_back(sum_e[k] / hits[k]);
    if (static_cast<double>(k + 1) * c.ring_width <= 0.7 * c.radius) {
      c.traction_error = std::max(c.traction_error, std::abs(sum_t[k] / sum_e[k] - 1.0));
    }
  }
  c.wall_s = seconds_since(t0);
  return c;
}

FarFieldCheck check_far_field(const elastic::Material& m, int max_distance,
                              const fft::FFTOptions& fft) {
  const auto t0 = std::chrono::steady_clock::now();
  FarFieldCheck c;
  const Shape2 block{2 * max_distance + 1, 2 * max_distance + 1};
  elastic::FreeSurfaceGF gf(m, elastic::Components::full, block, 1.0, fft);
  c.block = block;
  c.fft_grid = gf.fft_shape();
  const std::size_t n = block.count();
  const int mid = max_distance;
  std::vector<double> f(gf.size(), 0.0), ux(gf.size()), uz(gf.size());
  f[block.index(mid, mid)] = 1.0;  // unit Fx on the centre patch
  gf.apply(f, ux);
  f[block.index(mid, mid)] = 0.0;
  f[2 * n + block.index(mid, mid)] = 1.0;  // unit Fz
  gf.apply(f, uz);
  for (bool diagonal : {false, true}) {
    for (int s = 1; s <= max_distance; ++s) {
      const int o1 = diagonal ? s : 0;
      FarFieldCheck::Sample p;
      p.diagonal = diagonal;
      p.r = std::hypot(s, o1);
      p.ux_patch = ux[block.index(mid + s, mid + o1)];
      p.uz_patch = uz[2 * n + block.index(mid + s, mid + o1)];
      p.ux_point = elastic::point_force_gf(m, 0, 0, s, o1);
      p.uz_point = elastic::point_force_gf(m, 2, 2, s, o1);
      if (s >= 5) {
        for (auto [patch, point] : {std::pair{p.ux_patch, p.ux_point}, {p.uz_patch, p.uz_point}}) {
          c.worst_scaled_error =
              std::max(c.worst_scaled_error, std::abs(patch / point - 1.0) * p.r * p.r);
        }
      }
      c.samples.push_back(p);
    }
  }
  c.wall_s = seconds_since(t0);
  return c;
}

}  // namespace asperity::validation
