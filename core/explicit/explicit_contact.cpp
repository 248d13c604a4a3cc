// The explicit atomistic contact, MODEL.md section 4 (geometry, potential, protocol) on the
// free-boundary GF of section 2 and the pair representation of SOLVERS.md; equations and
// definitions in explicit_contact.hpp.
#include "asperity/core/explicit/explicit_contact.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "asperity/core/common/validate.hpp"
#include "asperity/core/minimize/problem.hpp"

namespace asperity::explicit_model {

const settings::Table<ExplicitScene>& ExplicitScene::settings() {
  using R = settings::Range;
  static const settings::Table<ExplicitScene> table = {
      settings::number<ExplicitScene>(
          "explicit.G", [](auto& s) -> auto& { return s.G_eps_sigma3; }, R::positive(),
          "eps/sigma^3", "substrate shear modulus in the potential's units"),
      // Below 0.75 the cutoff barely exceeds the hollow-site gap d/sqrt(2) and tip atoms sink
      // into the hollows; above 1, the neighbour windows grow beyond 3 x 3.
      settings::number<ExplicitScene>(
          "explicit.sigma_over_d", [](auto& s) -> auto& { return s.sigma_over_d; },
          R::closed(0.75, 1.0), "d", "Lennard-Jones sigma (2^(-1/6): cutoff r_c = d)"),
  };
  return table;
}

void ExplicitScene::validate() const {
  require_positive("ExplicitScene.R", R);
  require_positive("ExplicitScene.d", d);
  settings::validate(*this, settings());
  material.validate();
  if (!tip.aligned()) {
    const double rc = potential().cutoff(), gap = tip_spacing() / std::numbers::sqrt2;
    if (!(rc >= 1.19 * gap)) {
      throw std::invalid_argument(
          "explicit model: tip lattice spacing (1 + contact.tip_mismatch) d = " +
          settings::format_number(tip_spacing()) +
          " d: allowed: hollow-site gap d_tip/sqrt(2) <= " + "r_c / 1.19 = " +
          settings::format_number(rc / 1.19) +
          " d (the margin sigma/d >= 0.75 keeps for the aligned tip), or tip atoms sink between "
          "substrate atoms");
    }
  }
}

LennardJones ExplicitScene::potential() const {
  return LennardJones::in_substrate_units(G_eps_sigma3 / material.G, sigma_over_d, d);
}
double ExplicitScene::energy_unit() const {
  return potential().eps();
}
double ExplicitScene::force_unit() const {
  const LennardJones lj = potential();
  return lj.eps() / lj.sigma();
}
double ExplicitScene::contact_gap() const {
  const double rc = potential().cutoff();
  const double dt = tip.aligned() ? d : tip_spacing();
  return std::sqrt(std::max(0.0, rc * rc - 0.5 * dt * dt));
}
double ExplicitScene::touch_height() const {
  // The apex atom's tip neighbours are d_tip/sqrt(2) from the tip centre at any rotation.
  const double dt = tip.aligned() ? d : tip_spacing();
  const double rho2 = 0.5 * dt * dt;
  return contact_gap() - rho2 / (R + std::sqrt(R * R - rho2));
}

void require_small_slope(double a, double R) {
  if (!(a / R < 0.1)) {
    throw std::invalid_argument(
        "explicit model: a/R = " + std::to_string(a / R) + " (a = " + std::to_string(a) +
        " d, R = " + std::to_string(R) +
        " d) is not < 0.1: the continuum contact theory it is compared with assumes small "
        "slopes (MODEL.md 4); lower the load or use a larger R");
  }
}

void LoadOptions::validate() const {
  require_positive("LoadOptions.load", load);
  require_positive("LoadOptions.load_tolerance", load_tolerance);
  require_at_least("LoadOptions.max_load_steps", max_load_steps, 1);
  if (!(margin >= 1.0) || !std::isfinite(margin)) {
    reject("LoadOptions.margin", std::to_string(margin), "finite and >= 1 d");
  }
  if (!(initial_radius >= 0.0) || !std::isfinite(initial_radius)) {
    reject("LoadOptions.initial_radius", std::to_string(initial_radius), "finite and >= 0");
  }
  require_at_least("LoadOptions.max_growths", max_growths, 0);
  minimizer.validate();
}

// The minimisation problem on the active sites: 3 components per site, component-major
// ([x of each active site][y ...][z ...]).
class ExplicitContact::Problem final : public minimize::Problem {
 public:
  explicit Problem(ExplicitContact& c) : c_(c) {}

