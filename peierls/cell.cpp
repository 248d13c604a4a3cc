// The periodic Peierls cell: MODEL.md sections 2 (periodic kernel), 3 (interface energy) and 6
// (frustration w(X)); see cell.hpp for the reduced representation.
#include "asperity/peierls/cell.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

#include "asperity/core/common/validate.hpp"
#include "asperity/core/elastic/surface_gf.hpp"

namespace asperity::peierls {

namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

int positive_mod(long long a, int L) {
  const long long r = a % L;
  return static_cast<int>(r < 0 ? r + L : r);
}

// Wave number index folded into [-L/2, L/2].
int fold(long long a, int L) {
  const int r = positive_mod(a, L);
  return r > L / 2 ? r - L : r;
}

}  // namespace

double line_angle_deg(int mx, int my) {
  // The line runs along (-my, mx); its angle with x-hat, folded into [0, 90].
  const double angle =
      std::atan2(std::abs(static_cast<double>(mx)), std::abs(static_cast<double>(my)));
  return angle * 180.0 / std::numbers::pi;
}

std::vector<Orientation> available_orientations(int L, double min_line_spacing, int max_index) {
  std::vector<Orientation> all;
  for (int mx = 0; mx <= max_index; ++mx) {
    for (int my = 0; my <= max_index; ++my) {
      if (std::gcd(mx, my) != 1) continue;
      const double norm = std::hypot(mx, my);
      const double spacing = L / norm;
      if (spacing < min_line_spacing) continue;
      all.push_back({mx, my, line_angle_deg(mx, my), spacing});
    }
  }
  std::sort(all.begin(), all.end(), [](const Orientation& a, const Orientation& b) {
    if (std::abs(a.theta_deg - b.theta_deg) > 1e-9) return a.theta_deg < b.theta_deg;
    return a.line_spacing > b.line_spacing;
  });
  std::vector<Orientation> unique;
  for (const Orientation& o : all) {
    if (unique.empty() || std::abs(unique.back().theta_deg - o.theta_deg) > 1e-9)
      unique.push_back(o);
  }
  return unique;
}

Orientation orientation_for_angle(int L, double theta_deg, double tolerance_deg,
                                  double min_line_spacing) {
  const std::vector<Orientation> offered = available_orientations(L, min_line_spacing);
  const Orientation* best = nullptr;
  for (const Orientation& o : offered) {
    if (!best || std::abs(o.theta_deg - theta_deg) < std::abs(best->theta_deg - theta_deg))
      best = &o;
  }
  if (!best || std::abs(best->theta_deg - theta_deg) > tolerance_deg) {
    std::string list;
    for (const Orientation& o : offered) {
      if (!list.empty()) list += ", ";
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.2f (m=%d,%d)", o.theta_deg, o.mx, o.my);
      list += buf;
    }
    throw std::invalid_argument("line angle " + std::to_string(theta_deg) +
                                " degrees: no orientation of an L = " + std::to_string(L) +
                                " cell within " + std::to_string(tolerance_deg) +
                                " degrees; offered: " + list);
  }
  return *best;
}

std::string to_string(CellModel m) {
  return m == CellModel::full ? "full" : "reduced";
}

CellModel cell_model_from_string(const std::string& name) {
  if (name == "reduced") return CellModel::reduced;
  if (name == "full") return CellModel::full;
  throw std::invalid_argument("cell model: got '" + name + "', allowed: reduced, full");
}

