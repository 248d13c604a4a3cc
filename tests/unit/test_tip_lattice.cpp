// A tip lattice out of registry (interface/tip_lattice.hpp, issue 27): the frame change, the
// lateral force model's energy, force and Hessian under a rotated and scaled tip, the interface
// Hessian the minimisers use, the slip test's registry index, and the settings rows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <span>
#include <vector>

#include "asperity/core/explicit/explicit_contact.hpp"
#include "asperity/core/interface/lfm.hpp"
#include "asperity/core/minimize/problem.hpp"
#include "asperity/core/slide/slider.hpp"

using namespace asperity;

namespace {

interface::ContactScene scene_with(double angle, double mismatch) {
  interface::ContactScene s {
    .a = 12.0, .R = 300.0, .alpha = 0.7
  };
  s.tip = {.angle = angle, .mismatch = mismatch};
  return s;
}

// An LFM at tip position Dx on a block around the contact, and a displacement field of about
// 0.3 d on its contact sites.
struct Fixture {
  interface::LateralForceModel lfm;
  std::vector<double> u;
  Fixture(const interface::ContactScene& s, double Dx)
      : lfm(s, LatticeBlock{Shape2{31, 31}, -15, -15}) {
    lfm.set_tip(Dx);
    std::mt19937 gen(7);
    std::uniform_real_distribution<double> dist(-0.3, 0.3);
    u.resize(2 * lfm.contact_sites().size());
    for (double& v : u)
      v = dist(gen);
  }
};

}  // namespace

TEST(TipLattice, FrameOfTheAlignedTipIsTheIdentity) {
  const interface::TipFrame f({}, 1.0);
  EXPECT_TRUE(f.aligned());
  double r1 = 0.0, r2 = 0.0;
  f.registry(3.37, -2.71, r1, r2);
  EXPECT_EQ(r1, 3.37);
  EXPECT_EQ(r2, -2.71);
}

TEST(TipLattice, FrameRotatesAndScales) {
  // 30 degrees and d_tip = 1.1 d: a tip site Q(theta) (2, 1) d_tip has rho = (2, 1).
  const interface::TipFrame f({.angle = 30.0, .mismatch = 0.1}, 1.0);
  const double c = std::cos(std::numbers::pi / 6), s = std::sin(std::numbers::pi / 6);
  const double x = 1.1 * (2 * c - 1 * s), y = 1.1 * (2 * s + 1 * c);
  double r1 = 0.0, r2 = 0.0;
  f.registry(x, y, r1, r2);
  EXPECT_NEAR(r1, 2.0, 1e-14);
  EXPECT_NEAR(r2, 1.0, 1e-14);
  double vx = 0.0, vy = 0.0, v1 = 0.0, v2 = 0.0;
  f.to_substrate(0.3, -0.7, vx, vy);
  f.to_tip(vx, vy, v1, v2);
  EXPECT_NEAR(v1, 0.3, 1e-15);
  EXPECT_NEAR(v2, -0.7, 1e-15);
}

