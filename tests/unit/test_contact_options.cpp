// The options of the normal-contact (Polonsky-Keer) and bonded (CG) solvers: their settings
// tables are what validate() checks and what gf_validate lifts, so a bad value is refused by
// its key with the allowed set, both by validate() and by the solver before any work.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "asperity/core/contact/bonded.hpp"
#include "asperity/core/contact/normal_contact.hpp"
#include "common/messages.hpp"

using namespace asperity;

using asperity::test_support::invalid_argument_message;

TEST(ContactOptions, DefaultsAreAllowed) {
  EXPECT_NO_THROW(contact::NormalContactOptions{}.validate());
  EXPECT_NO_THROW(contact::BondedOptions{}.validate());
  EXPECT_EQ(contact::NormalContactOptions::settings().size(), 2U);
  EXPECT_EQ(contact::BondedOptions::settings().size(), 2U);
}

TEST(ContactOptions, ChecksNameTheKeyAndTheAllowedSet) {
  EXPECT_EQ(
      invalid_argument_message([] { contact::NormalContactOptions{.tolerance = 0.0}.validate(); }),
      "tolerance = 0: allowed: (0, 1)");
  EXPECT_EQ(
      invalid_argument_message([] { contact::NormalContactOptions{.tolerance = 1.0}.validate(); }),
      "tolerance = 1: allowed: (0, 1)");
  EXPECT_EQ(invalid_argument_message(
                [] { contact::NormalContactOptions{.max_iterations = 0}.validate(); }),
            "max_iterations = 0: allowed: an integer [1, 1000000000]");
  EXPECT_EQ(invalid_argument_message([] { contact::BondedOptions{.tolerance = -1e-9}.validate(); }),
            "tolerance = -1e-09: allowed: (0, 1)");
  EXPECT_EQ(
      invalid_argument_message([] { contact::BondedOptions{.max_iterations = -3}.validate(); }),
      "max_iterations = -3: allowed: an integer [1, 1000000000]");
}

TEST(ContactOptions, SolversRefuseBadOptionsBeforeWork) {
  elastic::FreeSurfaceGF gf(elastic::Material{}, elastic::Components::normal, Shape2{8, 8});
  const std::vector<double> heights(gf.size(), 0.0);
  EXPECT_EQ(invalid_argument_message(
                [&] { contact::solve_normal_contact(gf, heights, 1.0, {.tolerance = 2.0}); }),
            "tolerance = 2: allowed: (0, 1)");
  EXPECT_EQ(gf.applications(), 0U);

  elastic::FreeSurfaceGF shear(elastic::Material{}, elastic::Components::in_plane, Shape2{8, 8});
  const std::vector<std::uint8_t> mask(shear.region().n0 * shear.region().n1, 1);
  const std::vector<double> prescribed(shear.size(), 1.0);
  EXPECT_EQ(invalid_argument_message(
                [&] { contact::solve_bonded(shear, mask, prescribed, {.max_iterations = 0}); }),
            "max_iterations = 0: allowed: an integer [1, 1000000000]");
  EXPECT_EQ(shear.applications(), 0U);
}