const settings::Table<CellOptions>& CellOptions::settings() {
  using R = settings::Range;
  using O = CellOptions;
  static const settings::Table<O> table = [] {
    settings::Table<O> t = {
        settings::integer<O>(
            "cell.L", [](auto& o) -> auto& { return o.L; }, R::closed(8, 1 << 16), "",
            "cell size: sites per period along x and y (even)", "--L"),
        settings::choice<O>(
            "cell.model", [](auto& o) -> auto& { return o.model; }, {"reduced", "full"},
            [](CellModel m) { return to_string(m); }, cell_model_from_string,
            "cell model: reduced (the line's profile) | full (every site)", "--model"),
        settings::integer<O>(
            "cell.alias_images", [](auto& o) -> auto& { return o.alias_images; },
            R::closed(1, 1000), "", "reciprocal images per direction in the periodic kernel")};
    settings::lift(
        t, elastic::Material::settings(), "material.", [](auto& o) -> auto& { return o.material; });
    return t;
  }();
  return table;
}

void CellOptions::validate() const {
  settings::validate(*this, settings());
  if (L % 2 != 0) reject("cell.L", std::to_string(L), "even");
  if (mx < 0 || my < 0 || std::gcd(mx, my) != 1) {
    std::string value = std::to_string(mx);
    value.append(", ").append(std::to_string(my));
    reject("CellOptions.(mx, my)", value, "non-negative integers with gcd 1 (one line per cell)");
  }
  require_positive("CellOptions.b_core", b_core);
  require_at_least("CellOptions.threads", threads, 1);
}

PeierlsCell::PeierlsCell(const CellOptions& options) : options_(options) {
  options_.validate();
  const int L = options_.L;
  const bool full = options_.model == CellModel::full;
  sites_ = full ? static_cast<std::size_t>(L) * static_cast<std::size_t>(L)
                : static_cast<std::size_t>(L);
  tau_max_ = options_.material.G / options_.b_core;
  chain_.resize(sites_);
  for (std::size_t s = 0; s < sites_; ++s) {
    if (!full) {
      chain_[s] = static_cast<int>(s);  // the reduced chain is indexed by k itself
      continue;
    }
    int X = 0, Y = 0;
    site_position(s, X, Y);
    chain_[s] = positive_mod(
        static_cast<long long>(options_.mx) * X + static_cast<long long>(options_.my) * Y, L);
  }

  fft::FFTOptions fo;
  fo.threads = options_.threads;
  const Shape2 shape = full ? Shape2{L, L} : Shape2{1, L};
  engine_ = fft::make_engine(shape, 2, fo);
  const Shape2 fs = engine_->fourier_shape();
  stiffness_.assign(4 * fs.count(), {});
  preconditioner_.assign(4 * fs.count(), {});
  const double c = two_pi * tau_max_;  // interface stiffness per site in registry (G d)
  const double norm = engine_->normalisation();
  std::vector<std::complex<double>> g(4);
  for (int k0 = 0; k0 < fs.n0; ++k0) {
    for (int k1 = 0; k1 < fs.n1; ++k1) {
      // Wave vector of this entry, folded into the first Brillouin zone.
      int n0 = 0, n1 = 0;
      if (full) {
        n0 = fold(k0, L);
        n1 = fold(k1, L);
      } else {
        n0 = fold(static_cast<long long>(k1) * options_.mx, L);
        n1 = fold(static_cast<long long>(k1) * options_.my, L);
      }
      Eigen::Matrix2cd K = Eigen::Matrix2cd::Zero();
      if (n0 != 0 || n1 != 0) {
        elastic::periodic_compliance_block(options_.material, elastic::Components::in_plane,
                                           two_pi * n0 / L, two_pi * n1 / L, 1.0,
                                           options_.alias_images, g);
        Eigen::Matrix2cd G;
        G << g[0], g[1], g[2], g[3];
        K = G.inverse();
      }
      const Eigen::Matrix2cd P = (K + c * Eigen::Matrix2cd::Identity()).inverse();
      const std::size_t at = 4 * fs.index(k0, k1);
      for (int e = 0; e < 4; ++e) {
        stiffness_[at + static_cast<std::size_t>(e)] = K(e / 2, e % 2) * norm;
        preconditioner_[at + static_cast<std::size_t>(e)] = P(e / 2, e % 2) * norm;
      }
    }
  }
  // Read contiguously by convolve()'s blocks (fft::Engine::block_order).
  const std::vector<std::size_t> order = engine_->block_order();
  stiffness_ = fft::to_block_order(order, stiffness_, 4);
  preconditioner_ = fft::to_block_order(order, preconditioner_, 4);
}

