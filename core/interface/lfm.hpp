// The lateral force model (MODEL.md section 3): the tip is an in-plane force field on the
// substrate sites, with registry energy per site
//   V_i = (tau_max(r_i) d^3 / 2 pi) [2 - cos(2 pi s_ix / d) - cos(2 pi s_iy / d)],
//   s_i = X_i + u_i - (Dx, 0),  f_i = -tau_max(r_i) d^2 [sin(2 pi s_ix/d), sin(2 pi s_iy/d)],
// and envelope tau_max(r) (envelope.hpp): alpha p(r), the Hertz pressure of MODEL.md 1 around the
// tip centre (Dx, 0) (contact.envelope = "hertz"); tau0 inside r < a ("adhesive"); tau0 + alpha p
// ("mixed", issue 27). Friction Fx = sum_i f_ix; load Fz = sum_i p(r_i) d^2 (the discrete Hertz
// load; 0 for the adhesive envelope); contact-site area A = N_c d^2 (N_c the sites with
// tau_max > 0), which turns Fx into the friction stress tau_fric = Fx / A.
// Core width at the centre b_core^0 = d G / tau_max(0), tau_max(0) = alpha p0, tau0 or
// tau0 + alpha p0; the control parameter a / b_core^0 (Hertz: c alpha a^2 / (R d), c = 4 / (pi
// (1 - nu)); adhesive: a tau0 / (d G)). Regime I (rigid) friction force F_I = sum_i tau_max(r_i)
// d^2, continuum alpha Fz, tau0 pi a^2 or both; Prandtl-Tomlinson lambda = 2 pi F_I / (d k),
// k = 8 G a / (2 - nu).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "asperity/core/common/shape.hpp"
#include "asperity/core/contact/hertz.hpp"
#include "asperity/core/elastic/material.hpp"
#include "asperity/core/interface/envelope.hpp"
#include "asperity/core/interface/tip_lattice.hpp"

namespace asperity::interface {

struct ContactScene {
  double a = 43.0;                 // contact radius (d)
  double R = 535.0;                // sphere radius (d); not used by the adhesive envelope
  double alpha = 0.7;              // local friction coefficient: peak shear stress / pressure
  double tau0 = 0.0;               // shear strength without load (G): adhesive, mixed envelopes
  elastic::Material material{};    // substrate: G (unit of stress), nu
  TipLattice tip{};                // the tip's lattice (tip_lattice.hpp): aligned by default
  double d = 1.0;                  // lattice spacing (unit of length)
  std::string envelope = "hertz";  // interface envelope (envelope.hpp): hertz, adhesive, mixed

  // The settings, keyed as in a scene ("contact.a", "contact.R", "contact.alpha",
  // "contact.tau0", "contact.envelope", "material.G", "material.nu"): common/settings.hpp. d is
  // the unit of length, not a setting.
  static const settings::Table<ContactScene>& settings();
  // Throws std::invalid_argument naming the violated constraint (the table's ranges, d > 0,
  // a < R where the envelope has a sphere, tau0 > 0 for the adhesive envelope, tau0 = 0 for the
  // Hertz one, which does not use it).
  void validate() const;

  // Whether the envelope has a pressure (Hertz, mixed): friction is then mu = Fx / Fz; without
  // (adhesive) it is the stress tau_fric = Fx / A (slide::FrictionMeasure).
  [[nodiscard]] bool carries_load() const;
  // Whether tau0 enters the envelope (adhesive, mixed).
  [[nodiscard]] bool uses_tau0() const;

  [[nodiscard]] contact::Hertz hertz() const;  // of a and R (the sphere's; not adhesive)
  [[nodiscard]] double tau_max0() const;       // tau_max at the centre: alpha p0, tau0 or both
  [[nodiscard]] double bcore0() const;         // d G / tau_max0()
  [[nodiscard]] double a_over_bcore0() const;  // the control parameter
  // The contact radius (d) at which a / b_core^0 = x, the other parameters as they are: Hertz
  // sqrt(x R d / (c alpha)); adhesive x d G / tau0; mixed the root of x = a tau0 / (d G) +
  // c alpha a^2 / (R d) (the two parts of the control parameter add, as p0 grows with a).
  [[nodiscard]] double radius_for(double a_over_bcore0) const;
  [[nodiscard]] double load() const;              // continuum Fz: the Hertz load, 0 (adhesive)
  [[nodiscard]] double regime_one_force() const;  // continuum F_I: alpha Fz + tau0 pi a^2
  // Discrete F_I = sum_i tau_max(r_i) d^2 from the load Fz = sum_i p(r_i) d^2 and the
  // contact-site area A of a tip position: alpha Fz + tau0 A, each term where it enters.
  [[nodiscard]] double regime_one_force(double Fz, double area) const;
  [[nodiscard]] double lateral_stiffness() const;  // k = 8 G a / (2 - nu)
  [[nodiscard]] double lambda() const;             // 2 pi F_I / (d k), continuum F_I
};

// A tip lattice out of registry (rotated by contact.tip_angle, spacing (1 + contact.tip_mismatch)
// d) replaces s / d by the registry coordinates rho = Q(-theta) s / d_tip in the cosines and the
// amplitude d^3 by d^2 d_tip (tip_lattice.hpp); the aligned tip keeps the arithmetic of MODEL.md 3.

// Per-site registry physics of the LFM at a tip position, for the sites of a block.
class LateralForceModel {
 public:
  LateralForceModel(const ContactScene& scene, LatticeBlock block);

  // Moves the tip centre to (Dx, 0): recomputes the envelope and the set of contact sites.
  void set_tip(double Dx);
  [[nodiscard]] double tip() const { return Dx_; }

