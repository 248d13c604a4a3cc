// Regression tier: gf_validate on the default scene against data/reference/gf_validation.json.
// Compared: the physical results (Hertz contact radius, approach, load; bonded-disk stiffness;
// far-field error), to a relative 1e-8: they are deterministic, and a change beyond round-off
// means the discretisation or a solver changed and the reference must be re-examined
// (regenerate it with the command stored in the reference file).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

namespace {
nlohmann::json load(const char* path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "cannot read " << path;
  return nlohmann::json::parse(in);
}
}  // namespace

TEST(GfValidationRegression, MatchesStoredAnswers) {
  const auto got = load(SUMMARY);
  const auto ref = load(REFERENCE);
  for (const auto& [section, keys] : ref.at("compare").items()) {
    for (const auto& key : keys) {
      const double want = ref.at("values").at(section).at(key.get<std::string>()).get<double>();
      const double have = got.at(section).at(key.get<std::string>()).get<double>();
      EXPECT_NEAR(have, want, 1e-8 * std::abs(want) + 1e-14) << section << "." << key;
    }
  }
  for (const char* section : {"hertz", "bonded_disk", "far_field"}) {
    EXPECT_TRUE(got.at(section).at("pass").get<bool>()) << section;
  }
}