void PeierlsCell::site_position(std::size_t site, int& X, int& Y) const {
  const int L = options_.L;
  if (options_.model == CellModel::full) {
    X = static_cast<int>(site / static_cast<std::size_t>(L));
    Y = static_cast<int>(site % static_cast<std::size_t>(L));
    return;
  }
  // A representative site with m . X = k: walk along x if mx = 1 is invertible mod L, else
  // solve mx X + my Y = k (mod L) by search over the small cell (done once per site).
  const int k = static_cast<int>(site);
  for (int x = 0; x < L; ++x) {
    for (int y = 0; y < L; ++y) {
      if (positive_mod(
              static_cast<long long>(options_.mx) * x + static_cast<long long>(options_.my) * y,
              L) == k) {
        X = x;
        Y = y;
        return;
      }
    }
  }
  assert(false && "gcd(mx, my) = 1 makes every chain index reachable");
}

double PeierlsCell::registry_shift(std::size_t site) const {
  return static_cast<double>(chain_[site]) / options_.L;
}

void PeierlsCell::multiply(std::span<const double> in, std::span<double> out,
                           const std::vector<std::complex<double>>& kernel) {
  assert(in.size() == size() && out.size() == size());
  for (int c = 0; c < 2; ++c)
    std::copy_n(in.data() + static_cast<std::size_t>(c) * sites_, sites_, engine_->input(c).data());
  engine_->convolve([&kernel](const fft::FourierBlock& b) {
    const std::size_t count = static_cast<std::size_t>(b.rows) * static_cast<std::size_t>(b.width);
    for (std::size_t at = 0; at < count; ++at) {
      const std::complex<double>* kq = kernel.data() + 4 * (b.offset + at);  // block order
      const std::complex<double> vx = b.field[0][at], vy = b.field[1][at];
      b.field[0][at] = kq[0] * vx + kq[1] * vy;
      b.field[1][at] = kq[2] * vx + kq[3] * vy;
    }
  });
  for (int c = 0; c < 2; ++c)
    std::copy_n(engine_->output(c).data(), sites_,
                out.data() + static_cast<std::size_t>(c) * sites_);
  ++transforms_;
}

void PeierlsCell::stiffness(std::span<const double> u, std::span<double> Ku) {
  multiply(u, Ku, stiffness_);
}

void PeierlsCell::precondition(std::span<const double> r, std::span<double> z) {
  multiply(r, z, preconditioner_);
}

void PeierlsCell::interface_force(std::span<const double> u, std::span<double> f_int) const {
  // MODEL.md 3: f = -tau_max d^2 [sin(2 pi s_x / d), sin(2 pi s_y / d)], s_x = u_x - w.
  // std::sin, not the fast table of the contact model: Peierls stresses go down to 1e-10 tau_max.
  for (std::size_t s = 0; s < sites_; ++s) {
    f_int[s] = -tau_max_ * std::sin(two_pi * (u[s] - registry_shift(s)));
    f_int[sites_ + s] = -tau_max_ * std::sin(two_pi * u[sites_ + s]);
  }
}

double PeierlsCell::interface_energy(std::span<const double> u) const {
  double e = 0.0;
  for (std::size_t s = 0; s < sites_; ++s) {
    e += 2.0 - std::cos(two_pi * (u[s] - registry_shift(s))) - std::cos(two_pi * u[sites_ + s]);
  }
  return e * tau_max_ / two_pi;
}

double PeierlsCell::max_site_norm(std::span<const double> d) const {
  double m = 0.0;
  for (std::size_t s = 0; s < sites_; ++s)
    m = std::max(m, std::hypot(d[s], d[sites_ + s]));
  return m;
}

