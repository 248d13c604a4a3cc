// Regression tier: friction_sweep with both models (sweep.model = "both";
// tests/regression/sweep_models.toml: R = 160 d, a/b_core^0 = 0.3, 1, 2.6).
//
// - The explicit rows go to sweep_explicit.csv with the columns of sweep.csv. Each explicit
//   target is met with the alpha of the potential at that point's central load: alpha in the
//   table is that alpha (0.70-0.73 at sigma/d = 2^(-1/6), docs/explicit.md), and a/b_core^0
//   equals the target to 1e-6 (the fixed point on alpha(a) converges in 3 rounds: alpha varies
//   by 2% over 100x in load).
// - mu/alpha of each explicit point agrees with the stored answer
//   data/reference/sweep_explicit_R160.csv within kMuTolerance, and so do the slip events. The
//   tolerance: the minimiser stops at a force residual of 1e-6 G d^2 per site, which moves
//   Fx/Fz by ~1e-5 on these contacts; 1e-3 leaves room for another compiler's round-off to
//   change the peak refinement's path, and is far below what a change of physics would do
//   (the points differ by 0.15 to 0.3 in mu/alpha).
// - summary.json "explicit_vs_lfm" holds the ratio at every explicit point, recomputed here
//   from the two tables (the LFM rows sit at the same targets, so no interpolation is needed),
//   and collapse.png exists.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "asperity/apps/common/output_files.hpp"

namespace {

namespace fs = std::filesystem;
const fs::path kDir = SWEEP_DIR;
const fs::path kReference = REFERENCE;
constexpr double kMuTolerance = 1e-3;

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << "cannot read " << path;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

using asperity::app::CsvTable;

}  // namespace

TEST(SweepModels, ExplicitRowsMeetTheTargetsWithTheAlphaOfThePotential) {
  const auto table = CsvTable::read(kDir / "sweep_explicit.csv");
  ASSERT_EQ(table.rows(), 3u);
  const double targets[] = {0.3, 1.0, 2.6};
  for (std::size_t i = 0; i < table.rows(); ++i) {
    EXPECT_EQ(table.integer(i, "failed"), 0) << table.text(i, "stop_reason");
    EXPECT_NEAR(table.number(i, "a_over_bcore0") / targets[i], 1.0, 1e-6);
    EXPECT_GT(table.number(i, "alpha"), 0.70);
    EXPECT_LT(table.number(i, "alpha"), 0.73);
    EXPECT_LT(table.number(i, "a") / table.number(i, "R"), 0.1);
  }
}

TEST(SweepModels, ExplicitMuOverAlphaMatchesTheStoredAnswer) {
  const auto table = CsvTable::read(kDir / "sweep_explicit.csv");
  const auto reference = CsvTable::read(kReference);
  ASSERT_EQ(table.rows(), reference.rows());
  for (std::size_t i = 0; i < table.rows(); ++i) {
    EXPECT_NEAR(table.number(i, "a"), reference.number(i, "a"), 1e-9 * reference.number(i, "a"));
    EXPECT_NEAR(table.number(i, "mu_over_alpha"), reference.number(i, "mu_over_alpha"),
                kMuTolerance)
        << "a/b_core^0 = " << reference.number(i, "a_over_bcore0");
    EXPECT_EQ(table.integer(i, "slip_events"), reference.integer(i, "slip_events"));
  }
}

TEST(SweepModels, SummaryComparesTheModelsPointByPoint) {
  const auto summary = nlohmann::json::parse(slurp(kDir / "summary.json"));
  EXPECT_EQ(summary.at("points").get<int>(), 6);
  EXPECT_EQ(summary.at("explicit_points").get<int>(), 3);
  EXPECT_EQ(summary.at("failed").get<int>(), 0);
  const auto& cmp = summary.at("explicit_vs_lfm");
  const auto lfm = CsvTable::read(kDir / "sweep.csv");
  const auto expl = CsvTable::read(kDir / "sweep_explicit.csv");
  ASSERT_EQ(cmp.at("points").size(), 3u);
  double worst = 0.0;
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& p = cmp.at("points")[i];
    ASSERT_FALSE(p.at("ratio").is_null()) << p.dump();
    const double ratio = expl.number(i, "mu_over_alpha") / lfm.number(i, "mu_over_alpha");
    EXPECT_NEAR(p.at("ratio").get<double>(), ratio, 1e-12);
    worst = std::max(worst, std::abs(ratio - 1.0));
  }
  EXPECT_EQ(cmp.at("compared_in_window").get<int>(), 3);
  EXPECT_NEAR(cmp.at("max_deviation_in_window").get<double>(), worst, 1e-12);
  EXPECT_TRUE(fs::exists(kDir / "collapse.png"));
  for (std::size_t i = 0; i < 3; ++i) {
    char folder[96];
    std::snprintf(folder, sizeof folder, "explicit_a%.6g_R160", expl.number(i, "a"));
    EXPECT_TRUE(fs::exists(kDir / "points" / folder / "summary.json")) << folder;
  }
}