  [[nodiscard]] const LatticeBlock& block() const { return block_; }
  [[nodiscard]] const ContactScene& scene() const { return scene_; }
  // Block indices of the sites with tau_max > 0, the unknowns of the problem.
  [[nodiscard]] const std::vector<std::size_t>& contact_sites() const { return sites_; }
  // Envelope tau_max and pressure per block site (zero outside the contact).
  [[nodiscard]] const std::vector<double>& tau_max() const { return tau_max_; }
  [[nodiscard]] const std::vector<double>& pressure() const { return pressure_; }
  // Discrete load sum_i p(r_i) d^2 at the current tip position.
  [[nodiscard]] double load() const { return load_; }
  // Contact-site area N_c d^2 at the current tip position (N_c = contact_sites().size()).
  [[nodiscard]] double area() const { return area_; }

  // Relative position s = X + u - (Dx, 0) of block site i.
  [[nodiscard]] double sx(std::size_t i, double ux) const;
  [[nodiscard]] double sy(std::size_t i, double uy) const;
  // Registry coordinates rho = Q(-theta) s / d_tip of block site i (tip spacings; s / d for the
  // aligned tip): round(rho) is the site's registry index along each tip axis.
  void registry(std::size_t i, double ux, double uy, double& rho1, double& rho2) const;
  [[nodiscard]] const TipFrame& tip_frame() const { return frame_; }

  // On the contact sites, with u and f_int component-major ([x of each contact site][y ...]):
  // returns V, writes the interface force. threads: for the per-site terms of large contacts
  // (V and f_int are bit for bit the same on any number; the sum runs in site order).
  double energy_and_force(std::span<const double> u, std::span<double> f_int,
                          int threads = 1) const;
  // The same, with V made row by row: rows[r] (block().shape.n0 values) is the energy of the
  // contact sites in block row r, their terms added in site order. For sums that must not depend
  // on how the rows are spread over processes (Comm::ordered_sum of the rows: slide/
  // lfm_problem.hpp). f_int is bit for bit energy_and_force's.
  void energy_and_force_rows(std::span<const double> u, std::span<double> f_int,
                             std::span<double> rows, int threads = 1) const;
  // Interface Hessian diagonal d2V/du2 = tau_max d^2 (2 pi/d) cos(2 pi s/d); under a rotated
  // tip c^2 k1 + s^2 k2 (x) and s^2 k1 + c^2 k2 (y), k_j = tau_max d^2 (2 pi/d_tip) cos(2 pi
  // rho_j).
  void curvature(std::span<const double> u, std::span<double> h) const;
  // The interface Hessian's coupling d2V/dux duy of each contact site, c s (k1 - k2), into hxy
  // (one value per contact site). Returns false, writing nothing, when the tip's lattice is not
  // rotated: the interface then couples no two unknowns.
  bool curvature_coupling(std::span<const double> u, std::span<double> hxy) const;

 private:
  void site_terms(std::span<const double> u, std::span<double> f_int, std::size_t j0,
                  std::size_t len, double* terms) const;

  ContactScene scene_;
  std::shared_ptr<const Envelope> envelope_;  // shared: copies of a model share it
  LatticeBlock block_;
  double Dx_ = 0.0;
  std::vector<double> tau_max_, pressure_;
  std::vector<std::size_t> sites_;
  std::vector<double> site_tau_, site_phase_x_;  // per contact site: tau_max, (X - Dx)/d mod 1
  TipFrame frame_;
  // Out of registry, per contact site: rho at u = 0 mod 1 (tip_lattice.hpp); empty if aligned.
  std::vector<double> site_rho1_, site_rho2_;
  double load_ = 0.0;
  double area_ = 0.0;
};

// Static friction of the tip on a rigid substrate (u = 0): the largest Fx(Dx) / F_I over one
// period of the slide, Fx the sum of the site forces of MODEL.md 3 at u = 0 (Fx(Dx + d) = Fx(Dx):
// the envelope moves with the tip). For the aligned tip Fx / F_I = 1 (MODEL.md 3, Regime I). Out of
// registry (tip_lattice.hpp) the site forces are phase-shifted across the contact and cancel in
// part: the Regime I limit of mu under a rotated or mismatched tip (a << b_core^0); beyond, the
// substrate's elasticity pulls sites into registry (misfit dislocations). For many sites it tends
// to cos(theta) |T(q)| / T(0), T the Fourier transform of tau_max(r) (the pressure's for Hertz) and
// q = 2 pi |Q(theta) e_x / d_tip - e_x / d| the beat of the two lattices along the slide
// (|3 (sin x - x cos x) / x^3| at x = q a for Hertz; q = (2 pi / d) sqrt(theta^2 + m^2) for small
// theta and m); the tip's other axis adds nothing to Fx for a symmetric envelope.
// The friction is taken relative to the aligned tip's Regime I force F_I = sum_i tau_max(r_i)
// d^2 (alpha Fz for the Hertz envelope, so that over_regime_one = mu / alpha), which needs no
// load: the measure of any envelope.
struct RigidTipFriction {
  double over_regime_one = 0.0;  // max Fx / F_I over the period
  double mu = 0.0;               // Fx / Fz there (NaN without load)
  double Dx = 0.0;               // where, in [0, d)
  double Fx = 0.0, Fz = 0.0, F_I = 0.0;
};
// `samples` tip positions over [0, d), then a golden-section search around the best to 1e-9 d.
// Throws std::invalid_argument for samples < 4 and for a scene validate() rejects.
RigidTipFriction rigid_tip_friction(const ContactScene& scene, int samples = 64);

}  // namespace asperity::interface