  [[nodiscard]] std::size_t size() const override { return 3 * c_.sites_.size(); }

  void compliance(std::span<const double> f, std::span<double> u) override {
    c_.gf_->apply(c_.sites_, f, u);
  }

  double interface(std::span<const double> u, std::span<double> f_int) const override {
    const std::size_t m = c_.sites_.size();
    double v = 0.0;
    for (std::size_t j = 0; j < m; ++j) {
      const double uj[3] = {u[j], u[m + j], u[2 * m + j]};
      double fj[3];
      v += c_.site_interface(c_.sites_[j], uj, fj);
      f_int[j] = fj[0], f_int[m + j] = fj[1], f_int[2 * m + j] = fj[2];
    }
    return v;
  }

  // The diagonal of each site's 3 x 3 interface Hessian. The in-site off-diagonal terms (x-z,
  // y-z: a pair pushes along its own direction) are left out, as Problem::curvature() asks for
  // a diagonal: the perturb stability check does not use the curvature beyond its sign test,
  // whereas the Lanczos check and Newton finish see this approximation (minimize/problem.hpp).
  void curvature(std::span<const double> u, std::span<double> h) const override {
    const std::size_t m = c_.sites_.size();
    for (std::size_t j = 0; j < m; ++j) {
      const double uj[3] = {u[j], u[m + j], u[2 * m + j]};
      double fj[3], hj[3];
      c_.site_interface(c_.sites_[j], uj, fj, hj);
      h[j] = hj[0], h[m + j] = hj[1], h[2 * m + j] = hj[2];
    }
  }

  [[nodiscard]] std::size_t gf_applications() const override { return c_.gf_->applications(); }
  [[nodiscard]] int threads() const override { return c_.gf_->threads(); }

