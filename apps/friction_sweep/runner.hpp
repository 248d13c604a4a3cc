// friction_sweep's point runner: plans the points still to run (cheapest first), checks that
// the largest of them fit in memory (and their snapshots on disk), runs them through
// Ranks::run_points (threads, and MPI ranks under mpirun) with checkpoints, progress lines and
// frame sinks, and records each finished point's row in its table as it comes in (runner.cpp).
// main.cpp wires the options to it; report.cpp writes what the sweep found once every point is in.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>

#include "asperity/apps/common/mpi_points.hpp"
#include "sweep.hpp"

namespace asperity::app {

struct SweepRunOptions {
  std::filesystem::path out;  // output directory
  bool figures = false;       // per point also figures and snapshots (as contact_slide)
  bool largest_slip = false;  // per point the states of its largest slip
  RunControl control;         // checkpoints and progress lines of the running points
  // Continue points' checkpoints and keep finished rows of another build or of other slide.*,
  // solver.* and fft.* settings of the same problem (slide_checkpoint.hpp, adoption)
  bool adopt = false;
  // Only say what the sweep would do (its points, what each needs, the rows an existing table
  // in `out` would keep) and return, writing nothing
  bool plan = false;
  // Only write the states held by the checkpoints of the points in `out` (the last accepted
  // state, the peak and a paused slip flow's) as NetCDF into points/<point>/peek/ and return:
  // a run is looked at while it runs, inside a slip flow of hours
  bool peek = false;
  std::string command_line;  // printed when a stopped sweep says how to continue
};

// Runs the sweep of scene `s` (validated) into options.out and writes its results; returns the
// exit status (kInterrupted if stopped with points left, 1 if a point failed). Over MPI ranks
// (mpi_points.hpp) rank 0 plans, records and reports, and every rank runs points; the other
// ranks return 0 once the points are done (their exit status is rank 0's).
int run_sweep(const SweepScene& s, const SweepRunOptions& options, Ranks& ranks);

}  // namespace asperity::app
