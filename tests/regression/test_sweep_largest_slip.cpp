// Regression tier: friction_sweep --largest-slip. The fixture slides R = 40 d, a = 24 d
// (tests/regression/sweep_largest_slip.toml) through slips of different sizes; the point's
// largest_slip/ must hold exactly the states before and after the slip with the most slipped
// sites in its trace (the first of equals), the very states of its trace rows, the states
// before and after its last slip, the peak, and slips.csv with its figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "asperity/apps/common/output_files.hpp"
#include "asperity/apps/common/snapshot_io.hpp"
#include "asperity/tracking/census.hpp"
#include "asperity/tracking/lines.hpp"
#include "asperity/tracking/profile.hpp"

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

  // Two pairs, the peak, slips.csv and its two figures, however many slips.
  EXPECT_EQ(std::distance(fs::directory_iterator(point / "largest_slip"), fs::directory_iterator()),
            8);
  for (const char* png : {"slips.png", "slips_loops.png"}) {
    ASSERT_TRUE(fs::exists(point / "largest_slip" / png)) << png;
    EXPECT_GT(fs::file_size(point / "largest_slip" / png), 1000u) << png;
  }
}

// slips.csv: a row per slip event of the trace, in order, at its row's Dx and Fx (Fx before: the
// row above), with the census of its "after" state; the largest and the latest slip's rows are
// the census of the kept frames. R = 40 d, a = 24 d is Regime III: the first slip nucleates a
// loop at the edge that is arrested around the centre, and the slips after it are that loop's
// front creeping inward, so every row holds one loop, whose area does not grow.
TEST(FrictionSweepLargestSlip, SlipsTableHasTheLoopsAfterEverySlip) {
  using asperity::app::CsvTable;
  const fs::path point = kDir / "points" / "a24_R40";
  const auto trace = CsvTable::read(point / "trace.csv");
  const auto slips = CsvTable::read(point / "largest_slip" / "slips.csv");
  std::size_t k = 0;
  long long largest = 0;
  std::size_t largest_k = 0;
  long long trace_gf = 0;  // the trace rows' GF applications through row i
  for (std::size_t i = 0; i < trace.rows(); ++i) {
    trace_gf += trace.integer(i, "gf_applications");
    if (trace.integer(i, "slip") == 0) continue;
    ASSERT_LT(k, slips.rows()) << "fewer rows than slips";
    EXPECT_EQ(slips.integer(k, "slip"), static_cast<long long>(k + 1));
    EXPECT_DOUBLE_EQ(slips.number(k, "Dx"), trace.number(i, "Dx"));
    EXPECT_DOUBLE_EQ(slips.number(k, "Fx_after"), trace.number(i, "Fx"));
    EXPECT_DOUBLE_EQ(slips.number(k, "Fx_before"), trace.number(i - 1, "Fx"));
    EXPECT_EQ(slips.integer(k, "slipped_sites"), trace.integer(i, "slipped_sites"));
    // The slide's cost when it accepted the slip: at least what the trace's rows count (a row
    // counts its own relaxation, not the bisection's trials that were undone before it), and
    // growing from slip to slip.
    EXPECT_GE(slips.integer(k, "gf_applications"), trace_gf) << "slip " << k + 1;
    if (k > 0) {
      EXPECT_GT(slips.integer(k, "gf_applications"), slips.integer(k - 1, "gf_applications"));
      EXPECT_GT(slips.number(k, "wall_s"), slips.number(k - 1, "wall_s"));
    } else {
      EXPECT_GT(slips.number(k, "wall_s"), 0.0);
    }
    if (trace.integer(i, "slipped_sites") > largest) {
      largest = trace.integer(i, "slipped_sites");
      largest_k = k;
    }
    ++k;
  }
  EXPECT_EQ(k, slips.rows());
  ASSERT_GE(k, 3u);
  // The last slip's cost is within the point's (the slide may go on after it).
  EXPECT_LE(slips.integer(k - 1, "gf_applications"),
            CsvTable::read(kDir / "sweep.csv").integer(0, "gf_applications"));

  const auto census_of = [](const fs::path& nc) {
    const auto frames = asperity::app::read_snapshots(nc);
    return asperity::tracking::census(
        asperity::tracking::find_lines(asperity::tracking::view_of(frames.at(0))));
  };
  // The sink takes the census of the state in memory, in double; the kept frames are float32
  // (the tools' snapshot default), which moves s_x by up to 6e-8 of its size (some 30 d here):
  // the cores by about 2e-6 d and a loop's area by its length (about 100 d) times that, 2e-4 d^2
  // of some 800, 3e-7 relative. Counts of lines are the same; a site whose tau_x lies within
  // float32 rounding of zero could change sides of a core, so the slipped area may differ by a
  // few sites (it did not here).
  const auto same = [&](std::size_t row, const asperity::tracking::LineCensus& c) {
    EXPECT_EQ(slips.integer(row, "contact_sites"), static_cast<long long>(c.contact_sites));
    EXPECT_EQ(slips.integer(row, "loops"), c.loops);
    EXPECT_EQ(slips.integer(row, "open_lines"), c.open_lines);
    EXPECT_NEAR(slips.number(row, "loop_area"), c.loop_area, 1e-5 * c.loop_area);
    EXPECT_NEAR(slips.number(row, "largest_loop_area"), c.largest_loop_area,
                1e-5 * c.largest_loop_area);
    EXPECT_NEAR(slips.number(row, "slipped_area"), c.slipped_area, 3.0);
  };
  same(largest_k, census_of(point / "largest_slip" / "largest_slip_after.nc"));
  same(k - 1, census_of(point / "largest_slip" / "latest_slip_after.nc"));
  // The stress the held loop's cores hold where they cross the profiles (its edge ends along x,
  // its screw sides along y), as tracking finds it in the kept frame. The float32 frame moves
  // tau_x by 6e-8 of tau_max and each bond's slip by about 4e-6 of its size: 1e-4 relative
  // with room.
  const auto held_in = [&](std::size_t row, const fs::path& nc) {
    const auto frames = asperity::app::read_snapshots(nc);
    const auto held = asperity::tracking::loop_core_stress(
        frames.at(0), asperity::tracking::find_lines(asperity::tracking::view_of(frames.at(0))));
    for (int a = 0; a < 2; ++a) {
      const std::string axis = a == 0 ? "x" : "y";
      ASSERT_EQ(held[a].crossings, 2) << axis;  // both ends (sides) of the one loop, resolved
      EXPECT_NEAR(slips.number(row, "loop_stress_" + axis), held[a].stress,
                  1e-4 * std::abs(held[a].stress) + 1e-7)
          << axis;
      EXPECT_NEAR(slips.number(row, "loop_tau_max_" + axis), held[a].tau_max,
                  1e-6 * held[a].tau_max)
          << axis;
    }
  };
  held_in(largest_k, point / "largest_slip" / "largest_slip_after.nc");
  held_in(k - 1, point / "largest_slip" / "latest_slip_after.nc");
  // The stress held all along the held loop (front_stresses): a contact large enough for its
  // windows (unlike the default slip's), so that the loop's front resolves all round, each
  // stretch holding less than the lattice's bound tau_max where it is, with the sign of the
  // crossings' (the loop is held against the sliding direction all round).
  {
    const auto frames =
        asperity::app::read_snapshots(point / "largest_slip" / "latest_slip_after.nc");
    const auto lines = asperity::tracking::find_lines(asperity::tracking::view_of(frames.at(0)));
    const auto front = asperity::tracking::front_stresses(frames.at(0), lines);
    const double sign = std::copysign(1.0, slips.number(k - 1, "loop_stress_x"));
    std::size_t resolved = 0;
    const asperity::tracking::FrontOptions options;
    for (const auto& p : front) {
      // What "resolved" means, recomputed (the track_loops.profiles fixtures resolve no point,
      // so this is where it is checked): the full window, widths local core widths either side
      // (b_core = d G / tau_max, MODEL.md 3) up to max_half_width, holding about one Burgers
      // vector of slip across it; a point short of either is not resolved.
      const double full = std::min(options.widths / p.tau_max, options.max_half_width);
      const bool whole = p.half_width >= full * (1 - 1e-12);
      EXPECT_EQ(p.cut, !whole) << p.at.x << ", " << p.at.y;
      const bool one_b = std::abs(p.held.slip) >= 0.75 && std::abs(p.held.slip) <= 1.25;
      EXPECT_EQ(p.resolved(), whole && one_b && std::isfinite(p.held.tau))
          << p.at.x << ", " << p.at.y << ": half width " << p.half_width << " of " << full
          << ", slip " << p.held.slip;
      if (!p.resolved()) continue;
      ++resolved;
      EXPECT_NEAR(p.half_width, full, 1e-9 * full) << p.at.x << ", " << p.at.y;
      EXPECT_LT(std::abs(p.held.tau), p.tau_max) << p.at.x << ", " << p.at.y;
      EXPECT_GT(sign * p.held.tau, 0.0) << p.at.x << ", " << p.at.y;
    }
    EXPECT_GE(resolved, front.size() * 9 / 10);
    EXPECT_GT(resolved, 10u);
  }

  // The arrested loop of Regime III (the fixture's scene comment: the first slip is the largest).
  EXPECT_EQ(largest_k, 0u);
  for (std::size_t r = 0; r < slips.rows(); ++r) {
    EXPECT_EQ(slips.integer(r, "loops"), 1) << "row " << r;
    // A held loop's cores hold less than the lattice's bound tau_max where they are.
    for (const char* axis : {"x", "y"}) {
      const double held = slips.number(r, std::string("loop_stress_") + axis);
      EXPECT_TRUE(std::isfinite(held)) << "row " << r << " " << axis;
      EXPECT_LT(std::abs(held), slips.number(r, std::string("loop_tau_max_") + axis));
    }
    EXPECT_GT(slips.number(r, "slipped_area"), 0.0) << "row " << r;
    if (r > 0) {
      EXPECT_LE(slips.number(r, "loop_area"), slips.number(r - 1, "loop_area")) << "row " << r;
      EXPECT_GE(slips.number(r, "slipped_area"), slips.number(r - 1, "slipped_area"))
          << "row " << r;
    }
  }
}

