// track_loops on the snapshots of a Peierls cell (MODEL.md sections 6 and 7): peierls_scan
// --snapshots writes the relaxed and the loaded cell (L = 64, b_core = 4 d) holding one straight
// dislocation, b = d x-hat, whose line is perpendicular to the frustration vector (m_x, m_y).
//
// Expected, exactly from the construction: in every frame exactly one line, of kind "wrapping"
// (it closes only through the cell's sides), |Burgers vector| = 1 with every crossing agreeing
// (registry consistency 1), mean angle between line and b equal to theta = atan(m_x/m_y):
// 0 (screw), 90 (edge), 63.43 degrees; length = the line's period in the cell, L |m| d
// (64, 64, 64 sqrt 5 = 143.1 d). Tolerances: none on the count, kind or Burgers vector; angle
// 0.5 degree; length 1e-6 relative for lines along the lattice (the polyline is straight) and
// 1% for the 63.4 degree line, whose marching-squares polyline crosses the lattice cells in a
// zigzag (measured +0.5%).
// The frustration winds the registry across the cell's sides by (m_x, m_y): before
// track_loops measured that winding, the cells' sides were reported as extra lines with
// Burgers vectors -2 and -64.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

namespace {

struct Case {
  const char* point;
  double theta_deg;
  double length;
  double length_tolerance;  // relative
};

class TrackPeierls : public ::testing::TestWithParam<Case> {};

TEST_P(TrackPeierls, OneWrappingLineWithTheCellsCharacter) {
  const Case& c = GetParam();
  std::ifstream in(std::string(TRACKS) + "/" + c.point + "/lines.json");
  ASSERT_TRUE(in.good()) << c.point;
  const auto lines = nlohmann::json::parse(in);
  const auto& frames = lines.at("frames");
  ASSERT_EQ(frames.size(), 2u) << "relaxed and loaded cell";
  for (const auto& f : frames) {
    const auto& ls = f.at("lines");
    ASSERT_EQ(ls.size(), 1u) << c.point << " " << f.at("label");
    const auto& l = ls[0];
    EXPECT_EQ(l.at("kind"), "wrapping") << c.point;
    EXPECT_EQ(std::abs(l.at("burgers_x").get<double>()), 1.0) << c.point;
    EXPECT_EQ(l.at("registry_consistency").get<double>(), 1.0) << c.point;
    EXPECT_NEAR(l.at("mean_angle_deg").get<double>(), c.theta_deg, 0.5) << c.point;
    EXPECT_NEAR(l.at("length").get<double>(), c.length, c.length_tolerance * c.length) << c.point;
  }
}

INSTANTIATE_TEST_SUITE_P(Cells, TrackPeierls,
                         ::testing::Values(Case{"b4_m0_1", 0.0, 64.0, 1e-6},
                                           Case{"b4_m1_0", 90.0, 64.0, 1e-6},
                                           Case{"b4_m2_1", 63.43, 64.0 * std::sqrt(5.0), 0.01}),
                         [](const auto& p) { return std::string(p.param.point); });

}  // namespace
