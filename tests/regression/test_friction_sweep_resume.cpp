// Regression tier: friction_sweep resumes. The fixture runs the tiny sweep
// (tests/regression/sweep_tiny.toml: two Regime I points) into an empty folder, keeps a copy of
// its sweep.csv, and runs the same sweep again into the same folder. The second run must reuse
// both rows instead of recomputing them: its summary says so, and its table is byte-identical
// to the first (as a recomputed one would also be: the table holds no timings).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "asperity/apps/common/output_files.hpp"

namespace {

const std::filesystem::path kDir = SWEEP_DIR;

std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << "cannot read " << path;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TEST(FrictionSweepResume, SecondRunReusesBothPoints) {
  const auto summary = nlohmann::json::parse(slurp(kDir / "summary.json"));
  EXPECT_EQ(summary.at("points").get<int>(), 2);
  EXPECT_EQ(summary.at("reused").get<int>(), 2);
  EXPECT_EQ(summary.at("computed").get<int>(), 0);
  EXPECT_EQ(summary.at("failed").get<int>(), 0);
  EXPECT_EQ(slurp(kDir / "sweep.csv"), slurp(kDir / "sweep_first_run.csv"));
}

TEST(FrictionSweepResume, TableHoldsTheRegimeOnePoints) {
  const auto table = asperity::app::CsvTable::read(kDir / "sweep.csv");
  ASSERT_EQ(table.rows(), 2u);
  // Sorted by R, then a.
  EXPECT_EQ(table.number(0, "a"), 4.0);
  EXPECT_EQ(table.number(1, "a"), 6.0);
  for (std::size_t i = 0; i < table.rows(); ++i) {
    EXPECT_EQ(table.number(i, "R"), 535.0);
    EXPECT_EQ(table.integer(i, "failed"), 0) << table.text(i, "stop_reason");
    // Regime I: mu/alpha near 1; the sampled peak of a short fixed-distance slide may fall
    // below it, never far above.
    const double mu_over_alpha = table.number(i, "mu_over_alpha");
    EXPECT_GT(mu_over_alpha, 0.5) << "a = " << table.number(i, "a");
    EXPECT_LE(mu_over_alpha, 1.05) << "a = " << table.number(i, "a");
    // append() rather than "a" + string: GCC 12 warns falsely (-Wrestrict) on the latter.
    const auto point =
        kDir / "points" / std::string("a").append(table.text(i, "a")).append("_R535");
    EXPECT_TRUE(std::filesystem::exists(point / "summary.json")) << point;
    EXPECT_TRUE(std::filesystem::exists(point / "trace.csv")) << point;
  }
}
