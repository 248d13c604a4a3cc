// Lateral force model, MODEL.md section 3; equations in lfm.hpp.
#include "asperity/core/interface/lfm.hpp"

#include "asperity/core/common/parallel.hpp"
#include "asperity/core/common/validate.hpp"
#include "asperity/core/interface/sincos.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace asperity::interface {

const settings::Table<ContactScene>& ContactScene::settings() {
  using R = settings::Range;
  static const settings::Table<ContactScene> table = [] {
    settings::Table<ContactScene> t = {
        settings::number<ContactScene>(
            "contact.a", [](auto& c) -> auto& { return c.a; }, R::closed(1.0, 4096.0), "d",
            "contact radius", "--a"),
        // A sphere of 1e9 d is a 0.3 m ball at d = 0.3 nm; far beyond, the Hertz pressure
        // 2 a E*/(pi R) underflows and Fz = 0 would make mu = Fx/Fz meaningless.
        settings::number<ContactScene>(
            "contact.R", [](auto& c) -> auto& { return c.R; }, R::open_closed(0.0, 1e9), "d",
            "sphere radius (hertz, mixed)", "--R"),
        settings::number<ContactScene>(
            "contact.alpha", [](auto& c) -> auto& { return c.alpha; }, R::open_closed(0.0, 10.0),
            "", "local friction coefficient: peak shear stress / pressure (hertz, mixed)",
            "--alpha"),
        settings::number<ContactScene>(
            "contact.tau0", [](auto& c) -> auto& { return c.tau0; }, R::non_negative(), "G",
            "shear strength without load: tau_max = tau0 (adhesive), tau0 + alpha p (mixed)",
            "--tau0"),
        settings::choice<ContactScene>(
            "contact.envelope", [](auto& c) -> auto& { return c.envelope; }, envelope_names(),
            "interface envelope: hertz (tau_max = alpha p, Hertz p) | adhesive (tau_max = tau0 "
            "for r < a, no load) | mixed (tau0 + alpha p)",
            "--envelope")};
    settings::lift(
        t, elastic::Material::settings(), "material.", [](auto& c) -> auto& { return c.material; });
    // The tip's lattice out of registry (tip_lattice.hpp, issue 27). A square lattice turned by
    // 90 degrees is itself, and -theta is the mirror image of theta in y -> -y, which sliding
    // along x respects: [-45, 45] degrees holds every orientation. The single-harmonic registry
    // potential per substrate site models nearly commensurate lattices: |m| <= 0.2.
    t.push_back(settings::number<ContactScene>(
        "contact.tip_angle", [](auto& c) -> auto& { return c.tip.angle; }, R::closed(-45.0, 45.0),
        "degrees",
        "rotation of the tip's lattice about z against the substrate's (registry potential in "
        "the tip's frame)",
        "--tip-angle"));
    t.push_back(settings::number<ContactScene>(
        "contact.tip_mismatch", [](auto& c) -> auto& { return c.tip.mismatch; },
        R::closed(-0.2, 0.2), "", "lattice mismatch m: the tip's lattice spacing is (1 + m) d",
        "--tip-mismatch"));
    return t;
  }();
  return table;
}

const std::vector<std::string>& envelope_names() {
  static const std::vector<std::string> names = {"hertz", "adhesive", "mixed"};
  return names;
}

std::unique_ptr<Envelope> make_envelope(const ContactScene& scene) {
  if (scene.envelope == "hertz") return std::make_unique<HertzEnvelope>(scene.hertz(), scene.alpha);
  if (scene.envelope == "adhesive") return std::make_unique<AdhesiveEnvelope>(scene.a, scene.tau0);
  if (scene.envelope == "mixed")
    return std::make_unique<MixedEnvelope>(scene.hertz(), scene.alpha, scene.tau0);
  throw std::invalid_argument("contact.envelope = \"" + scene.envelope +
                              "\": not an envelope of this build");
}

