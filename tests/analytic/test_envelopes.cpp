// Analytic tier: Regime I of the adhesive and mixed envelopes (issue 27; MODEL.md 3 and 5).
//
// Analytic answer: a contact much smaller than its core width moves rigidly (u ~ 0), every
// contact site at the same registry phase, so the largest friction force is the sum of the
// sites' strengths,
//   Fx_max = sum_i tau_max(r_i) d^2 = tau0 N_c d^2 (adhesive),  tau0 N_c d^2 + alpha Fz (mixed),
// with N_c the sites inside the circle at the peak's tip position: tau_fric / tau0 = 1 and
// friction_over_regime_one = 1.
// Scene: a = 2 d, tau0 = 0.005 G (a / b_core^0 = 0.01, lambda = 0.037).
// Tolerance: the sites are not exactly rigid. Their elastic displacements lie between 0 and the
// contact's mean u = F_I / k (k = 8 G a / (2 - nu) = 10.7 G d, F_I = tau0 N_c d^2:
// u = 0.0047 d with N_c = 10 at the peak); a spread du of the phases 2 pi u_i / d lowers the sum
// of the sines at its peak by at most 2 pi^2 (du / d)^2 <= 2 pi^2 (u / d)^2 = 4.3e-4 relative;
// the reference protocol's fixed steps of 0.01 d sample the sine's top to 1 - cos(pi 0.01) =
// 4.9e-4 more (the adaptive one refines the peak to 1e-9). Checked to 1e-3.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "asperity/core/slide/slider.hpp"

using namespace asperity;

namespace {

// Lattice sites (i d, j d) inside the circle of radius a around the tip centre (Dx, 0), by the
// envelopes' own test 1 - r^2/a^2 > 0.
int sites_inside(double a, double Dx) {
  int n = 0;
  const int m = static_cast<int>(std::ceil(a)) + 2;
  for (int i = -m; i <= m + static_cast<int>(std::ceil(Dx)); ++i) {
    for (int j = -m; j <= m; ++j) {
      const double x = i - Dx, y = j;
      if (1.0 - (x * x + y * y) / (a * a) > 0.0) ++n;
    }
  }
  return n;
}

// 2 pi^2 (F_I / (k d))^2: the bound on the relative deficit of Fx_max from the sites' spread.
double rigidity_bound(const interface::ContactScene& c, double regime_one_force) {
  const double u = regime_one_force / c.lateral_stiffness();
  return 2.0 * std::numbers::pi * std::numbers::pi * u * u;
}

}  // namespace

TEST(EnvelopesRegimeOne, AdhesiveFrictionIsTheSumOfTheSiteStrengths) {
  interface::ContactScene c;
  c.envelope = "adhesive";
  c.a = 2.0;
  c.tau0 = 0.005;
  ASSERT_LT(c.a_over_bcore0(), 0.02);
  ASSERT_LT(c.lambda(), 0.05);
  for (auto protocol : {slide::Protocol::adaptive, slide::Protocol::reference}) {
    const auto r = slide::slide(c, {.protocol = protocol});
    ASSERT_FALSE(r.failed) << r.stop_reason;
    const int n = sites_inside(c.a, r.peak_Dx);
    const double fx_max = r.tau_fric * r.area;
    const double expected = c.tau0 * n;  // d = 1
    const double bound = rigidity_bound(c, expected);
    std::printf(
        "%s: peak at Dx = %.4f d, N_c = %d, Fx_max = %.8g, tau0 N_c d^2 = %.8g (1 - "
        "ratio %.2e, bound %.2e), slips %d\n",
        slide::to_string(protocol).c_str(), r.peak_Dx, n, fx_max, expected, 1.0 - fx_max / expected,
        bound, r.slip_events);
    EXPECT_LT(bound, 1e-3);
    EXPECT_EQ(r.area, static_cast<double>(n));
    EXPECT_NEAR(fx_max / expected, 1.0, 1e-3);
    EXPECT_LE(fx_max, expected * (1.0 + 1e-12));  // never above the strengths' sum
    EXPECT_NEAR(r.tau_fric / c.tau0, 1.0, 1e-3);
    EXPECT_NEAR(slide::friction_over_regime_one(c, r), 1.0, 1e-3);
    EXPECT_EQ(r.slip_events, 0);
    EXPECT_FALSE(r.mu_is_lower_bound);
  }
}

