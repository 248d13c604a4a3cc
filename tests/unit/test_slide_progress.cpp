// Progress reports of a slide (SlideControl::progress, slide/slider.hpp) and the lines the tools
// make of them (app::describe_progress, app::ProgressLines, common/slide_io.hpp).
//
// A report comes before every relaxation (what it is, where it goes), from inside the lateral
// force model's relaxations every 16 iterations, and after every accepted step; reporting must
// not change the slide.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "asperity/apps/common/slide_io.hpp"
#include "asperity/core/slide/slider.hpp"

using namespace asperity;
using slide::SlidePhase;
using slide::SlideProgressInfo;

namespace {

struct Recorded {
  std::vector<SlideProgressInfo> reports;
  slide::SlideResult result;
};

Recorded slide_recording(const slide::SlideOptions& options) {
  Recorded r;
  const interface::ContactScene scene {};  // a = 43 d, R = 535 d: Regime II, two slips, replay
  r.result = slide::slide(scene, options,
                          [&r](const SlideProgressInfo& info) { r.reports.push_back(info); });
  return r;
}

}  // namespace

TEST(SlideProgress, ReportsEveryRelaxationInOrderAndChangesNothing) {
  const slide::SlideOptions options;
  const Recorded rec = slide_recording(options);
  const slide::SlideResult plain = slide::slide(interface::ContactScene{}, options);
  const slide::SlideResult& res = rec.result;
  ASSERT_FALSE(res.failed) << res.stop_reason;
  ASSERT_GE(res.slip_events, 2);
  ASSERT_GT(res.replayed_steps, 0);

  // Reporting (and the observer it installs in the minimiser) leaves the slide as it was.
  EXPECT_EQ(res.mu, plain.mu);
  EXPECT_EQ(res.gf_applications, plain.gf_applications);
  ASSERT_EQ(res.trace.size(), plain.trace.size());
  for (std::size_t k = 0; k < res.trace.size(); ++k)
    EXPECT_EQ(res.trace[k].Fx, plain.trace[k].Fx) << "row " << k;

  const auto& reps = rec.reports;
  ASSERT_FALSE(reps.empty());
  EXPECT_EQ(reps.front().phase, SlidePhase::start);
  EXPECT_EQ(reps.front().iteration, 0);

  int starts = 0, heartbeats = 0;
  std::size_t row = 1;  // trace row of the next accepted report
  const SlideProgressInfo* relaxing = nullptr;
  for (std::size_t k = 0; k < reps.size(); ++k) {
    const SlideProgressInfo& r = reps[k];
    if (k > 0) {
      EXPECT_GE(r.gf_applications, reps[k - 1].gf_applications) << "report " << k;
      EXPECT_GE(r.wall_s, reps[k - 1].wall_s) << "report " << k;
      EXPECT_GE(r.slip_events, reps[k - 1].slip_events) << "report " << k;
    }
    EXPECT_DOUBLE_EQ(r.limit, reps.front().limit);
    if (r.phase == SlidePhase::accepted) {
      ASSERT_LT(row, res.trace.size());
      EXPECT_EQ(r.Dx, res.trace[row].Dx) << "report " << k;
      EXPECT_EQ(r.target_Dx, r.Dx);
      // A computed slip comes out of the relaxation of its bracketed instability.
      if (res.trace[row].slip && !res.trace[row].replayed) {
        ASSERT_NE(relaxing, nullptr);
        EXPECT_EQ(relaxing->phase, SlidePhase::slip) << "row " << row;
        EXPECT_EQ(relaxing->target_Dx, res.trace[row].Dx) << "row " << row;
      }
      ++row;
    } else if (r.iteration == 0) {
      ++starts;
      relaxing = &r;
      if (r.phase == SlidePhase::peak) {
        EXPECT_EQ(row, res.trace.size()) << "the peak is refined after the stepping";
      }
    } else {
      ++heartbeats;
      ASSERT_NE(relaxing, nullptr);
      EXPECT_EQ(r.iteration % 16, 0);
      EXPECT_EQ(r.phase, relaxing->phase) << "report " << k;
      EXPECT_EQ(r.target_Dx, relaxing->target_Dx) << "report " << k;
    }
  }
  EXPECT_EQ(row, res.trace.size()) << "one accepted report per row after the first";
  EXPECT_EQ(starts, res.minimizations) << "one start report per relaxation";
  EXPECT_GT(heartbeats, 0) << "the slips take hundreds of iterations";
  EXPECT_LE(reps.back().gf_applications, res.gf_applications);
}

TEST(SlideProgress, LinesAtTheIntervalAndAtSlipEvents) {
  SlideProgressInfo info;
  app::ProgressLines every_10s(10.0, true);
  EXPECT_TRUE(every_10s.due(info)) << "the first report";
  info.wall_s = 9.0;
  EXPECT_FALSE(every_10s.due(info));
  info.slip_events = 1;
  EXPECT_TRUE(every_10s.due(info)) << "a new slip event";
  info.wall_s = 18.0;
  EXPECT_FALSE(every_10s.due(info)) << "10 s after the last line, not the first";
  info.wall_s = 19.5;
  EXPECT_TRUE(every_10s.due(info));

  app::ProgressLines quiet(60.0);
  info = {};
  EXPECT_TRUE(quiet.due(info));
  info.slip_events = 3;
  info.wall_s = 30.0;
  EXPECT_FALSE(quiet.due(info)) << "slip events do not count without each_slip";
}

TEST(SlideProgress, DescribesPositionCostAndRelaxation) {
  SlideProgressInfo info{.phase = SlidePhase::slip,
                         .Dx = 4.625,
                         .target_Dx = 4.626,
                         .limit = 9.25,
                         .slip_events = 1,
                         .steps = 25,
                         .replayed_steps = 7,
                         .gf_applications = 801,
                         .wall_s = 324.0,
                         .iteration = 3200};
  EXPECT_EQ(app::describe_progress(info),
            "Dx = 4.6250 d of at most 9.25 d, 1 slip event, 25 steps + 7 replayed, 801 GF, "
            "5.4 min; relaxing the slip at Dx = 4.6260 d, iteration 3200");
  info.phase = SlidePhase::accepted;
  info.replayed_steps = 0;
  info.wall_s = 7300.0;
  EXPECT_EQ(app::describe_progress(info),
            "Dx = 4.6250 d of at most 9.25 d, 1 slip event, 25 steps, 801 GF, 2.03 h");
}
