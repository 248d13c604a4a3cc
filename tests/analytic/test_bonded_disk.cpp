// Analytic tier: a bonded rigid disk displaced laterally on the free-boundary half-space.
//
// Analytic answer (MODEL.md section 2; Johnson, Contact Mechanics, 3.10): a rigid disk of radius
// a bonded to the surface and displaced by delta along x needs
//   Fx = k delta,  k = 8 G a / (2 - nu),
// with shear traction tau(r) = Fx / (2 pi a^2) (1 - r^2/a^2)^(-1/2).
// The discrete disk is the set of sites with |X| < a; its radius is taken from its area,
// a_eff = d sqrt(N / pi), so that the staircase edge is not counted as an error.
// Tolerances: the stiffness within 1% for a >= 20 d (the requirement; the discrete
// error falls roughly as d/a, checked by refinement); the traction, averaged over rings of
// width 2 d to remove the staircase noise, within 2% of the closed form for r <= 0.7 a (away
// from the square-root singularity, whose discretisation error spreads about a ring width
// inwards).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "asperity/core/validation/gf_checks.hpp"

using namespace asperity;

TEST(BondedDisk, StiffnessAndTraction) {
  for (double nu : {0.5, 0.25}) {
    for (double a : {20.0, 40.0}) {
      const auto r = validation::check_bonded_disk({.G = 1.0, .nu = nu}, a, {.tolerance = 1e-11});
      ASSERT_EQ(r.solve.termination, Termination::converged);
      std::printf(
          "bonded disk nu=%.2f a=%.0f: k/k_exact-1 = %.3e, traction error %.3e, CG its %d\n", nu, a,
          r.stiffness_error, r.traction_error, r.solve.iterations);
      EXPECT_LT(std::abs(r.stiffness_error), 0.01) << "nu " << nu << " a " << a;
      EXPECT_LT(r.traction_error, 0.02) << "nu " << nu << " a " << a;
    }
  }
}

TEST(BondedDisk, RefinementConverges) {
  // Same disk, finer lattice (a/d = 10, 20, 40, 80): the stiffness error must shrink steadily.
  double previous = 1.0;
  for (double a : {10.0, 20.0, 40.0, 80.0}) {
    const auto r = validation::check_bonded_disk({}, a, {.tolerance = 1e-11});
    std::printf("refinement a/d=%.0f: |k/k_exact-1| = %.3e\n", a, std::abs(r.stiffness_error));
    EXPECT_LT(std::abs(r.stiffness_error), previous) << "a/d " << a;
    previous = std::abs(r.stiffness_error);
  }
  EXPECT_LT(previous, 0.005);
}