void ContactScene::validate() const {
  settings::validate(*this, settings());
  require_positive("ContactScene.d", d);
  // The sphere's contact must be small against it (Hertz); the adhesive envelope has no sphere.
  if (carries_load() && !(a < R)) {
    throw std::invalid_argument("contact.a = " + settings::format_number(a) +
                                ": allowed: < contact.R = " + settings::format_number(R));
  }
  const auto with_envelope = [&](const char* allowed) {
    return std::invalid_argument("contact.tau0 = " + settings::format_number(tau0) + ": allowed: " +
                                 allowed + " with contact.envelope = \"" + envelope + "\"");
  };
  if (envelope == "adhesive" && !(tau0 > 0.0)) {
    throw with_envelope("> 0 (the contact's whole strength)");
  }
  // A tau0 that the envelope ignores would be a silent mistake (an envelope forgotten).
  if (!uses_tau0() && tau0 != 0.0) {
    throw with_envelope("0 (tau0 enters the adhesive and mixed envelopes)");
  }
}

bool ContactScene::carries_load() const {
  return envelope != "adhesive";
}
bool ContactScene::uses_tau0() const {
  return envelope != "hertz";
}

contact::Hertz ContactScene::hertz() const {
  return contact::Hertz::from_radius(material, R, a);
}
double ContactScene::tau_max0() const {
  // Mixed with tau0 = 0 is the Hertz value bit for bit (0 + x = x).
  if (!carries_load()) return tau0;
  const double hertz_part = alpha * hertz().p0;
  return uses_tau0() ? tau0 + hertz_part : hertz_part;
}
double ContactScene::bcore0() const {
  return d * material.G / tau_max0();
}
double ContactScene::a_over_bcore0() const {
  return a / bcore0();
}
double ContactScene::radius_for(double x) const {
  const double c = contact::bcore_factor(material.nu);
  // Hertz (and mixed without tau0): x = c alpha a^2 / (R d).
  if (!uses_tau0() || (carries_load() && tau0 == 0.0)) return std::sqrt(x * R * d / (c * alpha));
  const double t = tau0 / (d * material.G);  // adhesive: x = t a
  if (!carries_load()) return x / t;
  // Mixed: k a^2 + t a = x, the positive root in the form without cancellation.
  const double k = c * alpha / (R * d);
  return 2.0 * x / (t + std::sqrt(t * t + 4.0 * k * x));
}

double ContactScene::load() const {
  return carries_load() ? hertz().load : 0.0;
}
double ContactScene::regime_one_force() const {
  double f = carries_load() ? alpha * hertz().load : 0.0;
  if (uses_tau0()) f += tau0 * std::numbers::pi * a * a;
  return f;
}
double ContactScene::regime_one_force(double Fz, double area) const {
  double f = carries_load() ? alpha * Fz : 0.0;
  if (uses_tau0()) f += tau0 * area;
  return f;
}
double ContactScene::lateral_stiffness() const {
  return 8.0 * material.G * a / (2.0 - material.nu);
}
double ContactScene::lambda() const {
  // 2 pi F_I / (d k); the Hertz term in the order it always had (the same bits).
  double two_pi_f = carries_load() ? 2.0 * std::numbers::pi * alpha * hertz().load : 0.0;
  if (uses_tau0()) two_pi_f += 2.0 * std::numbers::pi * tau0 * std::numbers::pi * a * a;
  return two_pi_f / (d * lateral_stiffness());
}

LateralForceModel::LateralForceModel(const ContactScene& scene, LatticeBlock block)
    : scene_(scene), block_(block), frame_(scene.tip, scene.d) {
  scene.validate();
  envelope_ = make_envelope(scene);
  tau_max_.assign(block.shape.count(), 0.0);
  pressure_.assign(block.shape.count(), 0.0);
  set_tip(0.0);
}

