// Unit tier: the explicit atomistic contact (core/explicit/explicit_contact.hpp).
// Checks: the interface force of a site is minus the gradient of its energy and the Hessian
// diagonal its second derivative (central differences); in hollow-site registry the apex atom
// is pushed straight down by its four tip neighbours; the unknown set grows when the margin is
// too small, to the same state; a/R >= 0.1 and bad scenes are rejected with the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "asperity/core/contact/hertz.hpp"
#include "asperity/core/explicit/explicit_contact.hpp"

using namespace asperity;
using namespace asperity::explicit_model;

TEST(ExplicitContact, ForceIsMinusGradient) {
  const ExplicitScene scene{.R = 200.0};
  ExplicitContact c(scene);
  c.set_active_radius(5.0);
  c.set_tip(0.3, scene.touch_height() - 0.05);
  // Sites (0, 0), (1, 0), (0, 1) of the lattice, displaced off symmetry.
  for (int I : {0, 1}) {
    const std::size_t i = c.block().shape.index(I - c.block().origin0, -c.block().origin1);
    double u[3] = {0.03, -0.02, -0.06 + 0.01 * I}, f[3], h[3];
    c.site_interface(i, u, f, h);
    ASSERT_GT(std::abs(f[2]), 0.0) << "no contact at site " << I;
    for (int k = 0; k < 3; ++k) {
      const double e = 1e-6;
      double up[3] = {u[0], u[1], u[2]}, um[3] = {u[0], u[1], u[2]}, fp[3], fm[3];
      up[k] += e, um[k] -= e;
      const double vp = c.site_interface(i, up, fp), vm = c.site_interface(i, um, fm);
      EXPECT_NEAR(f[k], -(vp - vm) / (2 * e), 1e-6 * (1.0 + std::abs(f[k]))) << k;
      EXPECT_NEAR(h[k], -(fp[k] - fm[k]) / (2 * e), 1e-5 * (1.0 + std::abs(h[k]))) << k;
    }
  }
}

TEST(ExplicitContact, ApexPushedStraightDown) {
  const ExplicitScene scene{.R = 500.0};
  ExplicitContact c(scene);
  c.set_active_radius(3.0);
  c.set_tip(0.0, scene.touch_height() - 0.02);
  const std::size_t i = c.block().shape.index(-c.block().origin0, -c.block().origin1);
  double u[3] = {0.0, 0.0, 0.0}, f[3];
  c.site_interface(i, u, f);
  EXPECT_LT(f[2], 0.0);
  EXPECT_NEAR(f[0], 0.0, 1e-12 * std::abs(f[2]));
  EXPECT_NEAR(f[1], 0.0, 1e-12 * std::abs(f[2]));
  // Just above the touch height nothing interacts.
  c.set_tip(0.0, scene.touch_height() + 1e-9);
  c.site_interface(i, u, f);
  EXPECT_EQ(f[2], 0.0);
}

TEST(ExplicitContact, UnknownSetGrowsToTheSameState) {
  const ExplicitScene scene{.R = 300.0};
  const double load = contact::Hertz::from_radius(scene.material, scene.R, 12.0).load;
  LoadOptions wide{.load = load, .margin = 3.0};
  LoadOptions tight{.load = load, .margin = 1.0};  // the loaded area reaches ~1 d past Hertz a
  const auto a = load_to_force(scene, wide);
  const auto b = load_to_force(scene, tight);
  ASSERT_EQ(a.termination, Termination::converged) << a.message;
  ASSERT_EQ(b.termination, Termination::converged) << b.message;
  EXPECT_GE(b.growths, 1);
  EXPECT_EQ(a.state.loaded_sites, b.state.loaded_sites);
  EXPECT_NEAR(a.delta, b.delta, 1e-6);
}

TEST(ExplicitContact, RejectsSteepContactsAndBadScenes) {
  try {
    load_to_force({.R = 100.0}, {.load = contact::Hertz::from_radius({}, 100.0, 10.0).load});
    FAIL() << "a/R = 0.1 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("a/R"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(require_small_slope(9.9, 100.0));
  EXPECT_THROW(ExplicitContact({.sigma_over_d = 0.6}), std::invalid_argument);
  EXPECT_THROW(ExplicitContact({.G_eps_sigma3 = 0.0}), std::invalid_argument);
  EXPECT_THROW(load_to_force({}, {.load = -1.0}), std::invalid_argument);
}