std::vector<double> PeierlsCell::initial_state() const {
  std::vector<double> u(size(), 0.0);
  const int L = options_.L;
  for (std::size_t s = 0; s < sites_; ++s)
    u[s] = registry_shift(s) - (chain_[s] >= L / 2 ? 1.0 : 0.0);
  return u;
}

std::vector<double> PeierlsCell::chain_offset(std::span<const double> u) const {
  const int L = options_.L;
  std::vector<double> phi(static_cast<std::size_t>(L), 0.0);
  std::vector<int> count(static_cast<std::size_t>(L), 0);
  for (std::size_t s = 0; s < sites_; ++s) {
    const auto k = static_cast<std::size_t>(chain_[s]);
    phi[k] += registry_shift(s) - u[s];
    ++count[k];
  }
  for (std::size_t k = 0; k < phi.size(); ++k)
    phi[k] /= count[k];
  return phi;
}

std::vector<double> PeierlsCell::expand(std::span<const double> u) const {
  if (options_.model == CellModel::full) return {u.begin(), u.end()};
  const int L = options_.L;
  const std::size_t n = static_cast<std::size_t>(L) * static_cast<std::size_t>(L);
  std::vector<double> out(2 * n);
  for (int X = 0; X < L; ++X) {
    for (int Y = 0; Y < L; ++Y) {
      const auto k = static_cast<std::size_t>(positive_mod(
          static_cast<long long>(options_.mx) * X + static_cast<long long>(options_.my) * Y, L));
      const std::size_t s =
          static_cast<std::size_t>(X) * static_cast<std::size_t>(L) + static_cast<std::size_t>(Y);
      out[s] = u[k];
      out[n + s] = u[sites_ + k];
    }
  }
  return out;
}

CoreProfile core_profile(std::span<const double> phi, int mx, int my) {
  // Interpolate in t = tan(pi (phi - 1/2)) rather than in phi: t is linear in the normal
  // coordinate for a Peierls-Nabarro profile (phi = 1/2 + atan(x / zeta) / pi), so the
  // crossings of d/4 (t = -1) and 3d/4 (t = 1) are exact for it at any sampling, whereas linear
  // interpolation of phi overestimates a core a few sites wide by about 0.15 d.
  const double spacing = 1.0 / std::hypot(mx, my);
  const auto t = [](double p) {
    return std::tan(std::numbers::pi * (std::clamp(p, 0.0, 1.0) - 0.5));
  };
  const auto crossing = [&](double level) {
    const double target = t(level);
    for (std::size_t k = 0; k + 1 < phi.size(); ++k) {
      if (phi[k] < level && phi[k + 1] >= level) {
        const double t0 = t(phi[k]), t1 = t(phi[k + 1]);
        const double frac = std::isfinite(t0) && std::isfinite(t1) && t1 > t0
                                ? (target - t0) / (t1 - t0)
                                : (level - phi[k]) / (phi[k + 1] - phi[k]);
        return (static_cast<double>(k) + frac) * spacing;
      }
    }
    return std::numeric_limits<double>::quiet_NaN();
  };
  return {crossing(0.75) - crossing(0.25), crossing(0.5)};
}

double continuum_core_width(double b_core, double theta_deg, double nu) {
  const double t = theta_deg * std::numbers::pi / 180.0;
  const double c = std::cos(t), s = std::sin(t);
  return b_core / std::numbers::pi * (c * c + s * s / (1.0 - nu));
}

double rigid_peierls_estimate(double b_core, int mx, int my, double nu) {
  const double zeta = 0.5 * continuum_core_width(b_core, line_angle_deg(mx, my), nu);
  const double m = std::hypot(mx, my);
  return 4.0 * std::numbers::pi * zeta * m * std::exp(-two_pi * zeta * m);
}

}  // namespace asperity::peierls