void LateralForceModel::set_tip(double Dx) {
  Dx_ = Dx;
  sites_.clear();
  site_tau_.clear();
  site_phase_x_.clear();
  site_rho1_.clear();
  site_rho2_.clear();
  load_ = 0.0;
  const double d = scene_.d;
  for (int i0 = 0; i0 < block_.shape.n0; ++i0) {
    const double x = block_.x(i0, d) - Dx;
    for (int i1 = 0; i1 < block_.shape.n1; ++i1) {
      const std::size_t i = block_.shape.index(i0, i1);
      const double y = block_.y(i1, d);
      const double r = std::hypot(x, y);
      const double p = envelope_->pressure(r);
      pressure_[i] = p;
      tau_max_[i] = envelope_->tau_max(r);
      if (tau_max_[i] > 0.0) {
        sites_.push_back(i);
        site_tau_.push_back(tau_max_[i]);
        // (X - Dx)/d reduced to [-1/2, 1/2]: only the registry phase matters.
        site_phase_x_.push_back(x / d - std::round(x / d));
        if (!frame_.aligned()) {
          // rho at u = 0 reduced to [-1/2, 1/2]: the cosines need rho mod 1 only.
          double r1 = 0.0, r2 = 0.0;
          frame_.registry(x, y, r1, r2);
          site_rho1_.push_back(r1 - std::round(r1));
          site_rho2_.push_back(r2 - std::round(r2));
        }
        load_ += p * d * d;
      }
    }
  }
  area_ = static_cast<double>(sites_.size()) * d * d;
}

double LateralForceModel::sx(std::size_t i, double ux) const {
  return block_.x(static_cast<int>(i / static_cast<std::size_t>(block_.shape.n1)), scene_.d) + ux -
         Dx_;
}
double LateralForceModel::sy(std::size_t i, double uy) const {
  return block_.y(static_cast<int>(i % static_cast<std::size_t>(block_.shape.n1)), scene_.d) + uy;
}

void LateralForceModel::registry(std::size_t i, double ux, double uy, double& rho1,
                                 double& rho2) const {
  frame_.registry(sx(i, ux), sy(i, uy), rho1, rho2);
}

namespace {

// Terms and forces of len sites (MODEL.md 3), in a loop free of the running sum so that it
// vectorises (a floating-point sum does not, without reassociation). The pointers are
// restrict-qualified: with the output arrays possibly aliasing the inputs, it did not vectorise
// and took twice as long.
void lfm_site_terms(std::size_t len, double d, const double* __restrict tau,
                    const double* __restrict phase, const double* __restrict ux,
                    const double* __restrict uy, double* __restrict terms, double* __restrict fx,
                    double* __restrict fy) {
  for (std::size_t k = 0; k < len; ++k) {
    const double t = tau[k];
    // y sites are lattice multiples of d, so s_y enters through u_y alone.
    double sx = 0.0, cx = 0.0, sy = 0.0, cy = 0.0;
    sincos_2pi(phase[k] + ux[k] / d, sx, cx);
    sincos_2pi(uy[k] / d, sy, cy);
    terms[k] = t * (2.0 - cx - cy);
    fx[k] = -t * d * d * sx;
    fy[k] = -t * d * d * sy;
  }
}

// The same out of registry (tip_lattice.hpp): rho = rho(u = 0) + Q(-theta) u / d_tip, the force
// -tau_max d^2 Q(theta) [sin(2 pi rho1), sin(2 pi rho2)]; ct, st: cos and sin of theta.
void lfm_site_terms_tip(std::size_t len, double d, double d_tip, double ct, double st,
                        const double* __restrict tau, const double* __restrict rho1,
                        const double* __restrict rho2, const double* __restrict ux,
                        const double* __restrict uy, double* __restrict terms,
                        double* __restrict fx, double* __restrict fy) {
  for (std::size_t k = 0; k < len; ++k) {
    const double t = tau[k];
    double s1 = 0.0, c1 = 0.0, s2 = 0.0, c2 = 0.0;
    sincos_2pi(rho1[k] + (ct * ux[k] + st * uy[k]) / d_tip, s1, c1);
    sincos_2pi(rho2[k] + (ct * uy[k] - st * ux[k]) / d_tip, s2, c2);
    terms[k] = t * (2.0 - c1 - c2);
    const double g1 = t * d * d * s1, g2 = t * d * d * s2;
    fx[k] = -(ct * g1 - st * g2);
    fy[k] = -(st * g1 + ct * g2);
  }
}

}  // namespace

