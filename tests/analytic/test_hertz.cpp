// Analytic tier: Hertz contact of a rigid sphere on the free-boundary half-space.
//
// Analytic answer (MODEL.md section 1): a^3 = 3 Fz R / (4 E*), approach delta = a^2 / R,
// p(r) = p0 sqrt(1 - r^2/a^2) with p0 = 3 Fz / (2 pi a^2), E* = 2 G / (1 - nu).
// The indenter is the exact sphere z = R - sqrt(R^2 - r^2); Hertz assumes its paraboloid, which
// differs by O(a^2/R^2) (1.6e-3 here, a / R = 0.04).
// Numerical contact radius: from the contact area, a = d sqrt(N_contact / pi).
// Tolerances (from the issue): contact radius and load-penetration (approach) within 1%, and
// the pressure within 1e-3 E* of Hertz for r < 0.95 a. The pressure is also required within
// 2e-3 p0 there, a much tighter check (p0 = 0.025 E* here; 4e-4 p0 is reached): the error left is
// the discretisation of the square-root edge, which spreads about one site inwards.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "asperity/core/contact/hertz.hpp"
#include "asperity/core/validation/gf_checks.hpp"

using namespace asperity;

TEST(Hertz, RadiusApproachAndPressure) {
  for (double nu : {0.5, 0.3}) {
    const double a = 40.0, R = 1000.0;
    const auto c = validation::check_hertz({.G = 1.0, .nu = nu}, R, a);
    const double estar = c.exact.estar, p0 = c.exact.p0;
    std::printf(
        "Hertz nu=%.2f: radius %.2e, approach %.2e, |p-pH|max = %.2e E* = %.2e p0, %d its, %zu "
        "GF\n",
        nu, c.radius_error, c.approach_error, c.pressure_error / estar, c.pressure_error / p0,
        c.solve.iterations, c.solve.gf_applications);
    ASSERT_EQ(c.solve.termination, Termination::converged);
    EXPECT_LT(std::abs(c.radius_error), 0.01);
    EXPECT_LT(std::abs(c.approach_error), 0.01);
    EXPECT_LT(c.pressure_error, 1e-3 * estar);
    EXPECT_LT(c.pressure_error, 2e-3 * p0);
    EXPECT_LT(c.solve.max_penetration, 1e-9 * c.exact.approach);
  }
}

TEST(Hertz, RefinementConverges) {
  // Same a/R, finer lattice: a/d = 10, 20, 40, 80. The contact radius and the pressure converge
  // steadily (the approach is already within 2e-4 at a = 10 d and only fluctuates in sign).
  double previous_radius = 1.0, previous_pressure = 1.0;
  for (double a : {10.0, 20.0, 40.0, 80.0}) {
    const auto c = validation::check_hertz({}, 25.0 * a, a);
    const double pressure = c.pressure_error / c.exact.p0;
    std::printf("Hertz refinement a/d=%.0f: approach %.3e radius %.3e pressure/p0 %.3e\n", a,
                c.approach_error, c.radius_error, pressure);
    EXPECT_LT(std::abs(c.radius_error), previous_radius);
    EXPECT_LT(pressure, previous_pressure);
    EXPECT_LT(std::abs(c.approach_error), 2e-4);
    previous_radius = std::abs(c.radius_error);
    previous_pressure = pressure;
  }
}

// Surface deflection (Johnson, Contact Mechanics, 3.41-3.42): continuous at r = a, where both
// branches give a^2 / (2 R) (to round-off: 1e-14 relative), and far away w ~ 4 a^3 / (3 pi R r)
// (the next term is O((a/r)^2) relative: 1e-6 at r = 1000 a).
TEST(Hertz, DeflectionIsContinuousAndDecaysAsAPointLoad) {
  const auto h = contact::Hertz::from_radius({.G = 1.0, .nu = 0.5}, 1000.0, 40.0);
  const double at_edge = h.a * h.a / (2.0 * h.R);
  EXPECT_NEAR(h.deflection(h.a), at_edge, 1e-14 * at_edge);
  EXPECT_NEAR(h.deflection(h.a * (1.0 + 1e-12)), at_edge, 1e-10 * at_edge);
  EXPECT_EQ(h.deflection(0.0), h.approach);
  const double r = 1000.0 * h.a;
  const double far = 4.0 * h.a * h.a * h.a / (3.0 * std::numbers::pi * h.R * r);
  EXPECT_NEAR(h.deflection(r), far, 2e-6 * far);
}

// Cattaneo-Mindlin (Johnson 7.2): the traction carries Q = mu Fz, so int_0^1 2 pi rho q drho =
// (mu / alpha) 2 pi / 3 in units of alpha p0 a^2 (Fz = 2 pi a^2 p0 / 3); a midpoint rule on
// 2e5 panels integrates the square-root edges to about 1e-7. Limits: mu = alpha slips
// everywhere (q = sqrt(1 - rho^2)), mu = 0 carries nothing.
TEST(Hertz, CattaneoMindlinCarriesTheTangentialLoad) {
  for (double m : {0.0, 0.25, 0.4, 0.9, 1.0}) {
    const int n = 200000;
    double sum = 0.0;
    for (int k = 0; k < n; ++k) {
      const double rho = (k + 0.5) / n;
      sum += 2.0 * std::numbers::pi * rho * contact::cattaneo_mindlin(rho, m) / n;
    }
    EXPECT_NEAR(sum, m * 2.0 * std::numbers::pi / 3.0, 2e-6) << "mu/alpha = " << m;
  }
  EXPECT_EQ(contact::cattaneo_mindlin(0.3, 1.0), std::sqrt(1.0 - 0.09));
  EXPECT_EQ(contact::cattaneo_mindlin(0.3, 0.0), 0.0);
  EXPECT_EQ(contact::cattaneo_mindlin(1.2, 0.5), 0.0);
}