// f = -dV/du and the Hessian by central differences of the energy and the force, for rotated,
// scaled and mixed tips, step 1e-5 d. The energy (about 10 G d^3 over 450 sites) is summed to
// 1e-14, which the difference turns into 5e-10 in the force (tau_max d^2 ~ 0.08 G d^2):
// force within 1e-7 relative; the force of a site is its own, so the Hessian's differences
// err by the truncation, (2 pi)^2 eps^2 / 6 ~ 1e-9 relative: within 1e-7.
TEST(TipLattice, ForceAndHessianAreDerivativesOfTheEnergy) {
  for (const auto& [angle, mismatch] :
       {std::pair{2.0, 0.0}, {0.0, 0.05}, {-17.0, -0.08}, {45.0, 0.2}}) {
    Fixture fx(scene_with(angle, mismatch), 0.37);
    auto& lfm = fx.lfm;
    const std::size_t m = lfm.contact_sites().size(), n = 2 * m;
    ASSERT_GT(m, 300u);
    std::vector<double> f(n), h(n), hxy(m), fp(n), fm(n);
    lfm.energy_and_force(fx.u, f);
    lfm.curvature(fx.u, h);
    const bool coupled = lfm.curvature_coupling(fx.u, hxy);
    EXPECT_EQ(coupled, angle != 0.0);
    const double eps = 1e-5;
    double worst_f = 0.0, worst_h = 0.0, scale_f = 0.0, scale_h = 0.0;
    for (std::size_t j = 0; j < n; j += 7) {
      std::vector<double> up = fx.u, um = fx.u;
      up[j] += eps;
      um[j] -= eps;
      const double vp = lfm.energy_and_force(up, fp), vm = lfm.energy_and_force(um, fm);
      worst_f = std::max(worst_f, std::abs(-(vp - vm) / (2 * eps) - f[j]));
      scale_f = std::max(scale_f, std::abs(f[j]));
      // d f_j / d u_j = -H_jj; d f_k / d u_j = -H_kj for the other component k of the site.
      worst_h = std::max(worst_h, std::abs(-(fp[j] - fm[j]) / (2 * eps) - h[j]));
      scale_h = std::max(scale_h, std::abs(h[j]));
      const std::size_t k = j < m ? j + m : j - m;
      const double off = coupled ? hxy[j < m ? j : j - m] : 0.0;
      worst_h = std::max(worst_h, std::abs(-(fp[k] - fm[k]) / (2 * eps) - off));
    }
    EXPECT_LT(worst_f, 1e-7 * scale_f) << angle << " deg, m = " << mismatch;
    EXPECT_LT(worst_h, 1e-7 * scale_h) << angle << " deg, m = " << mismatch;
  }
}

// tau_max stays the peak shear stress per site: a lone site displaced along the tip's first axis
// by a quarter of the tip's period from registry feels tau_max d^2 (tip_lattice.hpp).
TEST(TipLattice, PeakForcePerSiteIsTauMaxWhateverTheLattice) {
  for (const auto& [angle, mismatch] : {std::pair{0.0, 0.0}, {10.0, 0.1}, {-30.0, -0.15}}) {
    Fixture fx(scene_with(angle, mismatch), 0.0);
    auto& lfm = fx.lfm;
    const interface::TipFrame& frame = lfm.tip_frame();
    const std::size_t m = lfm.contact_sites().size();
    // Put every site at rho = (n1 + 1/4, n2): u = Q d_tip (n + (1/4, 0)) - (X - Dx).
    std::vector<double> u(2 * m), f(2 * m);
    for (std::size_t j = 0; j < m; ++j) {
      const std::size_t i = lfm.contact_sites()[j];
      double r1 = 0.0, r2 = 0.0, tx = 0.0, ty = 0.0;
      lfm.registry(i, 0.0, 0.0, r1, r2);
      frame.to_substrate((std::round(r1) + 0.25 - r1) * frame.spacing(),
                         (std::round(r2) - r2) * frame.spacing(), tx, ty);
      u[j] = tx, u[m + j] = ty;
    }
    lfm.energy_and_force(u, f);
    for (std::size_t j = 0; j < m; j += 11) {
      const double tau = lfm.tau_max()[lfm.contact_sites()[j]];
      EXPECT_NEAR(std::hypot(f[j], f[m + j]), tau, 1e-12) << angle << ", " << mismatch;
      // Along -e1 = -Q (1, 0): back towards registry.
      EXPECT_NEAR(f[j], -tau * frame.cos(), 1e-12);
      EXPECT_NEAR(f[m + j], -tau * frame.sin(), 1e-12);
    }
  }
}