// The energy terms and interface forces of contact sites [j0, j0 + len) (MODEL.md 3, or out of
// registry tip_lattice.hpp), before the amplitude d^3 / 2 pi (d^2 d_tip / 2 pi out of registry).
void LateralForceModel::site_terms(std::span<const double> u, std::span<double> f_int,
                                   std::size_t j0, std::size_t len, double* terms) const {
  const std::size_t m = sites_.size();
  if (frame_.aligned()) {
    lfm_site_terms(len, scene_.d, site_tau_.data() + j0, site_phase_x_.data() + j0, u.data() + j0,
                   u.data() + m + j0, terms, f_int.data() + j0, f_int.data() + m + j0);
  } else {
    lfm_site_terms_tip(len, scene_.d, frame_.spacing(), frame_.cos(), frame_.sin(),
                       site_tau_.data() + j0, site_rho1_.data() + j0, site_rho2_.data() + j0,
                       u.data() + j0, u.data() + m + j0, terms, f_int.data() + j0,
                       f_int.data() + m + j0);
  }
}

double LateralForceModel::energy_and_force(std::span<const double> u, std::span<double> f_int,
                                           int threads) const {
  const std::size_t m = sites_.size();
  assert(u.size() == 2 * m && f_int.size() == 2 * m);
  // V sums the terms in site order whatever the threads, so it is bit for bit the plain loop's.
  double v = 0.0;
  if (par::threads_for(m, threads) <= 1) {
    // In chunks that stay in cache between the terms and their sum.
    constexpr std::size_t chunk = 512;
    double terms[chunk];
    for (std::size_t j0 = 0; j0 < m; j0 += chunk) {
      const std::size_t len = std::min(chunk, m - j0);
      site_terms(u, f_int, j0, len, terms);
      for (std::size_t k = 0; k < len; ++k)
        v += terms[k];
    }
  } else {
    // The terms of all sites first, on the threads (the sines and cosines are most of the
    // cost), then their sum on this one. The buffer is the calling thread's own, so it is
    // passed to the others by address (a thread_local named inside the region is theirs).
    thread_local std::vector<double> terms;
    terms.resize(m);
    double* const buffer = terms.data();
    par::for_ranges(m, threads, [&](std::size_t b, std::size_t e) {
      site_terms(u, f_int, b, e - b, buffer + b);
    });
    for (std::size_t j = 0; j < m; ++j)
      v += buffer[j];
  }
  const double d = scene_.d;
  if (!frame_.aligned()) return v * d * d * frame_.spacing() / (2.0 * std::numbers::pi);
  return v * d * d * d / (2.0 * std::numbers::pi);
}

void LateralForceModel::energy_and_force_rows(std::span<const double> u, std::span<double> f_int,
                                              std::span<double> rows, int threads) const {
  const std::size_t m = sites_.size(), n1 = static_cast<std::size_t>(block_.shape.n1);
  assert(u.size() == 2 * m && f_int.size() == 2 * m &&
         rows.size() == static_cast<std::size_t>(block_.shape.n0));
  // The terms of every site first (on the threads: the sines and cosines are most of the cost),
  // then their sums per row on this thread.
  thread_local std::vector<double> terms;
  terms.resize(m);
  double* const buffer = terms.data();
  par::for_ranges(m, threads, [&](std::size_t b, std::size_t e) {
    site_terms(u, f_int, b, e - b, buffer + b);
  });
  std::fill(rows.begin(), rows.end(), 0.0);
  for (std::size_t j = 0; j < m; ++j)
    rows[sites_[j] / n1] += buffer[j];
  const double d = scene_.d;
  const double scale = frame_.aligned() ? d * d * d / (2.0 * std::numbers::pi)
                                        : d * d * frame_.spacing() / (2.0 * std::numbers::pi);
  for (double& r : rows)
    r *= scale;
}

