// friction_sweep's report of a finished sweep (report.cpp): figures, the Regime II slope, the
// comparison of the two models, summary.json and the lines printed.
#pragma once

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "sweep.hpp"

namespace asperity::app {

// How many points a sweep had, and how many it computed and reused; how many it ran at once on
// each of how many MPI ranks (1: one process), and how they checkpointed and reported.
struct SweepCounts {
  std::size_t points = 0, explicit_points = 0, computed = 0, reused = 0;
  int jobs = 1, ranks = 1;
  RunControl control;
};

// The end of a sweep whose points are all in. Returns the exit status (1 if a point failed).
int finish_sweep(const std::filesystem::path& dir, const SweepScene& s,
                 const std::vector<SweepRow>& done, const std::vector<SweepRow>& done_x,
                 const SweepCounts& n, std::chrono::steady_clock::time_point t0);

// "1, 2.5, 10": a list of values for a progress line.
std::string describe_list(const std::vector<double>& v);

}  // namespace asperity::app
