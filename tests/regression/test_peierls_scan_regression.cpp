// Regression tier: peierls_scan against a stored table, and its resumption.
// - data/reference/peierls_L128.csv: a small grid (L = 128; b_core 2, 4, 6 d; screw, 63.4
//   degrees, edge); the second run (same settings) must reuse every point and leave the table
//   unchanged.
// - data/reference/peierls_narrow_cores.csv: the core widths at the centres of the largest
//   contacts (b_core 1.5, 1.87, 2 d) at 13 line angles, the cell grown until tau_P holds to 1%;
//   only the table is compared (test peierls_scan.narrow_cores.regression).
// The scan's folder and the table are the first two arguments (defaults: the L = 128 scan).
// Tolerances: tau_P/tau_max within 0.5% (the bracket's half-width is 0.1% and the force tolerance
// moves tau_P by less than that), resolved flags exact, core width within 0.5%.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "asperity/apps/common/output_files.hpp"

using asperity::app::CsvTable;

namespace {
std::string scan_dir = SCAN_DIR;
std::string reference = REFERENCE;
}  // namespace

TEST(PeierlsScanRegression, MatchesTheStoredTable) {
  const CsvTable now = CsvTable::read(scan_dir + "/peierls.csv");
  const CsvTable ref = CsvTable::read(reference);
  ASSERT_EQ(now.rows(), ref.rows());
  for (std::size_t i = 0; i < ref.rows(); ++i) {
    SCOPED_TRACE("b_core " + ref.text(i, "b_core") + ", theta " + ref.text(i, "theta_deg"));
    EXPECT_EQ(now.number(i, "b_core"), ref.number(i, "b_core"));
    EXPECT_EQ(now.integer(i, "m_x"), ref.integer(i, "m_x"));
    EXPECT_EQ(now.integer(i, "m_y"), ref.integer(i, "m_y"));
    for (const char* sign : {"pos", "neg"}) {
      const std::string resolved = std::string("resolved_") + sign;
      const std::string tau = std::string("tau_P_over_tau_max_") + sign;
      ASSERT_EQ(now.integer(i, resolved), ref.integer(i, resolved));
      if (ref.integer(i, resolved) != 0) {
        EXPECT_NEAR(now.number(i, tau) / ref.number(i, tau), 1.0, 5e-3);
      } else {
        EXPECT_TRUE(now.text(i, tau).empty()) << "an unresolved threshold must not be a number";
      }
    }
    EXPECT_NEAR(now.number(i, "core_width") / ref.number(i, "core_width"), 1.0, 5e-3);
  }
}

TEST(PeierlsScanRegression, ResumedRunReusesEveryPoint) {
  std::ifstream in(scan_dir + "/summary.json");
  ASSERT_TRUE(in) << "no summary.json";
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s.at("reused").get<int>(), s.at("points").get<int>());
  EXPECT_EQ(s.at("computed").get<int>(), 0);
  EXPECT_EQ(s.at("unresolved_points").get<int>(), 0);
  for (const char* c : {"edge", "screw"}) {
    ASSERT_TRUE(s.at("fits").at(c).at("valid").get<bool>()) << c;
    EXPECT_GT(s.at("fits").at(c).at("k2").get<double>(), 0.0) << c;
  }
  const CsvTable first = CsvTable::read(scan_dir + "/peierls_first_run.csv");
  const CsvTable second = CsvTable::read(scan_dir + "/peierls.csv");
  EXPECT_EQ(first.to_string(), second.to_string());
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  if (argc > 1) scan_dir = argv[1];
  if (argc > 2) reference = argv[2];
  return RUN_ALL_TESTS();
}