void LateralForceModel::curvature(std::span<const double> u, std::span<double> h) const {
  const std::size_t m = sites_.size();
  const double d = scene_.d;
  if (!frame_.aligned()) {
    const double dt = frame_.spacing(), ct = frame_.cos(), st = frame_.sin();
    const double k = 2.0 * std::numbers::pi / dt;
    for (std::size_t j = 0; j < m; ++j) {
      double sn = 0.0, c1 = 0.0, c2 = 0.0;
      sincos_2pi(site_rho1_[j] + (ct * u[j] + st * u[m + j]) / dt, sn, c1);
      sincos_2pi(site_rho2_[j] + (ct * u[m + j] - st * u[j]) / dt, sn, c2);
      const double k1 = site_tau_[j] * d * d * k * c1, k2 = site_tau_[j] * d * d * k * c2;
      h[j] = ct * ct * k1 + st * st * k2;
      h[m + j] = st * st * k1 + ct * ct * k2;
    }
    return;
  }
  const double k = 2.0 * std::numbers::pi / d;
  for (std::size_t j = 0; j < m; ++j) {
    const double c = site_tau_[j] * d * d * k;
    double sn = 0.0, cx = 0.0, cy = 0.0;
    sincos_2pi(site_phase_x_[j] + u[j] / d, sn, cx);
    sincos_2pi(u[m + j] / d, sn, cy);
    h[j] = c * cx;
    h[m + j] = c * cy;
  }
}

bool LateralForceModel::curvature_coupling(std::span<const double> u, std::span<double> hxy) const {
  if (frame_.sin() == 0.0) return false;
  const std::size_t m = sites_.size();
  const double d = scene_.d, dt = frame_.spacing(), ct = frame_.cos(), st = frame_.sin();
  const double k = 2.0 * std::numbers::pi / dt;
  for (std::size_t j = 0; j < m; ++j) {
    double sn = 0.0, c1 = 0.0, c2 = 0.0;
    sincos_2pi(site_rho1_[j] + (ct * u[j] + st * u[m + j]) / dt, sn, c1);
    sincos_2pi(site_rho2_[j] + (ct * u[m + j] - st * u[j]) / dt, sn, c2);
    hxy[j] = ct * st * site_tau_[j] * d * d * k * (c1 - c2);
  }
  return true;
}

RigidTipFriction rigid_tip_friction(const ContactScene& scene, int samples) {
  scene.validate();
  if (samples < 4) {
    throw std::invalid_argument("rigid_tip_friction: samples = " + std::to_string(samples) +
                                ": allowed: >= 4");
  }
  const double d = scene.d;
  // Sites up to a + d from the tip centre at any Dx in [0, d).
  const int half = static_cast<int>(std::ceil(scene.a / d)) + 2;
  LateralForceModel lfm(scene, LatticeBlock{Shape2{2 * half + 2, 2 * half + 1}, -half, -half});
  std::vector<double> u, f;
  const auto at = [&](double Dx) {
    lfm.set_tip(Dx);
    const std::size_t m = lfm.contact_sites().size();
    u.assign(2 * m, 0.0);
    f.assign(2 * m, 0.0);
    lfm.energy_and_force(u, f);
    RigidTipFriction r{.Dx = Dx, .Fz = lfm.load()};
    for (std::size_t j = 0; j < m; ++j) {
      r.Fx += f[j];
      r.F_I += lfm.tau_max()[lfm.contact_sites()[j]] * d * d;
    }
    r.over_regime_one = r.Fx / r.F_I;
    r.mu = r.Fz > 0.0 ? r.Fx / r.Fz : std::numeric_limits<double>::quiet_NaN();
    return r;
  };
  RigidTipFriction best = at(0.0);
  for (int k = 1; k < samples; ++k) {
    const RigidTipFriction r = at(d * k / samples);
    if (r.over_regime_one > best.over_regime_one) best = r;
  }
  // Golden-section search for the maximum within one sample of the best.
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double lo = best.Dx - d / samples, hi = best.Dx + d / samples;
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  RigidTipFriction f1 = at(x1), f2 = at(x2);
  while (hi - lo > 1e-9 * d) {
    if (f1.over_regime_one > f2.over_regime_one) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = at(x1);
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = at(x2);
    }
  }
  for (const RigidTipFriction& r : {f1, f2}) {
    if (r.over_regime_one > best.over_regime_one) best = r;
  }
  best.Dx -= d * std::floor(best.Dx / d);
  return best;
}

}  // namespace asperity::interface
