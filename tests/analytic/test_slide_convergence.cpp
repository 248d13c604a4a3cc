// Analytic tier (convergence): the default scene (a = 43 d, R = 535 d, alpha = 0.7, Regime II)
// with the adaptive protocol against the reference protocol (fixed 0.01 d steps).
//
// There is no closed form for mu here; the check is self-convergence. Requirement (issue):
// the two protocols agree on mu within 0.5%. Both must find the same stick-slip sequence
// (two slip events through the automatic distance) and a kinetic/static ratio within 1%.
// The slow-labelled companion (test_slide_refinement) halves the reference step and tightens
// the tolerance 10x.
#include <gtest/gtest.h>

#include <cmath>

#include "asperity/core/slide/slider.hpp"

using namespace asperity;

TEST(SlideConvergence, AdaptiveAgreesWithReference) {
  const interface::ContactScene scene {};  // the default scene
  const auto adaptive = slide::slide(scene, {.protocol = slide::Protocol::adaptive});
  const auto reference = slide::slide(scene, {.protocol = slide::Protocol::reference});
  ASSERT_FALSE(adaptive.failed) << adaptive.stop_reason;
  ASSERT_FALSE(reference.failed) << reference.stop_reason;
  std::printf("adaptive: mu/alpha %.6f, %zu GF, %.2f s; reference: mu/alpha %.6f, %zu GF, %.2f s\n",
              adaptive.mu_over_alpha, adaptive.gf_applications, adaptive.wall_s,
              reference.mu_over_alpha, reference.gf_applications, reference.wall_s);
  EXPECT_NEAR(adaptive.mu / reference.mu, 1.0, 0.005);
  EXPECT_EQ(adaptive.slip_events, 2);
  EXPECT_EQ(reference.slip_events, 2);
  EXPECT_NEAR(adaptive.kinetic_over_static, reference.kinetic_over_static, 0.01);
  EXPECT_LT(adaptive.gf_applications, reference.gf_applications);
}