// A tiny rotation and mismatch change the energy by about that much: the rotated code path
// joins the aligned one continuously.
TEST(TipLattice, NearlyAlignedTipIsCloseToTheAlignedOne) {
  Fixture a(scene_with(0.0, 0.0), 0.37), b(scene_with(1e-9, 1e-11), 0.37);
  const std::size_t n = a.u.size();
  ASSERT_EQ(n, b.u.size());
  std::vector<double> fa(n), fb(n);
  const double va = a.lfm.energy_and_force(a.u, fa), vb = b.lfm.energy_and_force(a.u, fb);
  EXPECT_NEAR(vb, va, 1e-9 * std::abs(va));
  for (std::size_t j = 0; j < n; ++j)
    EXPECT_NEAR(fb[j], fa[j], 1e-9);
}

// The mirror y -> -y turns a tip rotated by theta into one rotated by -theta.
TEST(TipLattice, MirrorImageOfARotatedTip) {
  Fixture p(scene_with(7.0, 0.03), 0.21), q(scene_with(-7.0, 0.03), 0.21);
  const auto& sp = p.lfm.contact_sites();
  const auto& sq = q.lfm.contact_sites();
  ASSERT_EQ(sp.size(), sq.size());
  const std::size_t m = sp.size();
  // Site (i0, i1) of p is site (i0, 30 - i1) of q (the block spans y = -15 .. 15).
  std::vector<double> uq(2 * m, 0.0), fp(2 * m), fq(2 * m);
  std::vector<std::size_t> image(m);
  for (std::size_t j = 0; j < m; ++j) {
    const std::size_t i = sp[j], mirrored = (i / 31) * 31 + (30 - i % 31);
    const auto it = std::find(sq.begin(), sq.end(), mirrored);
    ASSERT_NE(it, sq.end());
    image[j] = static_cast<std::size_t>(it - sq.begin());
    uq[image[j]] = p.u[j];
    uq[m + image[j]] = -p.u[m + j];
  }
  const double vp = p.lfm.energy_and_force(p.u, fp), vq = q.lfm.energy_and_force(uq, fq);
  EXPECT_NEAR(vq, vp, 1e-12 * vp);
  for (std::size_t j = 0; j < m; ++j) {
    EXPECT_NEAR(fq[image[j]], fp[j], 1e-12);
    EXPECT_NEAR(fq[m + image[j]], -fp[m + j], 1e-12);
  }
}

TEST(TipLattice, InterfaceHessianAppliesAndTestsTheSiteBlocks) {
  // A problem of two sites whose x and y are coupled: blocks [[1, 2], [2, 1]] (indefinite) and
  // [[2, 1], [1, 2]] (definite).
  struct TwoSites final : minimize::Problem {
    double coupling0 = 2.0;
    std::size_t size() const override { return 4; }
    void compliance(std::span<const double> f, std::span<double> u) override {
      std::copy(f.begin(), f.end(), u.begin());
    }
    double interface(std::span<const double>, std::span<double> f) const override {
      std::fill(f.begin(), f.end(), 0.0);
      return 0.0;
    }
    void curvature(std::span<const double>, std::span<double> h) const override {
      h[0] = 1.0, h[1] = 2.0, h[2] = 1.0, h[3] = 2.0;  // x of both sites, then y
    }
    std::size_t curvature_coupling(std::span<const double>, std::span<double> hxy) const override {
      hxy[0] = coupling0, hxy[1] = 1.0;
      return 2;
    }
    std::size_t gf_applications() const override { return 0; }
  } p;
  const std::vector<double> u(4, 0.0), v = {1.0, 10.0, 100.0, 1000.0};
  minimize::InterfaceHessian h;
  h.at(p, u);
  EXPECT_TRUE(h.coupled());
  std::vector<double> out(4);
  h.apply(v, out);
  EXPECT_EQ(out,
            (std::vector<double>{1.0 + 2.0 * 100.0, 20.0 + 1000.0, 100.0 + 2.0, 2000.0 + 10.0}));
  EXPECT_FALSE(h.positive_semidefinite());  // 1 * 1 < 2^2
  p.coupling0 = 0.5;
  h.at(p, u);
  EXPECT_TRUE(h.positive_semidefinite());
}

