// Regression tier: friction_sweep --largest-slip. The fixture slides R = 40 d, a = 24 d
// (tests/regression/sweep_largest_slip.toml) through slips of different sizes; the point's
// largest_slip/ must hold exactly the states before and after the slip with the most slipped
// sites in its trace (the first of equals), the very states of its trace rows, the states
// before and after its last slip, and the peak.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/snapshot_io.hpp"

namespace {

namespace fs = std::filesystem;
const fs::path kDir = SWEEP_DIR;

TEST(FrictionSweepLargestSlip, KeepsTheStatesOfTheSlipWithMostSites) {
  const fs::path point = kDir / "points" / "a24_R40";
  const auto trace = asperity::app::CsvTable::read(point / "trace.csv");
  // The largest slip by the trace, its event number and the rows either side of it.
  int event = 0, largest_event = 0;
  long long largest = 0;
  std::size_t largest_row = 0;
  for (std::size_t i = 0; i < trace.rows(); ++i) {
    if (trace.integer(i, "slip") == 0) continue;
    ++event;
    if (trace.integer(i, "slipped_sites") > largest) {
      largest = trace.integer(i, "slipped_sites");
      largest_event = event;
      largest_row = i;
    }
  }
  // The scene is meant to slide through smaller slips after a large one.
  ASSERT_GE(event, 3) << "the fixture's slide no longer has several slips";
  ASSERT_GT(largest, 100);
  ASSERT_GT(largest_row, 0u);

  char label[32];
  std::snprintf(label, sizeof label, "slip_%03d", largest_event);
  const auto before =
      asperity::app::read_snapshots(point / "largest_slip" / "largest_slip_before.nc");
  const auto after =
      asperity::app::read_snapshots(point / "largest_slip" / "largest_slip_after.nc");
  ASSERT_EQ(before.size(), 1u);
  ASSERT_EQ(after.size(), 1u);
  EXPECT_EQ(before[0].label, std::string(label) + "_before");
  EXPECT_EQ(after[0].label, std::string(label) + "_after");
  // Before: the accepted state of the row above (the stable state the slip leaves); after: the
  // slip row's. The trace is written to 17 significant digits, the frames in double.
  EXPECT_DOUBLE_EQ(before[0].Dx, trace.number(largest_row - 1, "Dx"));
  EXPECT_DOUBLE_EQ(before[0].Fx, trace.number(largest_row - 1, "Fx"));
  EXPECT_DOUBLE_EQ(after[0].Dx, trace.number(largest_row, "Dx"));
  EXPECT_DOUBLE_EQ(after[0].Fx, trace.number(largest_row, "Fx"));

  const auto peak = asperity::app::read_snapshots(point / "largest_slip" / "peak.nc");
  ASSERT_EQ(peak.size(), 1u);
  const auto table = asperity::app::CsvTable::read(kDir / "sweep.csv");
  EXPECT_DOUBLE_EQ(peak[0].Fx / peak[0].Fz, table.number(0, "mu"));
  // The latest slip's pair: the last slip row of the trace and the row above it.
  std::size_t last_row = 0;
  for (std::size_t i = 0; i < trace.rows(); ++i)
    if (trace.integer(i, "slip") != 0) last_row = i;
  std::snprintf(label, sizeof label, "slip_%03d", event);
  const auto latest_before =
      asperity::app::read_snapshots(point / "largest_slip" / "latest_slip_before.nc");
  const auto latest_after =
      asperity::app::read_snapshots(point / "largest_slip" / "latest_slip_after.nc");
  ASSERT_EQ(latest_before.size(), 1u);
  ASSERT_EQ(latest_after.size(), 1u);
  EXPECT_EQ(latest_before[0].label, std::string(label) + "_before");
  EXPECT_EQ(latest_after[0].label, std::string(label) + "_after");
  EXPECT_DOUBLE_EQ(latest_before[0].Dx, trace.number(last_row - 1, "Dx"));
  EXPECT_DOUBLE_EQ(latest_after[0].Dx, trace.number(last_row, "Dx"));
  EXPECT_DOUBLE_EQ(latest_after[0].Fx, trace.number(last_row, "Fx"));

  // Two pairs and the peak, however many slips.
  EXPECT_EQ(std::distance(fs::directory_iterator(point / "largest_slip"), fs::directory_iterator()),
            5);
}

}  // namespace
