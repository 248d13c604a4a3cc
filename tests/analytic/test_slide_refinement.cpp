// Analytic tier, slow (convergence): on the default scene, halving the reference step (0.01 ->
// 0.005 d) and tightening the force tolerance 10x (1e-6 -> 1e-7 G d^2) changes mu by less than
// 0.5% (the requirement), for the reference and the adaptive protocols (the latter with
// min_step halved).
#include <gtest/gtest.h>

#include <cmath>

#include "asperity/core/slide/slider.hpp"

using namespace asperity;

TEST(SlideRefinement, StepAndToleranceConverged) {
  const interface::ContactScene scene {};
  slide::SlideOptions coarse{.protocol = slide::Protocol::reference};
  slide::SlideOptions fine = coarse;
  fine.step = 0.005;
  fine.minimizer.force_tolerance = 1e-7;
  const auto a = slide::slide(scene, coarse);
  const auto b = slide::slide(scene, fine);
  ASSERT_FALSE(a.failed) << a.stop_reason;
  ASSERT_FALSE(b.failed) << b.stop_reason;
  std::printf("reference 0.01 d / 1e-6: mu/alpha %.6f; 0.005 d / 1e-7: %.6f\n", a.mu_over_alpha,
              b.mu_over_alpha);
  EXPECT_NEAR(a.mu / b.mu, 1.0, 0.005);
  slide::SlideOptions adaptive{};
  slide::SlideOptions adaptive_fine = adaptive;
  adaptive_fine.min_step = 0.5 * adaptive.min_step;
  adaptive_fine.minimizer.force_tolerance = 1e-7;
  const auto c = slide::slide(scene, adaptive);
  const auto e = slide::slide(scene, adaptive_fine);
  ASSERT_FALSE(c.failed) << c.stop_reason;
  ASSERT_FALSE(e.failed) << e.stop_reason;
  std::printf("adaptive: mu/alpha %.6f; refined: %.6f\n", c.mu_over_alpha, e.mu_over_alpha);
  EXPECT_NEAR(c.mu / e.mu, 1.0, 0.005);
}
