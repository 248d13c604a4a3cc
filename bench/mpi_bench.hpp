// What the MPI benchmarks (bench_gf_mpi, bench_iteration_mpi; issue 26) share: MPI started for
// FFTW threads inside ranks, and the per-rank measures they report.
#pragma once

#include <mpi.h>
#include <sys/resource.h>

namespace asperity::bench {

// MPI_Init_thread with MPI_THREAD_FUNNELED (FFTW's threads are the main thread's); the rank and
// the number of ranks of MPI_COMM_WORLD.
inline void init_mpi(int& argc, char**& argv, int& rank, int& ranks) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
}

// This process's peak resident memory (MB; getrusage's ru_maxrss is in KiB on Linux).
inline double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}

// The largest value over the ranks (the slowest rank's time).
inline double max_over_ranks(double v) {
  MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return v;
}

}  // namespace asperity::bench
