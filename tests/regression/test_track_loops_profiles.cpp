// track_loops --profiles --peierls on the relaxation path of the default scene's first slip (the
// frames of track_loops.slip, MODEL.md 3, 7) with the fits of the peierls_scan fixture: the
// seed's Fig. 9 made from a snapshot. Checks what must hold whatever the solver does:
// - every site of a profile has |tau_x| <= tau_max (the LFM's force is -tau_max sin(2 pi s/d));
// - the local Peierls columns are the fits' law at the local core width d G / tau_max, capped
//   at tau_max (recomputed here from the summary's k1, k2); the weakest column is the least of
//   every valid fit of the summary (the fixture's scan has screw, 63.4 degrees and edge), at
//   that fit's angle, and below edge and screw;
// - every core on a profile lies where tau_x changes sign between its neighbouring sites (a
//   core is such a sign change, MODEL.md 7), and frames with a loop crossing the row show it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "asperity/apps/common/output_files.hpp"

namespace {

namespace fs = std::filesystem;

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  return nlohmann::json::parse(in);
}

double law(const nlohmann::json& fit, double tau_max) {
  if (!(tau_max > 0.0)) return 0.0;
  return tau_max * std::min(1.0, fit.at("k1").get<double>() *
                                     std::exp(-fit.at("k2").get<double>() / tau_max));
}

TEST(TrackLoopsProfiles, ProfilesBoundTheStressAndMarkTheCores) {
  const fs::path dir = PROFILES;
  const auto fits = read_json(fs::path(PEIERLS) / "summary.json").at("fits");
  const auto frames = read_json(dir / "lines.json").at("frames");
  int profiled = 0, cores = 0, weakest_rows = 0, mixed_rows = 0;
  for (const auto& frame : frames) {
    if (frame.at("profiles").is_null()) continue;
    ++profiled;
    const auto& profiles = frame.at("profiles");
    const auto table = asperity::app::CsvTable::read(dir / profiles.at("table").get<std::string>());
    for (const char* axis : {"x", "y"}) {
      std::vector<double> position, tau;
      for (std::size_t i = 0; i < table.rows(); ++i) {
        if (table.text(i, "axis") != axis) continue;
        const double tau_max = table.number(i, "tau_max");
        const double tau_x = table.number(i, "tau_x");
        EXPECT_LE(std::abs(tau_x), tau_max * (1 + 1e-12) + 1e-300) << axis << " row " << i;
        EXPECT_NEAR(table.number(i, "tau_P_edge"), law(fits.at("edge"), tau_max), 1e-14);
        EXPECT_NEAR(table.number(i, "tau_P_screw"), law(fits.at("screw"), tau_max), 1e-14);
        if (tau_max > 0.0) {
          double least = INFINITY, theta = NAN;
          for (const auto& [key, fit] : fits.items()) {
            if (!fit.at("valid").get<bool>()) continue;
            if (const double t = law(fit, tau_max); t < least) {
              least = t;
              theta = fit.at("theta_deg").get<double>();
            }
          }
          EXPECT_NEAR(table.number(i, "tau_P_weakest"), least, 1e-14);
          EXPECT_EQ(table.number(i, "weakest_theta_deg"), theta);
          EXPECT_LE(table.number(i, "tau_P_weakest"), table.number(i, "tau_P_edge"));
          ++weakest_rows;
          if (theta > 0.0 && theta < 90.0) ++mixed_rows;
        }
        position.push_back(table.number(i, "position"));
        tau.push_back(tau_x);
      }
      ASSERT_GT(position.size(), 10u);
      EXPECT_TRUE(std::is_sorted(position.begin(), position.end()));
      for (const auto& core : profiles.at(axis).at("cores")) {
        ++cores;
        const double at = core.at("position").get<double>();
        const auto next = std::upper_bound(position.begin(), position.end(), at);
        ASSERT_TRUE(next != position.begin() && next != position.end()) << at;
        const auto k = static_cast<std::size_t>(next - position.begin());
        EXPECT_LE(tau[k - 1] * tau[k], 0.0)
            << "core at " << at << " along " << axis << " between sites with tau_x " << tau[k - 1]
            << " and " << tau[k];
      }
    }
  }
  EXPECT_GT(profiled, 3);
  // In this contact's core widths the 63.4-degree line is the weakest (docs/peierls.md).
  EXPECT_GT(weakest_rows, 100);
  EXPECT_EQ(mixed_rows, weakest_rows);
  // The slip's loop crosses the profiles in most of its frames.
  EXPECT_GT(cores, 4);
}

}  // namespace