// The mixed envelope: mu is the largest Fx / Fz, and rigid sites give
//   mu_rigid = max over Dx of (tau0 N_c d^2 + alpha Fz(Dx)) sin(2 pi Dx / d) / Fz(Dx),
// Fz = sum_i p0 sqrt(1 - r_i^2/a^2) d^2 (p0 = 2 a E* / (pi R)) counted here on a grid of tip
// positions. The ratio jumps where a site enters the circle (tau0 comes with it, its pressure
// does not), which no sampling of a trace resolves: a = 4 d keeps N_c = 48 for every Dx in
// [0.15, 0.35] d, around the peak, so the maximum is smooth there. R = 5000 d, tau0 = 0.001 G:
// the two parts of the strength are equal (alpha Fz = 0.048, tau0 N_c d^2 = 0.048 G d^2).
// Tolerance: the rigidity bound as above, 2 pi^2 (F_I / (k d))^2 = 4.0e-4 (the adaptive
// protocol refines a smooth peak to 1e-9, the grid of 2e-6 d resolves it to 1e-10), within 1e-3.
TEST(EnvelopesRegimeOne, MixedFrictionIsBothStrengthsSummed) {
  interface::ContactScene c;
  c.envelope = "mixed";
  c.a = 4.0;
  c.R = 5000.0;
  c.tau0 = 0.001;
  const double pi = std::numbers::pi;
  const double p0 = 2.0 * c.a * 4.0 * c.material.G / (pi * c.R);  // E* = 4 G at nu = 0.5
  double mu_rigid = 0.0, at = 0.0;
  for (int k = 0; k <= 100000; ++k) {
    const double Dx = 0.15 + k * 2e-6;
    double n = 0.0, fz = 0.0;
    for (int i = -6; i <= 7; ++i) {
      for (int j = -6; j <= 6; ++j) {
        const double x = i - Dx, y = j, s = 1.0 - (x * x + y * y) / (c.a * c.a);
        if (s <= 0.0) continue;
        n += 1.0;
        fz += p0 * std::sqrt(s);
      }
    }
    ASSERT_EQ(n, 48.0) << "Dx = " << Dx;
    const double mu = (c.tau0 * n + c.alpha * fz) * std::sin(2.0 * pi * Dx) / fz;
    if (mu > mu_rigid) mu_rigid = mu, at = Dx;
  }
  ASSERT_GT(at, 0.16);  // an interior maximum
  ASSERT_LT(at, 0.34);
  const auto r = slide::slide(c, {});
  ASSERT_FALSE(r.failed) << r.stop_reason;
  const double bound = rigidity_bound(c, c.regime_one_force(r.Fz, r.area));
  std::printf(
      "mixed: mu = %.8f (peak at Dx = %.4f d), rigid sites %.8f (at %.5f d): 1 - ratio "
      "%.2e, bound %.2e; mu/alpha = %.4f, tau_fric/tau0 = %.4f, Fx/F_I = %.6f\n",
      r.mu, r.peak_Dx, mu_rigid, at, 1.0 - r.mu / mu_rigid, bound, r.mu_over_alpha,
      r.tau_fric / c.tau0, slide::friction_over_regime_one(c, r));
  EXPECT_LT(bound, 1e-3);
  EXPECT_NEAR(r.mu / mu_rigid, 1.0, 1e-3);
  EXPECT_LE(r.mu, mu_rigid * (1.0 + 1e-9));
  EXPECT_EQ(r.slip_events, 0);
  // Against each limit it lies above: mu/alpha > 1 (tau0 adds strength without load) and
  // tau_fric/tau0 > 1 (the pressure adds strength).
  EXPECT_GT(r.mu_over_alpha, 1.0);
  EXPECT_GT(r.tau_fric / c.tau0, 1.0);
}
