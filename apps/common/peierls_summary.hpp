// Reads a fit of the Peierls law tau_P = k1 tau_max exp(-k2 b_core / d) (MODEL.md 6) from a
// peierls_scan summary.json: fit_scaling takes the edge fit for the Regime III law, track_loops
// the edge and screw fits for the local Peierls stress beside a stress profile.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "asperity/nucleation/regime_three.hpp"

namespace asperity::app {

struct PeierlsSummaryFit {
  nucleation::PeierlsLaw law;        // k1, k2, their errors (plain standard errors), window
  int points = 0;                    // resolved cell results the fit used
  int L = 0;                         // cell size of the scan (0: not recorded)
  bool correlation_missing = false;  // a summary written before k1_k2_correlation: taken as 0
  std::filesystem::path file;        // the summary read
};

// `path`: the summary or its folder; `character`: a key of its "fits" ("edge", "screw",
// "theta_45.0"). Every number is checked: a missing, mistyped or invalid entry throws
// std::invalid_argument naming the file and the key.
PeierlsSummaryFit read_peierls_fit(const std::filesystem::path& path, const std::string& character);

// Every valid fit of the summary, one per line angle the scan made ("edge", "screw",
// "theta_45.0", ...), each read and checked as read_peierls_fit does; fits marked not valid
// (too few resolved points in the window) are left out. Throws as read_peierls_fit for a file
// that is not a summary with fits, or a valid fit with a bad number or no theta_deg.
struct PeierlsAngleFit {
  std::string key;         // the key in "fits"
  double theta_deg = 0.0;  // line angle (0 screw, 90 edge)
  PeierlsSummaryFit fit;
};
std::vector<PeierlsAngleFit> read_peierls_fits(const std::filesystem::path& path);

}  // namespace asperity::app
