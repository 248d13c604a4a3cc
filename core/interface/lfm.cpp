// Lateral force model, MODEL.md section 3; equations in lfm.hpp.
#include "asperity/core/interface/lfm.hpp"

#include "asperity/core/common/parallel.hpp"
#include "asperity/core/common/validate.hpp"
#include "asperity/core/interface/sincos.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
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
            "Hertz contact radius", "--a"),
        // A sphere of 1e9 d is a 0.3 m ball at d = 0.3 nm; far beyond, the Hertz pressure
        // 2 a E*/(pi R) underflows and Fz = 0 would make mu = Fx/Fz meaningless.
        settings::number<ContactScene>(
            "contact.R", [](auto& c) -> auto& { return c.R; }, R::open_closed(0.0, 1e9), "d",
            "sphere radius", "--R"),
        settings::number<ContactScene>(
            "contact.alpha", [](auto& c) -> auto& { return c.alpha; }, R::open_closed(0.0, 10.0),
            "", "local friction coefficient: peak shear stress / pressure", "--alpha"),
        settings::choice<ContactScene>(
            "contact.envelope", [](auto& c) -> auto& { return c.envelope; }, envelope_names(),
            "interface envelope: hertz (tau_max = alpha p, Hertz p)")};
    settings::lift(
        t, elastic::Material::settings(), "material.", [](auto& c) -> auto& { return c.material; });
    return t;
  }();
  return table;
}

const std::vector<std::string>& envelope_names() {
  static const std::vector<std::string> names = {"hertz"};
  return names;
}

std::unique_ptr<Envelope> make_envelope(const ContactScene& scene) {
  if (scene.envelope == "hertz") return std::make_unique<HertzEnvelope>(scene.hertz(), scene.alpha);
  throw std::invalid_argument("contact.envelope = \"" + scene.envelope +
                              "\": not an envelope of this build");
}

void ContactScene::validate() const {
  settings::validate(*this, settings());
  require_positive("ContactScene.d", d);
  if (!(a < R)) {
    throw std::invalid_argument("contact.a = " + settings::format_number(a) +
                                ": allowed: < contact.R = " + settings::format_number(R));
  }
}

contact::Hertz ContactScene::hertz() const {
  return contact::Hertz::from_radius(material, R, a);
}
double ContactScene::bcore0() const {
  return d * material.G / (alpha * hertz().p0);
}
double ContactScene::a_over_bcore0() const {
  return a / bcore0();
}
double ContactScene::lateral_stiffness() const {
  return 8.0 * material.G * a / (2.0 - material.nu);
}
double ContactScene::lambda() const {
  return 2.0 * std::numbers::pi * alpha * hertz().load / (d * lateral_stiffness());
}

LateralForceModel::LateralForceModel(const ContactScene& scene, LatticeBlock block)
    : scene_(scene), block_(block) {
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
        load_ += p * d * d;
      }
    }
  }
}

double LateralForceModel::sx(std::size_t i, double ux) const {
  return block_.x(static_cast<int>(i / static_cast<std::size_t>(block_.shape.n1)), scene_.d) + ux -
         Dx_;
}
double LateralForceModel::sy(std::size_t i, double uy) const {
  return block_.y(static_cast<int>(i % static_cast<std::size_t>(block_.shape.n1)), scene_.d) + uy;
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

}  // namespace

double LateralForceModel::energy_and_force(std::span<const double> u, std::span<double> f_int,
                                           int threads) const {
  const std::size_t m = sites_.size();
  assert(u.size() == 2 * m && f_int.size() == 2 * m);
  const double d = scene_.d;
  const auto site_terms = [&](std::size_t j0, std::size_t len, double* terms) {
    lfm_site_terms(len, d, site_tau_.data() + j0, site_phase_x_.data() + j0, u.data() + j0,
                   u.data() + m + j0, terms, f_int.data() + j0, f_int.data() + m + j0);
  };
  // V sums the terms in site order whatever the threads, so it is bit for bit the plain loop's.
  double v = 0.0;
  if (par::threads_for(m, threads) <= 1) {
    // In chunks that stay in cache between the terms and their sum.
    constexpr std::size_t chunk = 512;
    double terms[chunk];
    for (std::size_t j0 = 0; j0 < m; j0 += chunk) {
      const std::size_t len = std::min(chunk, m - j0);
      site_terms(j0, len, terms);
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
    par::for_ranges(m, threads,
                    [&](std::size_t b, std::size_t e) { site_terms(b, e - b, buffer + b); });
    for (std::size_t j = 0; j < m; ++j)
      v += buffer[j];
  }
  return v * d * d * d / (2.0 * std::numbers::pi);
}

void LateralForceModel::curvature(std::span<const double> u, std::span<double> h) const {
  const std::size_t m = sites_.size();
  const double d = scene_.d;
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

}  // namespace asperity::interface
