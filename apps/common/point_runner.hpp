// The pool that runs the points of a sweep (friction_sweep) or a scan (peierls_scan) side by
// side: one description of how points are handed out, stopped and failed.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>

namespace asperity::app {

// Runs points 0 .. count - 1 on `jobs` threads, each taking the next point when it has finished
// one, until every point has run, `stop` is set (by a point: its table could not be written), or
// a stop is requested (SIGINT, SIGTERM: stop_requested()); the points not begun are left for the
// next run, which continues from the table. The first exception a point lets out sets `stop`
// and is rethrown once the points in flight are done.
void run_points(std::size_t count, int jobs, const std::function<void(std::size_t)>& run,
                std::atomic<bool>& stop);

}  // namespace asperity::app
