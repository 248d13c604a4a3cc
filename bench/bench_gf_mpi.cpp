// One free-surface GF application (the unit of cost of every solver) on the FFTW-MPI engine,
// per rank: wall time (median of repeats, the slowest rank's), the share spent in the
// transforms and their all-to-all exchanges (engine convolve) against the copies in and out,
// and each rank's peak resident memory and grid memory. Run under mpirun by
// bench/run_mpi.sh, which records docs/benchmarks.md's MPI section (issue 26).
//
// Usage: bench_gf_mpi <n0> <n1> [repeats] [threads]: an n0 x n1 region (padded grid
// next_fft_size(2 n - 1) per axis), in-plane components (the lateral force model's).
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "asperity/core/elastic/surface_gf.hpp"
#include "asperity/core/fft/fftw_mpi_engine.hpp"

#include "mpi_bench.hpp"

using namespace asperity;
using bench::max_over_ranks;
using bench::peak_rss_mb;

namespace {}  // namespace

int main(int argc, char** argv) {
  int rank = 0, ranks = 1;
  bench::init_mpi(argc, argv, rank, ranks);
  if (argc < 3) {
    if (rank == 0) std::fprintf(stderr, "usage: bench_gf_mpi n0 n1 [repeats] [threads]\n");
    MPI_Finalize();
    return 2;
  }
  // The GF (its FFTW-MPI plans hold a communicator) must be gone before MPI_Finalize.
  {
    const Shape2 region{std::atoi(argv[1]), std::atoi(argv[2])};
    const int repeats = argc > 3 ? std::atoi(argv[3]) : 5;
    fft::FFTOptions fo;
    fo.threads = argc > 4 ? std::atoi(argv[4]) : 1;
    const double rss_before = peak_rss_mb();
    const auto t_setup = std::chrono::steady_clock::now();
    elastic::FreeSurfaceGF gf({1.0, 0.5}, elastic::Components::in_plane, region, 1.0, fo,
                              fft::mpi_engine_factory(MPI_COMM_WORLD));
    const double setup_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_setup).count();
    std::vector<double> f(gf.size()), u(gf.size());
    std::mt19937_64 rng(1 + static_cast<unsigned>(rank));
    std::uniform_real_distribution<double> dist(-1.0, 1.0);
    for (double& x : f)
      x = dist(rng);
    std::vector<double> times;
    for (int r = 0; r < repeats; ++r) {
      MPI_Barrier(MPI_COMM_WORLD);
      const auto t0 = std::chrono::steady_clock::now();
      gf.apply(f, u);
      times.push_back(max_over_ranks(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()));
    }
    std::sort(times.begin(), times.end());
    const double median = times[times.size() / 2];
    const double rss = peak_rss_mb();  // before the serial GF below
    // With one rank, the serial engine beside it (it skips the padding rows' transforms).
    double serial_median = 0.0;
    if (ranks == 1) {
      elastic::FreeSurfaceGF serial({1.0, 0.5}, elastic::Components::in_plane, region, 1.0, fo);
      std::vector<double> ts;
      for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        serial.apply(f, u);
        ts.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      std::sort(ts.begin(), ts.end());
      serial_median = ts[ts.size() / 2];
    }

    std::vector<double> all(static_cast<std::size_t>(ranks));
    MPI_Gather(&rss, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    const double setup = max_over_ranks(setup_s);
    if (rank == 0) {
      const Shape2 padded = gf.fft_shape();
      std::printf(
          "{\"ranks\": %d, \"threads\": %d, \"region\": [%d, %d], \"padded\": [%d, %d], "
          "\"apply_s_median\": %.6g, \"apply_s_min\": %.6g, \"setup_s\": %.4g, "
          "\"peak_rss_mb_per_rank\": [",
          ranks, fo.threads, region.n0, region.n1, padded.n0, padded.n1, median, times[0], setup);
      for (int k = 0; k < ranks; ++k)
        std::printf("%s%.1f", k ? ", " : "", all[static_cast<std::size_t>(k)]);
      std::printf("], \"rss_before_mb\": %.1f, \"serial_apply_s_median\": %.6g}\n", rss_before,
                  serial_median);
    }
  }
  MPI_Finalize();
  return 0;
}
