// Analytic tier: normal loading of the explicit atomistic model (MODEL.md 4) against Hertz
// (MODEL.md 1), issue acceptance 1.
//
// Analytic answer: a^3 = 3 Fz R / (4 E*), delta = a^2 / R, Fz = (4/3) E* sqrt(R) delta^(3/2),
// p(r) = p0 sqrt(1 - r^2/a^2), E* = 4 G at nu = 0.5.
// Measured: delta = h_touch - h (the apex height at first touch minus the one at the load, see
// explicit_contact.hpp), the contact radius from the loaded area (d sqrt(N/pi)) and from the
// second moment of the load (sqrt(5/2 <r^2>)).
// Tolerances (the issue's): contact radius within 2 d, load-penetration within 2% (both ways:
// delta at the load and the load at delta), for R >= 500 d. What is left is physics, not
// numerics: the LJ pairs at the centre compress by ~0.01-0.03 d under load, which adds to
// delta (0.35% of 3.46 d at G = 10 eps/sigma^3, a = 43 d), and the potential's range makes the
// edge atoms feel a force about 1 d beyond the Hertz radius (area radius +1.1 d; the moment
// radius, +0.1 d, weighs them by their small load). The force tolerance of the minimiser
// (1e-6 G d^2 per site) moves delta by < 1e-5 d.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "asperity/core/contact/hertz.hpp"
#include "asperity/core/explicit/explicit_contact.hpp"

using namespace asperity;
using namespace asperity::explicit_model;

TEST(ExplicitHertz, RadiusAndLoadPenetration) {
  struct Case {
    double a, R;
  };
  for (const Case c : {Case{20.0, 535.0}, Case{43.0, 535.0}, Case{30.0, 1000.0}}) {
    const ExplicitScene scene{.R = c.R};
    const double load = contact::Hertz::from_radius(scene.material, c.R, c.a).load;
    const auto r = load_to_force(scene, {.load = load});
    std::printf(
        "a = %g d, R = %g d: delta %.5f d (Hertz %.5f, %+.3f%%), load at delta %+.3f%%, "
        "a_area %+.2f d, a_moment %+.2f d; %d minimisations, %zu GF, %.2f s\n",
        c.a, c.R, r.delta, r.hertz.approach, 100 * r.delta_error, 100 * r.load_error,
        r.a_area_error, r.a_moment_error, r.minimizations, r.gf_applications, r.wall_s);
    ASSERT_EQ(r.termination, Termination::converged) << r.message;
    EXPECT_NEAR(r.state.Fz / load, 1.0, 1e-4);
    EXPECT_LT(std::abs(r.delta_error), 0.02);
    EXPECT_LT(std::abs(r.load_error), 0.02);
    EXPECT_LT(std::abs(r.a_area_error), 2.0);
    EXPECT_LT(std::abs(r.a_moment_error), 2.0);
    // Frictionless on average: the lateral forces of the symmetric contact cancel.
    EXPECT_LT(std::hypot(r.state.Fx, r.state.Fy), 1e-5 * load);
  }
}

TEST(ExplicitHertz, PressureProfile) {
  // The pressure per atom against p(r) inside 0.8 a, where the edge's softening (range of the
  // potential, ~1 d) does not reach: within 1% of p0 (0.28% measured) (Hertz's own discretisation
  // error on this lattice is 4e-4 p0, tests/analytic/test_hertz.cpp; the rest is the hollow-site
  // registry, whose lateral forces tilt each atom's load, and the interface compliance).
  const ExplicitScene scene{.R = 535.0};
  const double a = 43.0;
  const auto hz = contact::Hertz::from_radius(scene.material, scene.R, a);
  const auto r = load_to_force(scene, {.load = hz.load});
  ASSERT_EQ(r.termination, Termination::converged) << r.message;
  const auto& s = r.state;
  double worst = 0.0;
  for (int i0 = 0; i0 < s.block.shape.n0; ++i0) {
    for (int i1 = 0; i1 < s.block.shape.n1; ++i1) {
      const double rr = std::hypot(s.block.x(i0, 1.0), s.block.y(i1, 1.0));
      if (rr > 0.8 * a) continue;
      const double p = -s.fz[s.block.shape.index(i0, i1)];
      worst = std::max(worst, std::abs(p - hz.pressure(rr)) / hz.p0);
    }
  }
  std::printf("pressure inside 0.8 a: max |p - p_Hertz| = %.4f p0\n", worst);
  EXPECT_LT(worst, 0.01);
}
