// Regression tier: contact_slide --model explicit on data/scenes/explicit_default.toml against
// data/reference/explicit_load.json (approach, contact radii, alpha of the potential, loaded
// atoms), each within the tolerance stored with it. The Hertz comparison itself is the analytic
// tier's (tests/analytic/test_explicit_hertz.cpp); this guards the numbers of the tool.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

TEST(ExplicitLoadRegression, MatchesReference) {
  std::ifstream s(SUMMARY), r(REFERENCE);
  ASSERT_TRUE(s && r) << SUMMARY << " / " << REFERENCE;
  const auto summary = nlohmann::json::parse(s), ref = nlohmann::json::parse(r);
  EXPECT_EQ(summary.at("termination"), "converged");
  EXPECT_EQ(summary.at("model"), "explicit");
  for (const char* key : {"delta", "a_area", "a_moment", "alpha", "loaded_sites"}) {
    const double value = summary.at(key).get<double>();
    const double want = ref.at(key).at("value").get<double>();
    const double tol = ref.at(key).at("tolerance").get<double>();
    EXPECT_LE(std::abs(value - want), tol) << key << ": " << value << " vs " << want;
  }
  // Every setting echoed by its key, the run's flag (--threads 1) among them, the potential's
  // with the slide scene's.
  const auto& settings = summary.at("settings");
  EXPECT_EQ(settings.at("fft.threads"), 1);
  EXPECT_EQ(settings.at("contact.a").get<double>(), summary.at("a").get<double>());
  EXPECT_EQ(settings.at("explicit.sigma_over_d").get<double>(),
            summary.at("sigma_over_d").get<double>());
  EXPECT_TRUE(settings.contains("solver.tolerance"));
  // Not contact.alpha: the explicit model's alpha is the potential's (summary "alpha").
  EXPECT_FALSE(settings.contains("contact.alpha"));
}
