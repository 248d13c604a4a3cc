// friction_sweep's point runner: plans the points still to run (cheapest first), checks that
// the largest of them fit in memory (and their snapshots on disk), runs them through
// app::run_points with checkpoints, progress lines and frame sinks, and records each finished
// point's row in its table as it comes in (runner.cpp). main.cpp wires the options to it;
// report.cpp writes what the sweep found once every point is in.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>

#include "sweep.hpp"

namespace asperity::app {

struct SweepRunOptions {
  std::filesystem::path out;      // output directory
  bool figures = false;           // per point also figures and snapshots (as contact_slide)
  bool largest_slip = false;      // per point the states of its largest slip
  double checkpoint_every = 300;  // seconds of run time between a point's checkpoints
  double progress_every = 60;     // seconds between progress lines of a running point (0: none)
  std::string command_line;       // printed when a stopped sweep says how to continue
};

// Runs the sweep of scene `s` (validated) into options.out and writes its results; returns the
// exit status (kInterrupted if stopped with points left, 1 if a point failed).
int run_sweep(const SweepScene& s, const SweepRunOptions& options);

}  // namespace asperity::app
