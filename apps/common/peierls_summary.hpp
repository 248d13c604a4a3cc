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

// Every line angle of a peierls_scan folder (or its summary.json): the angle's valid fit, read
// and checked as read_peierls_fit does (fits marked not valid, too few resolved points in the
// window, have none), and, if the scan's table peierls.csv is beside the summary, the angle's
// resolved values as samples (the smaller of the two signs' thresholds at each b_core), which
// nucleation::local_peierls_stress interpolates inside their range. Throws
// std::invalid_argument for a file that is not a summary with fits, a valid fit with a bad
// number or no theta_deg, or a table with a bad row.
struct PeierlsAngles {
  std::vector<nucleation::AngleLaw> angles;  // ascending theta
  std::vector<std::string> fit_keys;         // the fit's key per angle ("" for none)
  std::filesystem::path summary, table;      // the files read (table: empty if none)
};
PeierlsAngles read_peierls_angles(const std::filesystem::path& path);

}  // namespace asperity::app