// A replayed slip (the state a period on equalled an earlier one, so the slide carries the cycle
// on instead of computing it) repeats a computed slip's numbers; its row in slips.csv says
// which slip, and a computed slip's says 0. The fixture: the default scene's Regime II contact,
// whose second slip is the first replayed a period (d, the aligned tip's) on.
TEST(FrictionSweepLargestSlip, ReplayedSlipsNameTheSlipTheyRepeat) {
  using asperity::app::CsvTable;
  const fs::path point = fs::path(REPLAY_DIR) / "points" / "a43_R535";
  const auto trace = CsvTable::read(point / "trace.csv");
  const auto slips = CsvTable::read(point / "largest_slip" / "slips.csv");
  std::size_t k = 0;
  int replayed = 0;
  for (std::size_t i = 0; i < trace.rows(); ++i) {
    if (trace.integer(i, "slip") == 0) continue;
    ASSERT_LT(k, slips.rows()) << "fewer rows than slips";
    const long long source = slips.integer(k, "replay_of");
    if (trace.integer(i, "replayed") == 0) {
      EXPECT_EQ(source, 0) << "slip " << k + 1 << " was computed";
    } else {
      ++replayed;
      // An earlier, computed slip, whose slipped sites, forces and lines these are, a whole
      // number of periods back.
      ASSERT_GE(source, 1) << "slip " << k + 1;
      ASSERT_LT(source, static_cast<long long>(k + 1)) << "slip " << k + 1;
      const auto j = static_cast<std::size_t>(source - 1);
      EXPECT_EQ(slips.integer(j, "replay_of"), 0);
      for (const char* column : {"slipped_sites", "loops", "open_lines"})
        EXPECT_EQ(slips.integer(k, column), slips.integer(j, column)) << column;
      for (const char* column : {"Fx_before", "Fx_after", "Fz", "slipped_area"})
        EXPECT_EQ(slips.number(k, column), slips.number(j, column)) << column;
      const double periods = slips.number(k, "Dx") - slips.number(j, "Dx");
      EXPECT_GE(periods, 1.0 - 1e-9);
      EXPECT_NEAR(periods, std::round(periods), 1e-9);
    }
    ++k;
  }
  EXPECT_EQ(k, slips.rows());
  ASSERT_GE(replayed, 1) << "the fixture's slide no longer replays a slip";
}

}  // namespace