// The slip test counts a jump of the registry index along a tip axis (tip_lattice.hpp): a site
// moved by one tip period along the tip's first axis slipped, one moved by a tenth did not.
TEST(TipLattice, SlipTestCountsIndexJumpsAlongTheTipAxes) {
  const interface::ContactScene s = scene_with(20.0, 0.1);
  const LatticeBlock block{Shape2{31, 31}, -15, -15};
  interface::LateralForceModel lfm(s, block);
  lfm.set_tip(0.0);
  const std::size_t n = block.shape.count();
  std::vector<double> before(2 * n, 0.0), after(2 * n, 0.0);
  const interface::TipFrame& f = lfm.tip_frame();
  const std::size_t site = lfm.contact_sites()[lfm.contact_sites().size() / 2];
  const std::size_t other = lfm.contact_sites()[lfm.contact_sites().size() / 3];
  f.to_substrate(-f.spacing(), 0.0, after[site], after[n + site]);
  f.to_substrate(0.1 * f.spacing(), 0.0, after[other], after[n + other]);
  EXPECT_EQ(slide::registry_jumps(s, block, 0.0, before, 0.0, after), 1);
}

TEST(TipLattice, SettingsRows) {
  interface::ContactScene s;
  EXPECT_TRUE(s.tip.aligned());
  const auto& t = interface::ContactScene::settings();
  const auto* angle = settings::find(t, "contact.tip_angle");
  const auto* mismatch = settings::find(t, "contact.tip_mismatch");
  ASSERT_NE(angle, nullptr);
  ASSERT_NE(mismatch, nullptr);
  EXPECT_EQ(angle->unit, "degrees");
  EXPECT_EQ(angle->flag, "--tip-angle");
  EXPECT_EQ(mismatch->flag, "--tip-mismatch");
  angle->set(s, 2.5);
  mismatch->set(s, -0.01);
  EXPECT_EQ(s.tip.angle, 2.5);
  EXPECT_EQ(s.tip.mismatch, -0.01);
  EXPECT_NO_THROW(s.validate());
  s.tip.angle = 46.0;
  EXPECT_THROW(s.validate(), std::invalid_argument);
  s.tip = {.angle = 0.0, .mismatch = 0.25};
  EXPECT_THROW(s.validate(), std::invalid_argument);
}

// The rigid tip (u = 0): alpha for the aligned tip, below it out of registry.
TEST(TipLattice, RigidTipFriction) {
  const auto aligned = interface::rigid_tip_friction(scene_with(0.0, 0.0));
  EXPECT_NEAR(aligned.mu, 0.7, 1e-12);
  EXPECT_NEAR(aligned.over_regime_one, 1.0, 1e-12);
  EXPECT_NEAR(aligned.Dx, 0.25, 1e-6);  // Fx = alpha Fz sin(2 pi Dx / d)
  const auto rotated = interface::rigid_tip_friction(scene_with(2.0, 0.0));
  EXPECT_LT(rotated.mu, 0.7);
  EXPECT_NEAR(rotated.over_regime_one, rotated.mu / 0.7, 1e-12);
  EXPECT_GT(rotated.mu, 0.0);
  EXPECT_THROW((void)interface::rigid_tip_friction(scene_with(2.0, 0.0), 3), std::invalid_argument);
}

