// Whether two slides gave the same result: every field of slide::SlideResult (the trace row by
// row, mu, the peak, the counts and costs, the snapshots) to the bit, NaNs included; or the same
// path at another cost. A slide
// stopped and resumed from its checkpoint must give the uninterrupted one's (MODEL.md 5: the path
// is the result); the tests of checkpoints and of the protocol compare with this one list, so
// that a field added to the result is compared everywhere.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <cstring>
#include <string>

#include "asperity/core/slide/types.hpp"

namespace asperity::test {

// Bit equality (NaN equals NaN; -0 does not equal 0).
inline bool same_bits(double x, double y) {
  return std::memcmp(&x, &y, sizeof x) == 0;
}

// Whether two slides took the same path, whatever it cost: every trace row's place, forces,
// energy and slips, mu and where it peaked, the slip events, why the slide stopped, and the
// frames handed over (label, iteration, Dx, Fx), to the bit. Settings that change only how a
// slide gets there (flow_first_after) must leave all of it as it is; expect_same_result below
// also compares the costs.
inline void expect_same_path(const slide::SlideResult& a, const slide::SlideResult& b,
                             const std::string& where) {
  ASSERT_EQ(a.trace.size(), b.trace.size()) << where;
  for (std::size_t i = 0; i < a.trace.size(); ++i) {
    const auto &x = a.trace[i], &y = b.trace[i];
    EXPECT_TRUE(same_bits(x.Dx, y.Dx) && same_bits(x.Fx, y.Fx) && same_bits(x.Fz, y.Fz) &&
                same_bits(x.energy, y.energy) && x.slip == y.slip &&
                x.slipped_sites == y.slipped_sites)
        << where << ": trace row " << i << " at Dx " << x.Dx << " / " << y.Dx << " d";
  }
  EXPECT_TRUE(same_bits(a.mu, b.mu)) << where;
  EXPECT_TRUE(same_bits(a.peak_Dx, b.peak_Dx)) << where;
  EXPECT_EQ(a.slip_events, b.slip_events) << where;
  EXPECT_EQ(a.stop_reason, b.stop_reason) << where;
  ASSERT_EQ(a.snapshots.size(), b.snapshots.size()) << where;
  for (std::size_t i = 0; i < a.snapshots.size(); ++i) {
    const auto &x = a.snapshots[i], &y = b.snapshots[i];
    EXPECT_TRUE(x.label == y.label && x.iteration == y.iteration && same_bits(x.Dx, y.Dx) &&
                same_bits(x.Fx, y.Fx))
        << where << ": frame " << i << " " << x.label << " / " << y.label;
  }
}

inline void expect_same_result(const slide::SlideResult& a, const slide::SlideResult& b,
                               const std::string& where) {
  ASSERT_EQ(a.trace.size(), b.trace.size()) << where;
  for (std::size_t i = 0; i < a.trace.size(); ++i) {
    const auto &x = a.trace[i], &y = b.trace[i];
    EXPECT_TRUE(same_bits(x.Dx, y.Dx) && same_bits(x.Fx, y.Fx) && same_bits(x.Fz, y.Fz) &&
                same_bits(x.energy, y.energy) && same_bits(x.max_force, y.max_force) &&
                x.iterations == y.iterations && x.gf_applications == y.gf_applications &&
                x.slip == y.slip && x.slipped_sites == y.slipped_sites &&
                x.replayed == y.replayed && same_bits(x.area, y.area))
        << where << ": trace row " << i;
  }
  EXPECT_EQ(a.measure, b.measure) << where;
  EXPECT_TRUE(same_bits(a.mu, b.mu)) << where;
  EXPECT_TRUE(same_bits(a.tau_fric, b.tau_fric)) << where;
  EXPECT_TRUE(same_bits(a.area, b.area)) << where;
  EXPECT_TRUE(same_bits(a.peak_Dx, b.peak_Dx)) << where;
  EXPECT_TRUE(same_bits(a.peak_precision, b.peak_precision)) << where;
  EXPECT_TRUE(same_bits(a.kinetic, b.kinetic)) << where;
  EXPECT_EQ(a.slip_events, b.slip_events) << where;
  EXPECT_EQ(a.steps, b.steps) << where;
  EXPECT_EQ(a.replayed_steps, b.replayed_steps) << where;
  EXPECT_TRUE(same_bits(a.cycle_verified_at, b.cycle_verified_at)) << where;
  EXPECT_TRUE(same_bits(a.cycle_mismatch, b.cycle_mismatch)) << where;
  EXPECT_EQ(a.minimizations, b.minimizations) << where;
  EXPECT_EQ(a.slip_relaxations, b.slip_relaxations) << where;
  EXPECT_EQ(a.flow_first_steps, b.flow_first_steps) << where;
  EXPECT_EQ(a.flow_first_stable, b.flow_first_stable) << where;
  EXPECT_EQ(a.filter_applications, b.filter_applications) << where;
  EXPECT_EQ(a.filtered, b.filtered) << where;
  EXPECT_EQ(a.gf_applications, b.gf_applications) << where;
  EXPECT_EQ(a.gradient_evaluations, b.gradient_evaluations) << where;
  EXPECT_EQ(a.iterations, b.iterations) << where;
  EXPECT_EQ(a.stop_reason, b.stop_reason) << where;
  EXPECT_EQ(a.mu_is_lower_bound, b.mu_is_lower_bound) << where;
  EXPECT_EQ(a.contact_sites, b.contact_sites) << where;
  ASSERT_EQ(a.snapshots.size(), b.snapshots.size()) << where;
  for (std::size_t k = 0; k < a.snapshots.size(); ++k) {
    EXPECT_EQ(a.snapshots[k].label, b.snapshots[k].label) << where;
    EXPECT_EQ(a.snapshots[k].ux, b.snapshots[k].ux) << where << ": snapshot " << k;
    EXPECT_EQ(a.snapshots[k].tau_x, b.snapshots[k].tau_x) << where << ": snapshot " << k;
    // A slip's "after" state carries the slide's GF applications so far (slips.csv's cost): a
    // resumed slide counts its earlier sessions once and not the work it repeats.
    EXPECT_EQ(a.snapshots[k].gf_applications, b.snapshots[k].gf_applications)
        << where << ": snapshot " << k << " " << a.snapshots[k].label;
    EXPECT_EQ(a.snapshots[k].slipped_sites, b.snapshots[k].slipped_sites)
        << where << ": snapshot " << k << " " << a.snapshots[k].label;
  }
}

}  // namespace asperity::test
