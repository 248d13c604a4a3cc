// slide.max_slips (SlideOptions::max_slips, MODEL.md 5): a slide stops at its N-th slip event
// whatever the distance, along the same path as without the bound, and reports mu as a lower
// bound (the static peak has not been established). The default scene (a = 43 d, R = 535 d,
// Regime II) slips twice before its peak holds.
#include <gtest/gtest.h>

#include <string>

#include "asperity/core/slide/slider.hpp"

using namespace asperity;

TEST(SlideMaxSlips, StopsAtTheNthSlipOnTheSamePathWithMuALowerBound) {
  const interface::ContactScene scene {};
  const slide::SlideResult full = slide::slide(scene, slide::SlideOptions{});
  ASSERT_FALSE(full.failed) << full.stop_reason;
  ASSERT_GE(full.slip_events, 2);
  ASSERT_FALSE(full.mu_is_lower_bound);

  slide::SlideOptions bounded;
  bounded.max_slips = 1;
  const slide::SlideResult cut = slide::slide(scene, bounded);
  ASSERT_FALSE(cut.failed) << cut.stop_reason;
  EXPECT_EQ(cut.slip_events, 1);
  ASSERT_FALSE(cut.trace.empty());
  EXPECT_TRUE(cut.trace.back().slip);
  EXPECT_NE(cut.stop_reason.find("slide.max_slips"), std::string::npos) << cut.stop_reason;
  EXPECT_TRUE(cut.mu_is_lower_bound);
  // The same path up to the first slip: the bound only decides where the slide stops.
  ASSERT_LE(cut.trace.size(), full.trace.size());
  for (std::size_t k = 0; k < cut.trace.size(); ++k) {
    EXPECT_EQ(cut.trace[k].Dx, full.trace[k].Dx) << "row " << k;
    EXPECT_EQ(cut.trace[k].Fx, full.trace[k].Fx) << "row " << k;
  }
  EXPECT_LE(cut.mu, full.mu);

  bounded.max_slips = -1;
  EXPECT_THROW(bounded.validate(), std::invalid_argument);
}