// The explicit model's tip atoms on the rotated, scaled lattice (explicit_contact.hpp): a site at
// lateral position p under the tip (theta, m) feels what a site at Q(-theta) p feels under an
// aligned tip of spacing d_tip, turned by Q(theta) (the tip atoms' heights depend on their
// distance from the centre only). Force and Hessian diagonal as derivatives of the energy.
TEST(TipLattice, ExplicitTipAtomsOnTheRotatedLattice) {
  const double angle = 12.0, m = 0.05;
  explicit_model::ExplicitScene rotated{.R = 300.0};
  rotated.tip = {.angle = angle, .mismatch = m};
  // The aligned reference: lengths scaled by d_tip, so its lattice is the rotated tip's.
  explicit_model::ExplicitScene aligned{.R = 300.0 / (1.0 + m)};
  aligned.sigma_over_d = rotated.sigma_over_d / (1.0 + m);
  explicit_model::ExplicitContact cr(rotated), ca(aligned);
  const double h = rotated.touch_height() - 0.05;
  cr.set_active_radius(5.0);
  ca.set_active_radius(5.0);
  cr.set_tip(0.0, h);
  ca.set_tip(0.0, h / (1.0 + m));
  const interface::TipFrame frame(rotated.tip, 1.0);
  int touching = 0;
  for (int I : {0, 1, 2}) {
    for (int J : {0, 1, -1}) {
      const std::size_t i = cr.block().shape.index(I - cr.block().origin0, J - cr.block().origin1);
      double u[3] = {0.03, -0.02, -0.06}, f[3], hr[3];
      const double vr = cr.site_interface(i, u, f, hr);
      // The same position in the aligned contact's units: Q(-theta) p / d_tip, z / d_tip.
      double qx = 0.0, qy = 0.0;
      frame.to_tip(I + u[0], J + u[1], qx, qy);
      qx /= 1.0 + m, qy /= 1.0 + m;
      const long K = std::lround(qx), L = std::lround(qy);
      const std::size_t k = ca.block().shape.index(static_cast<int>(K) - ca.block().origin0,
                                                   static_cast<int>(L) - ca.block().origin1);
      double ua[3] = {qx - static_cast<double>(K), qy - static_cast<double>(L), u[2] / (1.0 + m)},
             fa[3];
      const double va = ca.site_interface(k, ua, fa);
      // Energies in eps: the aligned scene's eps in its own G d^3 is the same eps (G and the
      // potential's eps/sigma^3 fixed, sigma scaled) times (1 + m)^3 of the rotated units.
      const double unit = rotated.energy_unit() / aligned.energy_unit();
      EXPECT_NEAR(vr, va * unit, 1e-12 * (1.0 + std::abs(vr))) << I << ", " << J;
      double fx = 0.0, fy = 0.0;
      const double funit = rotated.force_unit() / aligned.force_unit();
      frame.to_substrate(fa[0] * funit, fa[1] * funit, fx, fy);
      EXPECT_NEAR(f[0], fx, 1e-10 * (1.0 + std::abs(f[0])));
      EXPECT_NEAR(f[1], fy, 1e-10 * (1.0 + std::abs(f[1])));
      EXPECT_NEAR(f[2], fa[2] * funit, 1e-10 * (1.0 + std::abs(f[2])));
      if (f[2] != 0.0) ++touching;
      for (int c = 0; c < 3; ++c) {
        const double e = 1e-6;
        double up[3] = {u[0], u[1], u[2]}, um[3] = {u[0], u[1], u[2]}, fp[3], fm[3];
        up[c] += e, um[c] -= e;
        const double vp = cr.site_interface(i, up, fp), vm = cr.site_interface(i, um, fm);
        EXPECT_NEAR(f[c], -(vp - vm) / (2 * e), 1e-6 * (1.0 + std::abs(f[c]))) << c;
        EXPECT_NEAR(hr[c], -(fp[c] - fm[c]) / (2 * e), 1e-5 * (1.0 + std::abs(hr[c]))) << c;
      }
    }
  }
  EXPECT_GE(touching, 5);
}

TEST(TipLattice, ExplicitTipSpacingIsCheckedAgainstTheCutoff) {
  explicit_model::ExplicitScene s;
  s.tip = {.angle = 0.0, .mismatch = 0.15};
  EXPECT_NO_THROW(s.validate());
  s.tip.mismatch = 0.2;  // d_tip / sqrt(2) = 0.849 d > r_c / 1.19 = 0.840 d
  EXPECT_THROW(s.validate(), std::invalid_argument);
}
