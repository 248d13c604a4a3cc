// Unit tier: the slip test of MODEL.md 5 (slide::registry_jumps): a slip is a jump of a site's
// registry index round(s/d), which a core gliding by one spacing makes although no site moves by
// d/2; a smooth crossing of the barrier top is not one.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "asperity/core/slide/slider.hpp"

using namespace asperity;

namespace {

struct Block {
  explicit Block(const interface::ContactScene& s) : scene(s) {
    const int h = static_cast<int>(std::ceil(s.a / s.d)) + 2;
    block = LatticeBlock{Shape2{2 * h + 1, 2 * h + 1}, -h, -h};
  }
  [[nodiscard]] std::size_t sites() const { return block.shape.count(); }
  [[nodiscard]] double X(std::size_t i) const {
    return block.x(static_cast<int>(i / static_cast<std::size_t>(block.shape.n1)), scene.d);
  }
  [[nodiscard]] double Y(std::size_t i) const {
    return block.y(static_cast<int>(i % static_cast<std::size_t>(block.shape.n1)), scene.d);
  }
  [[nodiscard]] bool in_contact(std::size_t i, double Dx) const {
    return std::hypot(X(i) - Dx, Y(i)) < scene.a;
  }
  interface::ContactScene scene;
  LatticeBlock block;
};

// Peierls-Nabarro profile of a straight line along y at x = x0 with Burgers vector d x-hat (an
// edge line: b is normal to the line): u_x = d/2 + (d/pi) atan((x - x0)/w), w = b_core / 2.
std::vector<double> edge_line(const Block& b, double x0, double b_core) {
  const std::size_t n = b.sites();
  std::vector<double> u(2 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    u[i] =
        0.5 * b.scene.d + b.scene.d / std::numbers::pi * std::atan((b.X(i) - x0) / (0.5 * b_core));
  return u;
}

}  // namespace

TEST(SlipDetection, CoreGlideByOneSpacingIsASlip) {
  // Analytic answer: gliding the line from x0 = 0.3 d to 1.3 d moves the sites of the column
  // X = 1 d from u_x < d/2 to u_x > d/2: their registry index changes, and only theirs. The
  // largest displacement change is (2d/pi) atan(d / b_core) = 0.32 d at b_core = 1.87 d, below
  // the d/2 of the former test and above the d/4 floor.
  const interface::ContactScene scene { .a = 10.0, .R = 100.0 };
  const Block b(scene);
  const double b_core = 1.87;
  const auto before = edge_line(b, 0.3, b_core), after = edge_line(b, 1.3, b_core);
  double largest = 0.0;
  int column = 0;
  for (std::size_t i = 0; i < b.sites(); ++i) {
    largest = std::max(largest, std::abs(after[i] - before[i]));
    if (b.X(i) == 1.0 && b.in_contact(i, 0.0)) ++column;
  }
  EXPECT_NEAR(largest, 2.0 / std::numbers::pi * std::atan(1.0 / b_core), 0.02);
  EXPECT_LT(largest, 0.5);
  ASSERT_GT(column, 15);
  EXPECT_EQ(slide::registry_jumps(scene, b.block, 0.0, before, 0.0, after), column);
  // The reverse glide is a slip of the same sites.
  EXPECT_EQ(slide::registry_jumps(scene, b.block, 0.0, after, 0.0, before), column);
}

TEST(SlipDetection, SmoothCrossingOfTheBarrierIsNoSlip) {
  // A contact that slides smoothly (Regime I): the tip moves from 0.45 d to 0.55 d and every
  // site's s = X + u - Dx goes from -0.45 d to -0.53 d and crosses the barrier top with u moving by
  // 0.02 d: every
  // registry index changes, by a crossing rather than a jump.
  const interface::ContactScene scene { .a = 10.0, .R = 100.0 };
  const Block b(scene);
  std::vector<double> before(2 * b.sites(), 0.0), after(2 * b.sites(), 0.0);
  int crossing = 0;
  for (std::size_t i = 0; i < b.sites(); ++i) {
    after[i] = 0.02;
    if (b.in_contact(i, 0.45) && b.in_contact(i, 0.55) &&
        std::lround(b.X(i) - 0.45) != std::lround(b.X(i) + 0.02 - 0.55))
      ++crossing;
  }
  ASSERT_GT(crossing, 250);  // the index did change nearly everywhere
  EXPECT_EQ(slide::registry_jumps(scene, b.block, 0.45, before, 0.55, after), 0);
}

TEST(SlipDetection, AJumpToTheNextWellIsASlipOfEverySite) {
  // Every site falls back by one period (a whole-contact slip): each site in the contact at both
  // tip positions counts once, whichever component it jumped in.
  const interface::ContactScene scene { .a = 10.0, .R = 100.0 };
  const Block b(scene);
  const std::size_t n = b.sites();
  std::vector<double> before(2 * n, 0.0), after_x(2 * n, 0.0), after_y(2 * n, 0.0);
  int both = 0;
  for (std::size_t i = 0; i < n; ++i) {
    before[i] = 0.2;     // s_x = X + 0.2 - 0.4 = X - 0.2
    after_x[i] = -0.75;  // s_x = X - 0.75 - 0.41: one well back
    after_y[i] = 0.21;
    after_y[n + i] = 0.9;  // s_y = Y + 0.9: one well on in y
    if (b.in_contact(i, 0.4) && b.in_contact(i, 0.41)) ++both;
  }
  EXPECT_EQ(slide::registry_jumps(scene, b.block, 0.4, before, 0.41, after_x), both);
  EXPECT_EQ(slide::registry_jumps(scene, b.block, 0.4, before, 0.41, after_y), both);
  // Rows that entered the block between the states are not compared.
  EXPECT_LT(slide::registry_jumps(scene, b.block, 0.4, before, 0.41, after_x, 3), both);
  EXPECT_THROW(slide::registry_jumps(scene, b.block, 0.4, std::vector<double>(3), 0.41, after_x),
               std::invalid_argument);
}