 private:
  ExplicitContact& c_;
};

ExplicitContact::ExplicitContact(const ExplicitScene& scene, const fft::FFTOptions& fft)
    : scene_(scene),
      lj_((scene.validate(), scene.potential())),
      fft_(fft),
      frame_(scene.tip, scene.d) {
  rebuild(8);
}

ExplicitContact::~ExplicitContact() = default;

Shape2 ExplicitContact::fft_grid() const {
  return gf_->fft_shape();
}

double ExplicitContact::site_interface(std::size_t i, const double u[3], double f[3],
                                       double* h) const {
  const double d = scene_.d, R = scene_.R, rc = lj_.cutoff(), rc2 = lj_.cutoff2();
  const auto n1 = static_cast<std::size_t>(block_.shape.n1);
  // Position relative to the tip centre (Dx, 0) and the apex plane.
  const double px = block_.x(static_cast<int>(i / n1), d) + u[0] - Dx_;
  const double py = block_.y(static_cast<int>(i % n1), d) + u[1];
  const double pz = u[2];
  if (!frame_.aligned()) return site_interface_tip(px, py, pz, f, h);
  // Tip atoms (k, l) at ((k + 1/2) d, (l + 1/2) d) within a lateral cutoff of (px, py).
  const int k_lo = static_cast<int>(std::ceil((px - rc) / d - 0.5));
  const int k_hi = static_cast<int>(std::floor((px + rc) / d - 0.5));
  const int l_lo = static_cast<int>(std::ceil((py - rc) / d - 0.5));
  const int l_hi = static_cast<int>(std::floor((py + rc) / d - 0.5));
  double v = 0.0;
  f[0] = f[1] = f[2] = 0.0;
  if (h) h[0] = h[1] = h[2] = 0.0;
  for (int k = k_lo; k <= k_hi; ++k) {
    const double tx = (k + 0.5) * d, dx = px - tx;
    for (int l = l_lo; l <= l_hi; ++l) {
      const double ty = (l + 0.5) * d, dy = py - ty;
      const double rho2 = tx * tx + ty * ty;
      if (rho2 >= R * R) continue;  // beyond the sphere's rim: no tip atom
      // R - sqrt(R^2 - rho^2) without the cancellation of two numbers near R.
      const double tz = h_ + rho2 / (R + std::sqrt(R * R - rho2));
      const double dz = pz - tz;
      if (dz <= -rc) continue;
      const double r2 = dx * dx + dy * dy + dz * dz;
      if (r2 >= rc2) continue;
      const PairTerms t = lj_.at(r2);
      v += t.v;
      f[0] -= t.dv_r * dx;
      f[1] -= t.dv_r * dy;
      f[2] -= t.dv_r * dz;
      if (h) {
        // Hessian of phi(|r|): phi'' r_a r_b / r^2 + (phi'/r)(delta_ab - r_a r_b / r^2).
        const double c = (t.d2v - t.dv_r) / r2;
        h[0] += c * dx * dx + t.dv_r;
        h[1] += c * dy * dy + t.dv_r;
        h[2] += c * dz * dz + t.dv_r;
      }
    }
  }
  return v;
}

// site_interface() under a tip out of registry: the pair sums in the tip's frame, where tip
// atom (k, l) is at ((k + 1/2) d_tip, (l + 1/2) d_tip); (px, py) the site's lateral position
// relative to the tip centre in the substrate's frame.
double ExplicitContact::site_interface_tip(double px, double py, double pz, double f[3],
                                           double* h) const {
  const double dt = frame_.spacing(), R = scene_.R, rc = lj_.cutoff(), rc2 = lj_.cutoff2();
  double qx = 0.0, qy = 0.0;  // the position along the tip's axes
  frame_.to_tip(px, py, qx, qy);
  const int k_lo = static_cast<int>(std::ceil((qx - rc) / dt - 0.5));
  const int k_hi = static_cast<int>(std::floor((qx + rc) / dt - 0.5));
  const int l_lo = static_cast<int>(std::ceil((qy - rc) / dt - 0.5));
  const int l_hi = static_cast<int>(std::floor((qy + rc) / dt - 0.5));
  double v = 0.0, g1 = 0.0, g2 = 0.0, gz = 0.0;  // force along the tip's axes and z
  double h11 = 0.0, h22 = 0.0, h12 = 0.0, hzz = 0.0;
  for (int k = k_lo; k <= k_hi; ++k) {
    const double tx = (k + 0.5) * dt, dx = qx - tx;
    for (int l = l_lo; l <= l_hi; ++l) {
      const double ty = (l + 0.5) * dt, dy = qy - ty;
      const double rho2 = tx * tx + ty * ty;
      if (rho2 >= R * R) continue;  // beyond the sphere's rim: no tip atom
      const double tz = h_ + rho2 / (R + std::sqrt(R * R - rho2));
      const double dz = pz - tz;
      if (dz <= -rc) continue;
      const double r2 = dx * dx + dy * dy + dz * dz;
      if (r2 >= rc2) continue;
      const PairTerms t = lj_.at(r2);
      v += t.v;
      g1 -= t.dv_r * dx;
      g2 -= t.dv_r * dy;
      gz -= t.dv_r * dz;
      if (h) {
        const double c = (t.d2v - t.dv_r) / r2;
        h11 += c * dx * dx + t.dv_r;
        h22 += c * dy * dy + t.dv_r;
        h12 += c * dx * dy;
        hzz += c * dz * dz + t.dv_r;
      }
    }
  }
  frame_.to_substrate(g1, g2, f[0], f[1]);
  f[2] = gz;
  if (h) {
    // The diagonal of Q H Q^T: c^2 h11 - 2 c s h12 + s^2 h22 (x), s^2 h11 + 2 c s h12 + c^2 h22.
    const double c = frame_.cos(), s = frame_.sin();
    h[0] = c * c * h11 - 2.0 * c * s * h12 + s * s * h22;
    h[1] = s * s * h11 + 2.0 * c * s * h12 + c * c * h22;
    h[2] = hzz;
  }
  return v;
}

void ExplicitContact::rebuild(int half) {
  const double d = scene_.d;
  LatticeBlock nb{Shape2{2 * half + 1, 2 * half + 1}, static_cast<int>(std::lround(Dx_ / d)) - half,
                  -half};
  const std::size_t n = nb.shape.count();
  std::vector<double> f(3 * n, 0.0);
  if (gf_) {  // keep the forces by lattice index
    const std::size_t on = block_.shape.count();
    for (int i0 = 0; i0 < block_.shape.n0; ++i0) {
      for (int i1 = 0; i1 < block_.shape.n1; ++i1) {
        const int j0 = block_.origin0 + i0 - nb.origin0, j1 = block_.origin1 + i1 - nb.origin1;
        const std::size_t oi = block_.shape.index(i0, i1);
        const bool inside = j0 >= 0 && j0 < nb.shape.n0 && j1 >= 0 && j1 < nb.shape.n1;
        if (!inside) {
          if (f_[oi] != 0.0 || f_[on + oi] != 0.0 || f_[2 * on + oi] != 0.0) {
            throw std::logic_error("ExplicitContact: a loaded site left the block");
          }
          continue;
        }
        const std::size_t ni = nb.shape.index(j0, j1);
        for (std::size_t k = 0; k < 3; ++k)
          f[k * n + ni] = f_[k * on + oi];
      }
    }
  }
  block_ = nb;
  auto it = gf_cache_.find(half);
  if (it == gf_cache_.end()) {
    // A handful of sizes recur: the base block of every step and the few a relaxation grows
    // through. Beyond kMaxCachedGFs the largest ones are dropped first (their applications
    // still counted): they cost the most memory and recur the least.
    constexpr std::size_t kMaxCachedGFs = 6;
    while (gf_cache_.size() >= kMaxCachedGFs) {
      auto victim = std::prev(gf_cache_.end());
      if (victim->second.get() == gf_) {
        if (victim == gf_cache_.begin()) break;
        victim = std::prev(victim);
      }
      gf_apps_ += victim->second->applications();
      gf_cache_.erase(victim);
    }
    auto gf = std::make_unique<elastic::FreeSurfaceGF>(scene_.material, elastic::Components::full,
                                                       nb.shape, d, fft_);
    it = gf_cache_.emplace(half, std::move(gf)).first;
  }
  gf_ = it->second.get();
  f_ = std::move(f);
  u_.assign(3 * n, 0.0);
  refresh_u();
  select_active();
}

std::size_t ExplicitContact::gf_applications() const {
  std::size_t n = gf_apps_;
  for (const auto& [half, gf] : gf_cache_)
    n += gf ? gf->applications() : 0;
  return n;
}

void ExplicitContact::refresh_u() {
  // No forces, no displacement: a block rebuilt after clear_forces() needs no GF application.
  if (std::all_of(f_.begin(), f_.end(), [](double v) { return v == 0.0; })) {
    std::fill(u_.begin(), u_.end(), 0.0);
    return;
  }
  gf_->apply(f_, u_);
}

void ExplicitContact::select_active() {
  sites_.clear();
  const double d = scene_.d;
  const std::size_t n = block_.shape.count();
  for (int i0 = 0; i0 < block_.shape.n0; ++i0) {
    const double x = block_.x(i0, d) - Dx_;
    for (int i1 = 0; i1 < block_.shape.n1; ++i1) {
      const std::size_t i = block_.shape.index(i0, i1);
      const bool loaded = f_[i] != 0.0 || f_[n + i] != 0.0 || f_[2 * n + i] != 0.0;
      if (loaded || std::hypot(x, block_.y(i1, d)) <= radius_) sites_.push_back(i);
    }
  }
}

void ExplicitContact::set_active_radius(double radius) {
  radius_ = radius;
  // The block holds the disk plus a ring of at least 2 sites, where relax() looks for atoms
  // that feel a force outside the disk; 10% headroom so that small growths keep the block.
  const double d = scene_.d;
  const int c0 = static_cast<int>(std::lround(Dx_ / d));
  const double need = (radius + std::abs(Dx_ - c0 * d)) / d + 2.0;
  const int half = (block_.shape.n0 - 1) / 2;
  if (need > half || block_.origin0 + half != c0) {
    rebuild(static_cast<int>(std::ceil(std::max(need * 1.1, need + 2.0))));
  } else {
    select_active();
  }
}

void ExplicitContact::place(double Dx, double h, double radius) {
  Dx_ = Dx;
  h_ = h;
  radius_ = radius;
  const double d = scene_.d;
  const int c0 = static_cast<int>(std::lround(Dx_ / d));
  const double need = (radius + std::abs(Dx_ - c0 * d)) / d + 2.0;
  const int half = static_cast<int>(std::ceil(std::max(need * 1.1, need + 2.0)));
  if ((block_.shape.n0 - 1) / 2 != half || block_.origin0 + half != c0) {
    rebuild(half);
  } else {
    select_active();
  }
}

void ExplicitContact::set_tip(double Dx, double h) {
  Dx_ = Dx;
  h_ = h;
  set_active_radius(radius_);
}

void ExplicitContact::clear_forces() {
  std::fill(f_.begin(), f_.end(), 0.0);
  std::fill(u_.begin(), u_.end(), 0.0);
}

void ExplicitContact::set_forces(const std::vector<double>& f) {
  if (f.size() != f_.size()) {
    throw std::invalid_argument("ExplicitContact::set_forces: got " + std::to_string(f.size()) +
                                " values, allowed: " + std::to_string(f_.size()));
  }
  f_ = f;
  refresh_u();
  select_active();
}

void ExplicitContact::start_from_hertz(double load) {
  const auto hz = contact::Hertz::from_load(scene_.material, scene_.R, load);
  const double d = scene_.d;
  // The Hertz forces must all sit on unknowns: a truncated Hertz field would leave the tip
  // deep below an undeformed surface, where substrate atoms pass through its single layer.
  if (radius_ < hz.a + d) set_active_radius(hz.a + d);
  const std::size_t n = block_.shape.count();
  std::vector<double> f(3 * n, 0.0);
  for (int i0 = 0; i0 < block_.shape.n0; ++i0) {
    for (int i1 = 0; i1 < block_.shape.n1; ++i1) {
      f[2 * n + block_.shape.index(i0, i1)] =
          -hz.pressure(std::hypot(block_.x(i0, d) - Dx_, block_.y(i1, d))) * d * d;
    }
  }
  h_ = scene_.touch_height() - hz.approach;
  set_forces(f);
}

std::size_t ExplicitContact::passed_through() const {
  const double d = scene_.d, R = scene_.R;
  const std::size_t n = block_.shape.count();
  const auto n1 = static_cast<std::size_t>(block_.shape.n1);
  std::size_t count = 0;
  for (std::size_t i : sites_) {
    const double x = block_.x(static_cast<int>(i / n1), d) + u_[i] - Dx_;
    const double y = block_.y(static_cast<int>(i % n1), d) + u_[n + i];
    const double rho2 = std::min(x * x + y * y, R * R);
    if (u_[2 * n + i] > h_ + rho2 / (R + std::sqrt(R * R - rho2))) ++count;
  }
  return count;
}

double ExplicitContact::load() const {
  const std::size_t n = block_.shape.count();
  double fz = 0.0;
  for (std::size_t i : sites_) {
    const double u[3] = {u_[i], u_[n + i], u_[2 * n + i]};
    double f[3];
    site_interface(i, u, f);
    fz -= f[2];
  }
  return fz;
}

minimize::MinimizeResult ExplicitContact::relax(const minimize::MinimizerOptions& options,
                                                double margin, int max_growths, int* growths,
                                                const minimize::Observer& observer) {
  minimize::MinimizeResult total;
  const std::size_t gf0 = gf_applications();
  for (int grown = 0;; ++grown) {
    const std::size_t m = sites_.size(), n = block_.shape.count();
    std::vector<double> u(3 * m), f(3 * m);
    for (std::size_t k = 0; k < 3; ++k) {
      for (std::size_t j = 0; j < m; ++j) {
        u[k * m + j] = u_[k * n + sites_[j]];
        f[k * m + j] = f_[k * n + sites_[j]];
      }
    }
    Problem problem(*this);
    const auto r = minimize::minimize(problem, u, f, options, observer);
    for (std::size_t k = 0; k < 3; ++k) {
      for (std::size_t j = 0; j < m; ++j)
        f_[k * n + sites_[j]] = f[k * m + j];
    }
    total.termination = r.termination;
    total.iterations += r.iterations;
    total.interface_evaluations += r.interface_evaluations;
    total.energy = r.energy;
    total.max_force = r.max_force;
    total.escapes += r.escapes;
    total.stability_checked = total.stability_checked || r.stability_checked;
    refresh_u();  // u = G f on the whole block: the atoms outside the disk too
    if (r.termination != Termination::converged) break;
    if (passed_through() > 0) {
      // The tip is a single layer of atoms: a substrate atom above its sphere went through it
      // (a start far from equilibrium); the state is meaningless, not merely unconverged.
      total.termination = Termination::diverged;
      break;
    }
    // Atoms outside the disk that feel a force: the disk grows to the farthest plus the margin.
    double farthest = -1.0;
    const double d = scene_.d;
    std::vector<std::uint8_t> is_active(n, 0);
    for (std::size_t i : sites_)
      is_active[i] = 1;
    for (std::size_t i = 0; i < n; ++i) {
      if (is_active[i]) continue;
      const double ui[3] = {u_[i], u_[n + i], u_[2 * n + i]};
      double fi[3];
      site_interface(i, ui, fi);
      if (fi[0] != 0.0 || fi[1] != 0.0 || fi[2] != 0.0) {
        const auto n1 = static_cast<std::size_t>(block_.shape.n1);
        farthest = std::max(farthest, std::hypot(block_.x(static_cast<int>(i / n1), d) - Dx_,
                                                 block_.y(static_cast<int>(i % n1), d)));
      }
    }
    if (farthest < 0.0) break;
    if (grown >= max_growths) {
      total.termination = Termination::max_iterations;
      break;
    }
    if (growths) ++*growths;
    set_active_radius(std::max(radius_, farthest) + margin);
  }
  total.gf_applications = gf_applications() - gf0;
  return total;
}

ExplicitState ExplicitContact::state() const {
  ExplicitState s;
  s.block = block_;
  s.Dx = Dx_;
  s.h = h_;
  const std::size_t n = block_.shape.count();
  const double d = scene_.d;
  s.ux.assign(u_.begin(), u_.begin() + static_cast<std::ptrdiff_t>(n));
  s.uy.assign(u_.begin() + static_cast<std::ptrdiff_t>(n),
              u_.begin() + static_cast<std::ptrdiff_t>(2 * n));
  s.uz.assign(u_.begin() + static_cast<std::ptrdiff_t>(2 * n), u_.end());
  s.fx.assign(n, 0.0), s.fy.assign(n, 0.0), s.fz.assign(n, 0.0), s.active.assign(n, 0);
  for (std::size_t i : sites_)
    s.active[i] = 1;
  double v = 0.0, r2_load = 0.0;
  for (int i0 = 0; i0 < block_.shape.n0; ++i0) {
    for (int i1 = 0; i1 < block_.shape.n1; ++i1) {
      const std::size_t i = block_.shape.index(i0, i1);
      const double ui[3] = {u_[i], u_[n + i], u_[2 * n + i]};
      double fi[3];
      v += site_interface(i, ui, fi);
      s.fx[i] = fi[0], s.fy[i] = fi[1], s.fz[i] = fi[2];
      s.Fx += fi[0], s.Fy += fi[1], s.Fz -= fi[2];
      if (fi[0] != 0.0 || fi[1] != 0.0 || fi[2] != 0.0) ++s.loaded_sites;
      const double x = block_.x(i0, d) - Dx_, y = block_.y(i1, d);
      r2_load -= (x * x + y * y) * fi[2];
    }
  }
  s.energy = elastic::elastic_energy(f_, u_) + v;
  s.a_area = d * std::sqrt(static_cast<double>(s.loaded_sites) / std::numbers::pi);
  s.a_moment = s.Fz > 0.0 ? std::sqrt(2.5 * r2_load / s.Fz) : 0.0;
  return s;
}

LoadResult load_to_force(const ExplicitScene& scene, const LoadOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  scene.validate();
  options.validate();
  LoadResult res;
  res.target = options.load;
  res.hertz = contact::Hertz::from_load(scene.material, scene.R, options.load);
  require_small_slope(res.hertz.a, scene.R);
  ExplicitContact c(scene, options.fft);
  c.set_active_radius(options.initial_radius > 0.0 ? options.initial_radius
                                                   : res.hertz.a + options.margin);
  c.start_from_hertz(options.load);
  // dFz/dh, first from the Hertz contact stiffness 2 a E*, then by secant.
  double slope = -2.0 * res.hertz.a * res.hertz.estar;
  double h_prev = 0.0, load_prev = 0.0;
  bool have_prev = false;
  res.termination = Termination::max_iterations;
  for (int step = 0; step < options.max_load_steps; ++step) {
    const auto r = c.relax(options.minimizer, options.margin, options.max_growths, &res.growths);
    ++res.minimizations;
    res.load_steps = step + 1;
    res.iterations += r.iterations;
    res.interface_evaluations += r.interface_evaluations;
    if (r.termination != Termination::converged) {
      res.termination = r.termination;
      res.message = "minimisation at h = " + std::to_string(c.h()) +
                    " d: " + to_string(r.termination) + " (max force " +
                    std::to_string(r.max_force) + ")";
      break;
    }
    const double fz = c.load();
    if (std::abs(fz - options.load) <= options.load_tolerance * options.load) {
      res.termination = Termination::converged;
      break;
    }
    if (have_prev && fz != load_prev && c.h() != h_prev) {
      const double secant = (fz - load_prev) / (c.h() - h_prev);
      if (secant < 0.0) slope = secant;  // Fz falls as the tip rises
    }
    h_prev = c.h(), load_prev = fz, have_prev = true;
    const double dh = std::clamp((options.load - fz) / slope, -0.5 * scene.d, 0.5 * scene.d);
    c.set_tip(c.Dx(), c.h() + dh);
  }
  res.state = c.state();
  res.active_sites = c.active_sites();
  res.fft_grid = c.fft_grid();
  res.gf_applications = c.gf_applications();
  res.delta = scene.touch_height() - c.h();
  const double estar = scene.material.contact_modulus();
  res.delta_error = res.delta / res.hertz.approach - 1.0;
  res.load_error = res.state.Fz / (4.0 / 3.0 * estar * std::sqrt(scene.R) *
                                   std::pow(std::max(res.delta, 0.0), 1.5)) -
                   1.0;
  res.a_area_error = res.state.a_area - res.hertz.a;
  res.a_moment_error = res.state.a_moment - res.hertz.a;
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return res;
}

}  // namespace asperity::explicit_model
